# Section 57.6, the learned and model-based detectors (legkit_contact_learned) and the training
# set of the logistic model (legkit_contact_training).
legkit_add_test(test_contact_momentum_observer SOURCES momentum_observer_test.cpp
                LIBS legkit_contact_learned legkit_contact_training LABELS "57.6;physics")
legkit_add_test(test_contact_logistic SOURCES logistic_test.cpp LIBS legkit_contact_learned
                LABELS "57.6")
legkit_add_test(test_contact_training SOURCES contact_training_test.cpp
                LIBS legkit_contact_learned legkit_contact_training LABELS "57.6;physics")
