# Monitors and fault injection. Owner: monitors.
# Section 57.9's monitors on hand-made inputs (this program counts its allocations).
legkit_add_test(test_monitors SOURCES monitors_test.cpp LIBS legkit_monitors LABELS "57.9")
