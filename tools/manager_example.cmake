# The estimator manager's example program. Owner: manager.
