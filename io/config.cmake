# The strict YAML reader of settings files (io/yaml_reader.hpp), yaml-cpp from Debian. Owner: config.
