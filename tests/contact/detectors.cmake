# detect1's tests of section 57.6: the force, Schmitt, kinematic and gait-clock detectors, the
# force from joint torques and the fallback chain, on hand values; then scored against the
# physics simulator's true contacts (label physics: they run MuJoCo).
legkit_add_test(test_contact_detectors
                SOURCES force_detectors_test.cpp kinematic_gait_fallback_test.cpp
                LIBS legkit_contact legkit_sim LABELS "57.6")
