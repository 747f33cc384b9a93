# The settings file (estimation/settings.hpp, legkit_settings). Owner: config.
# Only the reader: the estimators made from the settings are legkit_estimators' (makeEstimator),
# so that what reads a settings file (the settings fuzzer, `legkit config`) builds no filter.
add_library(legkit_settings STATIC ${CMAKE_CURRENT_SOURCE_DIR}/settings.cpp)
target_include_directories(legkit_settings PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
target_link_libraries(legkit_settings PUBLIC legkit_estimation legkit_contact_factory legkit_model
                                      PRIVATE legkit_yaml)
