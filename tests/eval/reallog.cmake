# Metrics on real data. Owner: iometrics.
legkit_add_test(test_eval_metrics_reallog SOURCES metrics_reallog_test.cpp LIBS legkit_eval
                LABELS "eval;57.0")
