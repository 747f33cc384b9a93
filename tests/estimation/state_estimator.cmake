# The estimator manager. Owner: manager.
# Section 57.11: the manager against runOnLog on a short physics trot, its MPC query, bad input,
# no allocation per update.
legkit_add_test(test_state_estimator SOURCES state_estimator_test.cpp
                LIBS legkit_state_estimator legkit_eval legkit_physics LABELS "57.11;physics")
