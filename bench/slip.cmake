# Section 57.7: the slip check per foot (SlipDetector on four stance feet), the guard with a
# reaction, and the ground plane fit through four footholds.
add_executable(bench_slip bench_slip.cpp)
target_link_libraries(bench_slip PRIVATE legkit_slip benchmark::benchmark_main)
