#include "io/yaml_reader.hpp"

#include "io/input_file.hpp"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace legkit::io {
namespace {

std::string list(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::string formatNumber(double x) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, x);
  return ec == std::errc() ? std::string(buffer, end) : std::to_string(x);
}

// Where each document of a stream starts; the parse events themselves are not kept.
struct DocumentStarts : YAML::EventHandler {
  std::vector<YAML::Mark> starts;
  void OnDocumentStart(const YAML::Mark& mark) override { starts.push_back(mark); }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t,
                const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
};

// Refuses, before yaml-cpp builds any node, a ',' outside a list or a map at the top level (",a",
// "[a],b"): on that yaml-cpp 0.7's LoadAll parses an empty document without consuming the ',' and
// loops forever, allocating a document per turn (found by fuzz/settings_fuzz.cpp). Such a
// document starts where the previous one did; every other document moves on, so this ends.
void checkDocuments(const std::string& text, const std::string& file) {
  std::istringstream in(text);
  YAML::Parser parser(in);
  DocumentStarts documents;
  while (parser.HandleNextDocument(documents)) {
    const auto& s = documents.starts;
    if (s.size() >= 2 && s[s.size() - 1].pos == s[s.size() - 2].pos) {
      throw ConfigError(file + ":" + std::to_string(s.back().line + 1) +
                        ": YAML syntax: a ',' outside a [list] or a {map}");
    }
  }
}

}  // namespace

YamlValue::YamlValue(std::shared_ptr<const YAML::Node> node, std::string file, std::string path)
    : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {}

YamlValue YamlValue::parse(const std::string& text, const std::string& file) {
  std::vector<YAML::Node> documents;
  try {
    checkDocuments(text, file);
    documents = YAML::LoadAll(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(file + ":" + std::to_string(e.mark.line + 1) + ": YAML syntax: " + e.msg);
  }
  if (documents.size() > 1) {  // yaml-cpp's Load would read the first and drop the rest
    const YAML::Mark mark = documents[1].Mark();
    throw ConfigError(file + ":" + std::to_string(mark.is_null() ? 0 : mark.line + 1) +
                      ": a second YAML document (after '---' or '...'): a settings file is one "
                      "document");
  }
  return YamlValue(
      std::make_shared<const YAML::Node>(documents.empty() ? YAML::Node() : documents[0]), file,
      "");
}

YamlValue YamlValue::parseFile(const std::string& path) {
  // A directory opens as an empty stream (it would read as no keys at all), a FIFO blocks in
  // open(), /dev/zero never ends: regular files only, and at most 16 MiB of them.
  if (const std::string why = notARegularFile(path); !why.empty()) {
    throw ConfigError(path + ": " + why + " (a settings file is a regular file)");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path + ": cannot be read");
  std::string text;
  if (!readAtMost(in, kMaxTextFileBytes, text)) {
    throw ConfigError(path + ": " + tooLarge("settings file"));
  }
  if (in.bad()) throw ConfigError(path + ": cannot be read");
  YamlValue document = parse(text, path);
  // An empty file (or comments only) would load as every default without a word: more likely a
  // file cut short or the wrong one than a choice, which `{}` says explicitly.
  if (document.isNull()) {
    throw ConfigError(path +
                      ": holds no settings (the file is empty or only comments); `legkit config "
                      "--print` writes the defaults, and a file of `{}` takes them all");
  }
  return document;
}

YamlValue YamlValue::child(const YAML::Node& node, const std::string& path) const {
  return YamlValue(std::make_shared<const YAML::Node>(node), file_, path);
}

int YamlValue::line() const {
  const YAML::Mark mark = node_->Mark();
  return mark.is_null() ? 0 : mark.line + 1;
}

bool YamlValue::isNull() const {
  return !node_->IsDefined() || node_->IsNull();
}
bool YamlValue::isMap() const {
  return node_->IsMap();
}
bool YamlValue::isList() const {
  return node_->IsSequence();
}

void YamlValue::fail(const std::string& what) const {
  std::string where = file_ + ":" + std::to_string(line()) + ": ";
  if (!path_.empty()) where += path_ + ": ";
  throw ConfigError(where + what);
}

std::vector<std::string> YamlValue::keys() const {
  if (!isMap()) fail("expected a map of keys");
  std::vector<std::string> out;
  for (const auto& entry : *node_) {
    const YAML::Node& key = entry.first;
    if (!key.IsScalar()) {
      child(key, path_).fail("expected a plain key, not a list or a map");
    }
    const std::string name = key.Scalar();
    if (std::find(out.begin(), out.end(), name) != out.end()) {
      child(key, path_.empty() ? name : path_ + "." + name).fail("key given twice");
    }
    out.push_back(name);
  }
  return out;
}

std::optional<YamlValue> YamlValue::find(const std::string& key) const {
  if (!isMap()) fail("expected a map of keys");
  for (const auto& entry : *node_) {
    if (entry.first.IsScalar() && entry.first.Scalar() == key) {
      return child(entry.second, path_.empty() ? key : path_ + "." + key);
    }
  }
  return std::nullopt;
}

void YamlValue::checkKeys(const std::vector<std::string>& known) const {
  keys();  // a map, without repeated keys
  for (const auto& entry : *node_) {
    const std::string key = entry.first.Scalar();
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      child(entry.first, path_.empty() ? key : path_ + "." + key)
          .fail("unknown key (known here: " + list(known) + ")");
    }
  }
}

std::vector<YamlValue> YamlValue::elements(int size) const {
  if (!isList()) {
    fail(size >= 0 ? "expected a list of " + std::to_string(size) + " values" : "expected a list");
  }
  if (size >= 0 && static_cast<int>(node_->size()) != size) {
    fail("expected a list of " + std::to_string(size) + " values, got " +
         std::to_string(node_->size()));
  }
  std::vector<YamlValue> out;
  int i = 0;
  for (const auto& element : *node_) {
    out.push_back(child(element, path_ + "[" + std::to_string(i++) + "]"));
  }
  return out;
}

std::string YamlValue::scalar(const char* expected) const {
  if (!node_->IsScalar()) fail(std::string("expected ") + expected);
  return node_->Scalar();
}

double YamlValue::number(double lo, double hi) const {
  const std::string range = "[" + formatNumber(lo) + ", " + formatNumber(hi) + "]";
  const std::string expected = "a number in " + range;
  const std::string s = scalar(expected.c_str());
  double x = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
  if (node_->Tag() == "!" || ec != std::errc() || end != s.data() + s.size()) {
    fail("expected " + expected + ", got '" + s + "'");
  }
  if (!std::isfinite(x)) fail("expected a finite number in " + range + ", got " + s);
  if (x < lo || x > hi) fail("expected a number in " + range + ", got " + s);
  return x;
}

int YamlValue::integer(int lo, int hi) const {
  const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  const std::string s = scalar(("an integer in " + range).c_str());
  int x = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
  if (node_->Tag() == "!" || ec != std::errc() || end != s.data() + s.size() || x < lo || x > hi) {
    fail("expected an integer in " + range + ", got '" + s + "'");
  }
  return x;
}

bool YamlValue::boolean() const {
  const std::string s = scalar("true or false");
  if (node_->Tag() != "!") {
    if (s == "true" || s == "True" || s == "TRUE") return true;
    if (s == "false" || s == "False" || s == "FALSE") return false;
  }
  fail("expected true or false, got '" + s + "'");
}

std::string YamlValue::text() const {
  if (isNull()) return "";
  const std::string s = scalar("text");
  // A NUL would end the name where the C libraries below read it ("FL\0x" is "FL" to them).
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      char code[8];
      std::snprintf(code, sizeof code, "0x%02x", static_cast<unsigned>(u));
      fail(std::string("expected text without control characters, got one (") + code + ")");
    }
  }
  return s;
}

std::string YamlValue::oneOf(const std::vector<std::string>& allowed) const {
  std::string s = text();
  if (std::find(allowed.begin(), allowed.end(), s) == allowed.end()) {
    fail("expected one of " + list(allowed) + ", got '" + s + "'");
  }
  return s;
}

}  // namespace legkit::io
