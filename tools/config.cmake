# legkit config, legkit run --config. Owner: config.
