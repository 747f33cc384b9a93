// Option checks that CLI11's own do not make: CLI::Range and CLI::NonNegativeNumber let NaN
// through (every comparison with NaN is false), and then a run goes on with a NaN setting; and
// CLI11 reads an empty value of a number option as 0 (`--seed ''`, `--points ''` ran). Every
// option of every legkit command checks its value with one of these or with CLI::IsMember; the
// error is CLI11's (exit 1) and names the option. tools/bad-inputs/options.py tries them all.
#pragma once

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>

namespace legkit::tools {

// The longest simulated run [s] of `legkit run`, `sim` and the studies: an hour, the physics
// simulator's own cap. It bounds memory, which grows with it: at the default 1 kHz a simulated
// second takes about 2 MB in `legkit sim` (the log's rows) and 3.2 MB in `legkit run` (the log
// and every estimator's estimates), so an hour is about 7 GB and 12 GB (`--duration 1e308` once
// reserved until the memory ran out).
inline constexpr double kMaxSimulatedSeconds = 3600.0;
// The most samples a simulated log may have (`sim --duration` times `--rate`): that hour at
// 1 kHz, so that a higher rate does not undo the cap above.
inline constexpr double kMaxSimulatedSamples = 3.6e6;

namespace detail {

// The value as an error message shows it: a long one cut (a 10000-character value once filled
// the terminal).
inline std::string shown(const std::string& text) {
  if (text.size() <= 40) return "'" + text + "'";
  return "'" + text.substr(0, 40) + "...' (" + std::to_string(text.size()) + " characters)";
}

}  // namespace detail

// A finite number in [lo, hi]; the error names the range (CLI11 names the option).
inline CLI::Validator finiteRange(double lo, double hi) {
  std::ostringstream range;
  range << "[" << lo << ", " << hi << "]";
  const std::string description = range.str();
  return CLI::Validator(
      [lo, hi, description](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value) || value < lo ||
            value > hi) {
          return "must be a finite number in " + description + ", got " + detail::shown(text);
        }
        return "";
      },
      "FLOAT in " + description);
}

// A whole number in [lo, hi], written in decimal: seeds, counts. Not CLI11's own conversion
// alone, which reads '' as 0.
inline CLI::Validator wholeRange(long long lo, long long hi) {
  const std::string description = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  return CLI::Validator(
      [lo, hi, description](std::string& text) -> std::string {
        char* end = nullptr;
        errno = 0;
        const long long value = text.empty() ? 0 : std::strtoll(text.c_str(), &end, 10);
        if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || value < lo ||
            value > hi) {
          return "must be a whole number in " + description + ", got " + detail::shown(text);
        }
        return "";
      },
      "INT in " + description);
}

// A random seed: any unsigned 32-bit number.
inline CLI::Validator seedNumber() {
  return wholeRange(0, 4294967295LL);
}

// A name the option cannot do without: a file, a folder, a leg. Not empty (an empty value once
// meant the option's default: `run --log ''` simulated a trot, `run --out ''` wrote to
// legkit-out/) and at most 4095 bytes (PATH_MAX less its NUL: no longer path can be opened, and
// the error then does not repeat 10000 characters).
inline CLI::Validator nonEmptyName() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (text.empty()) return "must not be empty";
        if (text.size() > 4095) {
          return "is " + std::to_string(text.size()) +
                 " characters long, at most 4095: " + detail::shown(text);
        }
        return "";
      },
      "");
}

}  // namespace legkit::tools
