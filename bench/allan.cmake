# Allan deviation of two hours of 1 kHz six-axis data. Owner: allan.
add_executable(bench_allan bench_allan.cpp)
target_link_libraries(bench_allan PRIVATE legkit_allan benchmark::benchmark_main)
