# Settings files. Owner: config.
