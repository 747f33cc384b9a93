# `legkit study fusion` (section 57.8): proprioception alone against exteroceptive fusion on a long
# physics trot with simulated SLAM poses (loose coupling, pose injection with delayed updates, the
# fixed-lag smoother).
target_sources(legkit-study PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/legkit/study_fusion.cpp)
target_link_libraries(legkit-study PRIVATE legkit_contact_pipeline legkit_contact_training
                                           legkit_fusion_extero legkit_fusion_delayed
                                           legkit_fusion_smoother)

# Its test is in tests/tools/CMakeLists.txt (test_study_fusion).
