# Allan deviation. Owner: allan.
