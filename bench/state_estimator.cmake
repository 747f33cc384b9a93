# The estimator manager per update. Owner: manager.
