# The estimator manager. Owner: manager.
