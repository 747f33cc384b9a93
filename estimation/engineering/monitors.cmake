# Section 57.9: sensor-health and covariance monitors (legkit_monitors). Owner: monitors.
add_library(legkit_monitors STATIC ${CMAKE_CURRENT_SOURCE_DIR}/engineering/monitors.cpp)
target_include_directories(legkit_monitors PUBLIC ${PROJECT_SOURCE_DIR})
target_link_libraries(legkit_monitors PUBLIC legkit_estimation)
