# Gating and stationary initialisation. Owner: gating.
