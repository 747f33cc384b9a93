# Section 57.6: time per sample of the contact detectors of legkit_contact (and two fallback
# chains, built through makeDetector).
add_executable(bench_contact bench_contact.cpp)
target_link_libraries(bench_contact PRIVATE legkit_contact_factory benchmark::benchmark_main)
