# The estimator manager's example program. Owner: manager.
# legkit-estimate LOG: the manager (57.11) on a log row by row, with an MPC querying it.
add_executable(legkit-estimate legkit/state_estimator_example.cpp)
# legkit_log_run: the checks `legkit run --log` makes of a log against the settings' robot.
# legkit_cli: the exit codes and the output helpers (--out is written as `legkit run` writes).
target_link_libraries(legkit-estimate PRIVATE CLI11::CLI11 legkit_state_estimator legkit_eval
                                              legkit_log_run legkit_io legkit_cli
                                              nlohmann_json::nlohmann_json)
set_target_properties(legkit-estimate PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR})
