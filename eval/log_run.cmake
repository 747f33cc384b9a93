# A recorded log through the settings' pipeline (eval/log_run.hpp): `legkit run --log` and
# legkit.estimators.run share it. Its own library: it needs the settings and the robot models
# (MuJoCo), which the rest of eval/ does not.
add_library(legkit_log_run STATIC ${CMAKE_CURRENT_SOURCE_DIR}/log_run.cpp)
target_include_directories(legkit_log_run PUBLIC ${PROJECT_SOURCE_DIR})
target_link_libraries(legkit_log_run PUBLIC legkit_eval legkit_settings legkit_estimators
                                             legkit_mujoco_kinematics)

# `legkit tune` (eval/tuning.hpp): noise settings fitted on one part of a log, reported on the other.
add_library(legkit_tuning STATIC ${CMAKE_CURRENT_SOURCE_DIR}/tuning.cpp)
target_include_directories(legkit_tuning PUBLIC ${PROJECT_SOURCE_DIR})
target_link_libraries(legkit_tuning PUBLIC legkit_log_run)
