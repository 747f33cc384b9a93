// Reading a log CSV (format: io/log_columns.hpp, chapters/57.0-logs-and-simulator.md).
//
// The reader is strict: any bad row makes it throw a LogError naming the file, the line, the
// column and what was expected; it never hands back part of a file as if it were the whole.
// Checked: the header (unknown, duplicate or missing columns, incomplete groups), the number of
// fields per row, numbers (non-numeric, empty, NaN, inf), contact flags (0 or 1), variances (not
// negative), ground-truth quaternions (unit norm), timestamps (strictly increasing) and, when
// asked, gaps between consecutive samples.
#pragma once

#include <istream>
#include <optional>
#include <string>

#include "io/log.hpp"

namespace legkit::io {

struct ReadOptions {
  // Largest allowed step between consecutive timestamps [s]; nothing means no bound. A bound of
  // 1.5 sample periods catches dropped IMU samples.
  std::optional<double> max_gap;
};

// Throws LogError (file cannot be opened, or any problem above).
Log readLog(const std::string& path, const ReadOptions& options = {});

// The same from a stream; source names it in error messages.
Log readLog(std::istream& in, const std::string& source, const ReadOptions& options = {});

}  // namespace legkit::io
