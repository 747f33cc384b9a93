# Section 57.8 (owner: study): the loose pose update (MapOdomAlignment::update) and the odometry
# history's lookup at a pose's stamp, the delayed InEKF's pose update with 80 ms of re-propagation,
# one keyframe of the fixed-lag smoother (its window solve).
add_executable(bench_fusion bench_fusion.cpp)
target_link_libraries(bench_fusion PRIVATE legkit_fusion_extero legkit_fusion_delayed
                                           legkit_fusion_smoother legkit_sim
                                           benchmark::benchmark_main)
