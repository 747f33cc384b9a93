// libFuzzer target for the settings reader (tools/fuzz-reader.sh settings builds and runs it).
//
// Whatever the bytes, settingsFromYaml either throws io::ConfigError, whose message starts with
// the file's name and a line ("fuzz.yaml:<line>: ..."), or returns settings; nothing else may
// happen (no other exception, no crash, no sanitizer report). And every settings file it accepts
// survives the round trip: written by settingsYaml and read again, the settings are the same,
// which the writer, writing every key, shows as the same text.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "estimation/settings.hpp"
#include "io/yaml_reader.hpp"

namespace {

// "<name>:<digits>: ..."
bool startsWithFileAndLine(const std::string& message, const std::string& name) {
  if (message.compare(0, name.size() + 1, name + ":") != 0) return false;
  std::size_t i = name.size() + 1;
  const std::size_t digits = i;
  while (i < message.size() && message[i] >= '0' && message[i] <= '9') ++i;
  return i > digits && i < message.size() && message[i] == ':';
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace legkit;
  const std::string text(reinterpret_cast<const char*>(data), size);
  Settings read;
  try {
    read = settingsFromYaml(text, "fuzz.yaml");
  } catch (const io::ConfigError& e) {
    if (!startsWithFileAndLine(e.what(), "fuzz.yaml")) std::abort();
    return 0;
  }
  const std::string written = settingsYaml(read);  // must not throw for settings it read
  Settings again;
  try {
    again = settingsFromYaml(written, "fuzz-out.yaml");
  } catch (const io::ConfigError&) {
    std::abort();  // the writer wrote what the reader refuses
  }
  if (settingsYaml(again) != written) std::abort();  // the round trip changed a value
  return 0;
}
