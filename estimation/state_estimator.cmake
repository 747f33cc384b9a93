# Section 57.11: the estimator manager (legkit_state_estimator). Owner: manager.
