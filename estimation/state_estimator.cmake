# Section 57.11: the estimator manager (legkit_state_estimator). Owner: manager.
add_library(legkit_state_estimator STATIC ${CMAKE_CURRENT_SOURCE_DIR}/state_estimator.cpp)
target_include_directories(legkit_state_estimator PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
target_link_libraries(legkit_state_estimator PUBLIC legkit_contact_pipeline legkit_estimators legkit_settings
                                                    legkit_mujoco_kinematics
                                                    legkit_monitors)
