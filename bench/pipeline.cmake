# One filter step on detected contacts: the contact pipeline (detector, soft weighting, slip
# check and reaction) plus the ESKF's or InEKF's step, on a 10 s physics trot.
add_executable(bench_pipeline bench_pipeline.cpp)
target_link_libraries(bench_pipeline PRIVATE legkit_contact_pipeline legkit_estimators
                                             legkit_physics
                                             benchmark::benchmark_main)
