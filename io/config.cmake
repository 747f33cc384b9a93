# The strict YAML reader of settings files (io/yaml_reader.hpp), yaml-cpp from Debian. Owner: config.
find_package(yaml-cpp REQUIRED)
add_library(legkit_yaml STATIC ${CMAKE_CURRENT_SOURCE_DIR}/yaml_reader.cpp)
target_include_directories(legkit_yaml PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
target_link_libraries(legkit_yaml PRIVATE yaml-cpp)
