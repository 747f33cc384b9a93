# Section 57.10: Allan deviation and noise-parameter extraction (legkit_allan). Owner: allan.
