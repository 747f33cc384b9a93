# Settings files. Owner: config.
legkit_add_test(test_settings SOURCES settings_test.cpp
                LIBS legkit_settings legkit_estimators legkit_yaml legkit_eval legkit_sim
                LABELS "57.9;settings")
target_compile_definitions(test_settings PRIVATE LEGKIT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")

# `legkit config` and `legkit run --config` end to end (they run the built program).
legkit_add_test(test_config_cli SOURCES config_cli_test.cpp LABELS "cli;settings")
target_compile_definitions(test_config_cli PRIVATE LEGKIT_EXE="$<TARGET_FILE:legkit>"
                                                   LEGKIT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
target_include_directories(test_config_cli PRIVATE ${PROJECT_SOURCE_DIR})
add_dependencies(test_config_cli legkit)


# Issue 23 items 3 and 4: what the check and the run refuse, naming the file and the key.
legkit_add_test(test_robot_refusals_cli SOURCES robot_refusals_cli_test.cpp LABELS "cli;settings")
target_compile_definitions(test_robot_refusals_cli PRIVATE LEGKIT_EXE="$<TARGET_FILE:legkit>")
add_dependencies(test_robot_refusals_cli legkit)
