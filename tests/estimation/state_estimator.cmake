# The estimator manager. Owner: manager.
# Section 57.11: the manager against runOnLog on a short physics trot, its MPC query, bad input,
# no allocation per update.
legkit_add_test(test_state_estimator SOURCES state_estimator_test.cpp
                LIBS legkit_state_estimator legkit_eval legkit_physics LABELS "57.11;physics")

# legkit-estimate on a simulated trot without truth: the 1 s stand never passes the 2 s still
# window, so the manager gives up after --init-wait (0.8 s by default) and the loop runs on.
add_test(NAME legkit_estimate_gives_up
         COMMAND /bin/sh -c "\"$1\" sim --scenario physics-trot --duration 2 --seed 1 \
--no-ground-truth --out estimate-nogt.csv > /dev/null && \"$2\" estimate-nogt.csv"
                 sh $<TARGET_FILE:legkit> $<TARGET_FILE:legkit-estimate>
         WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(legkit_estimate_gives_up
                     PROPERTIES LABELS "57.11;cli;physics" PASS_REGULAR_EXPRESSION
                                "filter started at t = 0\\.80[0-9] s \\(gave up: tilt from the last samples\\)")

# legkit-estimate on the shipped iCub log with its settings: generic joints through the robot's
# URDF, the log's front end (smoothed stamps, velocities from the angles) as in `legkit run`.
add_test(NAME legkit_estimate_real_log
         COMMAND $<TARGET_FILE:legkit-estimate> ${PROJECT_SOURCE_DIR}/data/icub-walking/walking.csv
                 --config ${PROJECT_SOURCE_DIR}/config/robots/icub.yaml)
set_tests_properties(legkit_estimate_real_log
                     PROPERTIES LABELS "57.11;cli;real-robot" PASS_REGULAR_EXPRESSION
                                "front end: time stamps smoothed.*invariant-ekf on contacts from schmitt.*position RMSE 0\\.0[0-2][0-9] m")
# Without the settings the same log's generic joints have no robot: exit 2, and the message says
# what to give.
add_test(NAME legkit_estimate_needs_the_robot
         COMMAND /bin/sh -c "\"$1\" \"$2\" > out.txt 2>&1; s=$?; cat out.txt; \
test $s -eq 2 && grep -q 'need the robot.s model: --config with a robot: section' out.txt"
                 sh $<TARGET_FILE:legkit-estimate> ${PROJECT_SOURCE_DIR}/data/icub-walking/walking.csv
         WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(legkit_estimate_needs_the_robot PROPERTIES LABELS "57.11;cli;real-robot")

# Issue 23 item 7: legkit-estimate keeps `legkit run --log`'s contract: the logs run refuses, with
# its messages (exit 2), a row the filter cannot take as run's FAILED line (exit 3), the robot and
# the contact source against the log's columns, every option's range named (exit 1).
legkit_add_test(test_legkit_estimate_cli SOURCES legkit_estimate_cli_test.cpp
                LABELS "57.11;cli;robustness")
target_compile_definitions(test_legkit_estimate_cli
                           PRIVATE LEGKIT_EXE="$<TARGET_FILE:legkit>"
                                   LEGKIT_ESTIMATE_EXE="$<TARGET_FILE:legkit-estimate>"
                                   LEGKIT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
add_dependencies(test_legkit_estimate_cli legkit legkit-estimate)
