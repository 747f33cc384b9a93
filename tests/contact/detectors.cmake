# detect1's tests of section 57.6: the force, Schmitt, kinematic and gait-clock detectors, the
# force from joint torques and the fallback chain, on hand values; then scored against the
# physics simulator's true contacts (label physics: they run MuJoCo).
legkit_add_test(test_contact_detectors
                SOURCES force_detectors_test.cpp kinematic_gait_fallback_test.cpp
                        detectors_factory_test.cpp
                LIBS legkit_contact_factory legkit_sim LABELS "57.6")
# The fallback chain's laziness, counted on test detectors (its own program: it counts allocations).
legkit_add_test(test_contact_fallback SOURCES detectors_fallback_test.cpp
                LIBS legkit_contact_factory LABELS "57.6")
# Scored with eval/contact_scores.cpp (compiled in: it needs only the standard library), so the
# numbers use `legkit study contact`'s definitions without linking legkit_eval.
legkit_add_test(test_contact_detectors_physics
                SOURCES detectors_physics_test.cpp ${PROJECT_SOURCE_DIR}/eval/contact_scores.cpp
                LIBS legkit_contact_factory legkit_physics LABELS "57.6;physics")
