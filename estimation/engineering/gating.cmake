# Section 57.9: innovation gating and stationary initialisation, in legkit_estimation (every filter gates). Owner: gating.
