# New log columns (foot velocity, gt_valid, optional gt velocity, generic joints). Owner: iometrics.
legkit_add_test(test_io_log_reallog SOURCES log_reallog_test.cpp LIBS legkit_io
                LABELS "57.0;log")
