// What the settings reader says of a settings text, for the tests of its refusals.
#pragma once

#include <string>

#include "estimation/settings.hpp"
#include "io/yaml_reader.hpp"

namespace legkit::test {

// The error settingsFromYaml() throws for `text` (named t.yaml), or "" when it reads.
inline std::string settingsErrorOf(const std::string& text) {
  try {
    settingsFromYaml(text, "t.yaml");
  } catch (const io::ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace legkit::test
