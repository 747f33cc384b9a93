# Section 57.8, loose coupling (owner: extero): the pose file and its strict reader, simulated SLAM
# poses from a log's ground truth, the odometry's pose history and the map-to-odom alignment.
add_library(legkit_fusion_extero STATIC
  ${CMAKE_CURRENT_LIST_DIR}/pose_log.cpp
  ${CMAKE_CURRENT_LIST_DIR}/pose_simulator.cpp
  ${CMAKE_CURRENT_LIST_DIR}/odom_history.cpp
  ${CMAKE_CURRENT_LIST_DIR}/map_odom.cpp)
# legkit_estimation: the chi-square quantile of the gate (estimation/engineering/gating.hpp);
# it brings legkit_io (io::Log, io::LogError) and lie::lie.
target_link_libraries(legkit_fusion_extero PUBLIC legkit_estimation legkit_io lie::lie)
