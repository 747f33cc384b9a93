# legkit allan. Owner: allan.
target_sources(legkit PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/legkit/allan_command.cpp)
target_link_libraries(legkit PRIVATE legkit_allan)
