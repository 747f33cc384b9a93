# Allan deviation. Owner: allan.
legkit_add_test(test_allan SOURCES allan_test.cpp LIBS legkit_allan LABELS "57.10")
# `legkit allan` end to end (runs the built program).
legkit_add_test(test_allan_cli SOURCES allan_cli_test.cpp LABELS "57.10;cli")
target_include_directories(test_allan_cli PRIVATE ${PROJECT_SOURCE_DIR})  # tools/legkit/spawn.hpp
target_compile_definitions(test_allan_cli PRIVATE LEGKIT_EXE="$<TARGET_FILE:legkit>")
add_dependencies(test_allan_cli legkit)
