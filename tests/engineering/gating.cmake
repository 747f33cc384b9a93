# Gating and stationary initialisation. Owner: gating.
legkit_add_test(test_gating SOURCES gating_test.cpp
                LIBS legkit_estimators legkit_contact_pipeline legkit_eval legkit_sim legkit_physics
                LABELS "57.9")
legkit_add_test(test_stationary_init SOURCES stationary_init_test.cpp
                LIBS legkit_estimators legkit_sim LABELS "57.9")
