# Section 57.8, loose coupling (owner: extero): the pose file, the pose simulator, the odometry
# history and the map-to-odom alignment.
legkit_add_test(test_extero_pose_log SOURCES ${CMAKE_CURRENT_LIST_DIR}/extero_pose_log_test.cpp
                LIBS legkit_fusion_extero LABELS "fusion;57.8")
legkit_add_test(test_extero_simulator SOURCES ${CMAKE_CURRENT_LIST_DIR}/extero_simulator_test.cpp
                LIBS legkit_fusion_extero LABELS "fusion;57.8")
legkit_add_test(test_extero_history SOURCES ${CMAKE_CURRENT_LIST_DIR}/extero_history_test.cpp
                LIBS legkit_fusion_extero LABELS "fusion;57.8")
legkit_add_test(test_extero_map_odom SOURCES ${CMAKE_CURRENT_LIST_DIR}/extero_map_odom_test.cpp
                LIBS legkit_fusion_extero LABELS "fusion;57.8")
