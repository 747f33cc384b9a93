# (owner: delayed)
# The filters' pose update (NEES by Monte Carlo, gate, bad input) and the delayed-measurement
# history (the 80 ms equivalence, rejections, no allocation per step).
legkit_add_test(test_fusion_delayed_pose SOURCES ${CMAKE_CURRENT_LIST_DIR}/delayed_pose_test.cpp
                LIBS legkit_fusion_delayed LABELS "fusion;57.8")
legkit_add_test(test_fusion_delayed_filter
                SOURCES ${CMAKE_CURRENT_LIST_DIR}/delayed_filter_test.cpp
                LIBS legkit_fusion_delayed legkit_sim LABELS "fusion;57.8")
