# The settings file (estimation/settings.hpp, legkit_settings). Owner: config.
add_library(legkit_settings STATIC ${CMAKE_CURRENT_SOURCE_DIR}/settings.cpp)
target_include_directories(legkit_settings PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
target_link_libraries(legkit_settings PUBLIC legkit_estimators legkit_contact_pipeline
                                             legkit_contact_factory PRIVATE legkit_yaml)
