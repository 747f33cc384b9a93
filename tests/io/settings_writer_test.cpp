// Issue 23 item 11, the settings writer: a name with a control character (newline, tab, NUL) is
// written as a YAML escape, so that the file holds exactly the name; the reader then refuses it
// naming the file, the line and the key (io::YamlValue::text), where before a raw newline folded
// to a space and the name read back changed without a word.
#include <catch2/catch.hpp>
#include <sstream>
#include <string>

#include "estimation/settings.hpp"
#include "io/yaml_reader.hpp"

namespace legkit {
namespace {

using Catch::Matchers::Contains;

// The error settingsFromYaml() throws for `text` (named w.yaml), or "" when it reads.
std::string errorOf(const std::string& text) {
  try {
    settingsFromYaml(text, "w.yaml");
  } catch (const io::ConfigError& e) {
    return e.what();
  }
  return "";
}

// The 1-based line of `text` that starts (after indentation) with `key`.
int lineOf(const std::string& text, const std::string& key) {
  std::istringstream in(text);
  int n = 0;
  for (std::string line; std::getline(in, line);) {
    ++n;
    if (line.find_first_not_of(' ') != std::string::npos &&
        line.compare(line.find_first_not_of(' '), key.size(), key) == 0) {
      return n;
    }
  }
  return 0;
}

}  // namespace

TEST_CASE("settings writer: a newline in a name is escaped and refused, not folded",
          "[settings][issue23]") {
  Settings s = defaultSettings();
  s.robot.model = "robot.urdf";
  s.robot.base = "trunk\nlink";
  const std::string text = settingsYaml(s);
  CHECK_THAT(text, Contains("base: \"trunk\\nlink\"\n"));
  const int line = lineOf(text, "base:");
  REQUIRE(line > 0);
  // The newline comes back as a newline (0x0a), not as the space a raw one folds to.
  const std::string error = errorOf(text);
  CHECK_THAT(error, Contains("w.yaml:" + std::to_string(line) + ": robot.base: "));
  CHECK_THAT(error, Contains("control characters, got one (0x0a)"));
}

TEST_CASE("settings writer: a NUL, a tab or a DEL in a name is escaped and refused",
          "[settings][issue23]") {
  Settings s = defaultSettings();
  s.robot.model = "robot.urdf";
  s.robot.base = "trunk";
  s.robot.feet = {"FL", "FR", "RL", "RR"};
  SECTION("NUL") {
    s.robot.feet[2] = std::string("RL\0x", 4);
    const std::string text = settingsYaml(s);
    CHECK_THAT(text, Contains("\"RL\\x00x\""));
    CHECK_THAT(errorOf(text), Contains("robot.feet[2]: expected text without control characters, "
                                       "got one (0x00)"));
  }
  SECTION("tab") {
    s.robot.feet[0] = "F\tL";
    const std::string text = settingsYaml(s);
    CHECK_THAT(text, Contains("\"F\\tL\""));
    CHECK_THAT(errorOf(text), Contains("robot.feet[0]: expected text without control characters, "
                                       "got one (0x09)"));
  }
  SECTION("DEL and a carriage return") {
    s.robot.base = "a\x7f\rb";
    const std::string text = settingsYaml(s);
    CHECK_THAT(text, Contains("\"a\\x7f\\rb\""));
    CHECK_THAT(errorOf(text), Contains("robot.base: expected text without control characters, "
                                       "got one (0x7f)"));
  }
}

TEST_CASE("settings writer: quotes, backslashes and UTF-8 in names read back unchanged",
          "[settings][issue23]") {
  Settings s = defaultSettings();
  s.robot.model = "dir with space/\"quoted\" \\ model.urdf";
  s.robot.base = "Rumpf-\xc3\xbc";  // u with diaeresis
  s.robot.feet = {"#FL", "FR: x", "'RL'", "[RR]"};
  s.robot.joints = {"- j", "{k}", "&a", "*b"};
  const std::string text = settingsYaml(s);
  const Settings back = settingsFromYaml(text, "w.yaml");
  CHECK(back.robot.model == s.robot.model);
  CHECK(back.robot.base == s.robot.base);
  CHECK(back.robot.feet == s.robot.feet);
  CHECK(back.robot.joints == s.robot.joints);
  CHECK(settingsYaml(back) == text);
}

}  // namespace legkit

namespace legkit {

// Found by fuzz/settings_fuzz.cpp (",ULL?"): yaml-cpp 0.7's LoadAll loops forever on a ',' outside
// a list or a map at the top level, allocating a document per turn until the memory runs out.
TEST_CASE("settings reader: a ',' at the top level is a syntax error, not a hang",
          "[settings][issue23]") {
  const auto errorOf = [](const std::string& text) {
    try {
      settingsFromYaml(text, "t.yaml");
    } catch (const io::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK_THAT(errorOf(",ULL?"), Contains("t.yaml:1: YAML syntax: a ',' outside"));
  CHECK_THAT(errorOf(",a"), Contains("t.yaml:1: YAML syntax: a ',' outside"));
  CHECK_THAT(errorOf("# comment\n[a], b\n"), Contains("t.yaml:2: YAML syntax: a ',' outside"));
  CHECK_THAT(errorOf("imu: {}\n---\nlimits: {}\n---\n,a\n"), Contains("t.yaml:5: YAML syntax"));
  // A second document is refused as before.
  CHECK_THAT(errorOf("imu: {}\n---\nlimits: {}\n"), Contains("a second YAML document"));
}

}  // namespace legkit
