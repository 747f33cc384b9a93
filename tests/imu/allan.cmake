# Allan deviation. Owner: allan.
legkit_add_test(test_allan SOURCES allan_test.cpp LIBS legkit_allan LABELS "57.10")
