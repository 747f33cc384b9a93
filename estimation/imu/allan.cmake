# Section 57.10: Allan deviation and noise-parameter extraction (legkit_allan). Owner: allan.
add_library(legkit_allan STATIC ${CMAKE_CURRENT_LIST_DIR}/allan.cpp)
target_include_directories(legkit_allan PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
target_link_libraries(legkit_allan PUBLIC legkit_io Eigen3::Eigen)
