# legkit_contact_pipeline: log rows -> contact detection -> estimator inputs -> slip handling
# (contact_pipeline.hpp), for runOnLog, `legkit run` and the studies.
add_library(legkit_contact_pipeline STATIC ${CMAKE_CURRENT_SOURCE_DIR}/contact_pipeline.cpp)
target_include_directories(legkit_contact_pipeline PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
target_link_libraries(legkit_contact_pipeline PUBLIC legkit_estimation legkit_contact_factory
                                                     legkit_leg_odometry legkit_slip)
