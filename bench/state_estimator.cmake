# The estimator manager per update. Owner: manager.
# StateEstimator::update (pipeline + filter + ring buffer) and stateAt on a 10 s physics trot.
add_executable(bench_state_estimator bench_state_estimator.cpp)
target_link_libraries(bench_state_estimator PRIVATE legkit_state_estimator legkit_physics
                                                    benchmark::benchmark_main)
