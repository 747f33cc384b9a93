# The settings file (estimation/settings.hpp, legkit_settings). Owner: config.
