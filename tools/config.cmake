# legkit config, legkit robot, legkit tune, legkit run --config. Owner: config.
target_sources(legkit PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/legkit/config_command.cpp
                              ${CMAKE_CURRENT_SOURCE_DIR}/legkit/robot_command.cpp
                              ${CMAKE_CURRENT_SOURCE_DIR}/legkit/tune_command.cpp)
target_link_libraries(legkit PRIVATE legkit_settings legkit_mujoco_kinematics legkit_log_run
                                     legkit_tuning)
