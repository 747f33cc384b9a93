# Section 57.6: time per sample of the logistic contact probability and the momentum observer.
add_executable(bench_contact_learned bench_contact_learned.cpp)
target_link_libraries(bench_contact_learned PRIVATE legkit_contact_learned
                                                    benchmark::benchmark_main)
