// libFuzzer target for the log reader (tools/fuzz-reader.sh log builds and runs it).
//
// Whatever the bytes, readLog either throws LogError or returns a Log; nothing else may happen
// (no other exception, no crash, no sanitizer report), and a LogError's message is short and
// printable. And every log it accepts must survive the round trip: written back and read again,
// it is the same log, field for field.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "io/log_error.hpp"
#include "io/log_reader.hpp"
#include "io/log_writer.hpp"

namespace {

bool sameLog(const legkit::io::Log& a, const legkit::io::Log& b) {
  if (a.layout != b.layout || a.comments != b.comments || a.rows.size() != b.rows.size()) {
    return false;
  }
  for (std::size_t k = 0; k < a.rows.size(); ++k) {
    if (!legkit::io::exactlyEqual(a.rows[k], b.rows[k])) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace legkit::io;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  Log log;
  try {
    log = readLog(in, "fuzz.csv");
  } catch (const LogError& e) {
    // Refused: fine, if the message is one a terminal can show. Fields are quoted escaped and
    // cut, so whatever the input, the message is short and printable.
    const std::string message = e.what();
    if (message.size() > 600) std::abort();
    for (const char c : message) {
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e)
        std::abort();
    }
    return 0;
  }
  std::stringstream file;
  writeLog(file, log, "fuzz-out.csv");  // must not throw for an accepted log
  const Log again = readLog(file, "fuzz-out.csv");
  if (!sameLog(log, again)) std::abort();  // the round trip broke
  return 0;
}
