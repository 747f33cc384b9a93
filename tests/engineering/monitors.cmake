# Monitors and fault injection. Owner: monitors.
# Section 57.9's monitors on hand-made inputs (this program counts its allocations).
legkit_add_test(test_monitors SOURCES monitors_test.cpp LIBS legkit_monitors LABELS "57.9")
# Section 57.9's faults injected into a 3 s physics trot (and an analytic one for exteroception),
# the ESKF on the recommended contact chain with the monitor: detection times, bounded errors and
# the monitor's answers against runs without them (the troubleshooting table's runs).
legkit_add_test(test_fault_injection SOURCES fault_injection_test.cpp
                LIBS legkit_fault_injection legkit_estimators legkit_eval legkit_contact_training
                     legkit_physics
                LABELS "57.9;physics")
