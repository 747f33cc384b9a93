# Allan deviation of two hours of 1 kHz six-axis data. Owner: allan.
