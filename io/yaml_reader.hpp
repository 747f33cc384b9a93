// Strict, typed reading of a YAML document (yaml-cpp underneath): every value is checked for its
// type and range where it is read, every map for keys nobody reads, and every failure is one
// io::ConfigError "<file>:<line>: <key.path>: <what was expected>". The settings file
// (estimation/settings.hpp) is its user; what the keys mean is there.
#pragma once

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace YAML {
class Node;
}

namespace legkit::io {

// A settings file that cannot be used: the file, the line (1-based), the key and what was
// expected, in one message.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One value of a parsed document with where it came from: the file, its line, its key path
// ("imu.extrinsic.translation[1]").
class YamlValue {
 public:
  // The document in `text`, named `file` in messages. A syntax error, or a second document after
  // '---', is a ConfigError at its line.
  static YamlValue parse(const std::string& text, const std::string& file);
  // The document in the file at `path` (a file that cannot be read, or a directory, is a
  // ConfigError too).
  static YamlValue parseFile(const std::string& path);

  const std::string& path() const { return path_; }
  int line() const;  // 1-based; 0 when yaml-cpp knows none
  bool isNull() const;
  bool isMap() const;
  bool isList() const;

  // Maps: the keys in the order of the file (throws unless a map).
  std::vector<std::string> keys() const;
  // The value of `key`, or none when the map does not have it (throws unless a map).
  std::optional<YamlValue> find(const std::string& key) const;
  // Throws naming the first key of this map that is not in `known`, and listing `known`.
  void checkKeys(const std::vector<std::string>& known) const;

  // Lists: the elements (throws unless a list; with `size` >= 0, unless it has that many).
  std::vector<YamlValue> elements(int size = -1) const;

  // Scalars. A number is finite and within [lo, hi] (NaN, inf and text are errors).
  double number(double lo, double hi) const;
  int integer(int lo, int hi) const;
  bool boolean() const;      // true or false
  std::string text() const;  // no control characters (NUL, tab, newline, ...)
  // Text that is one of `allowed` (the message lists them).
  std::string oneOf(const std::vector<std::string>& allowed) const;

  // Throws ConfigError "<file>:<line>: <path>: <what>".
  [[noreturn]] void fail(const std::string& what) const;

 private:
  YamlValue(std::shared_ptr<const YAML::Node> node, std::string file, std::string path);
  YamlValue child(const YAML::Node& node, const std::string& path) const;
  std::string scalar(const char* expected) const;  // throws unless a scalar

  std::shared_ptr<const YAML::Node> node_;
  std::string file_;
  std::string path_;
};

}  // namespace legkit::io
