// Option checks that CLI11's own do not make: CLI::Range and CLI::NonNegativeNumber let NaN
// through (every comparison with NaN is false), and then a run goes on with a NaN setting.
#pragma once

#include <CLI/CLI.hpp>
#include <cmath>
#include <sstream>
#include <string>

namespace legkit::tools {

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
          return "must be a finite number in " + description + ", got " + text;
        }
        return "";
      },
      "FLOAT in " + description);
}

}  // namespace legkit::tools
