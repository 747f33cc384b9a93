# Section 57.9: sensor-health and covariance monitors (legkit_monitors). Owner: monitors.
add_library(legkit_monitors STATIC ${CMAKE_CURRENT_SOURCE_DIR}/engineering/monitors.cpp)
target_include_directories(legkit_monitors PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
target_link_libraries(legkit_monitors PUBLIC legkit_estimation)

# Fault injection and monitored runs (eval/fault_injection.hpp): section 57.9's fault runs.
add_library(legkit_fault_injection STATIC ${PROJECT_SOURCE_DIR}/eval/fault_injection.cpp)
target_include_directories(legkit_fault_injection PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
target_link_libraries(legkit_fault_injection PUBLIC legkit_monitors legkit_contact_pipeline
                                                    legkit_contact)
