// Reading a log CSV (format: io/log_columns.hpp, chapters/57.0-logs-and-simulator.md).
//
// The reader is strict: any bad row makes it throw a LogError naming the file, the line, the
// column and what was expected; it never hands back part of a file as if it were the whole.
// Checked: the header (unknown, duplicate or missing columns, incomplete groups, more than one
// leg description: quadruped joints, foot columns, generic joints; generic joints numbered
// without gaps, each with _q and _dq, fewer than kMaxJoints; foot velocities only with foot
// positions; gt_valid only with a ground truth), the number of fields per row, numbers
// (non-numeric, empty, NaN, overflow, underflow), contact and validity flags (0 or 1), variances
// (> 0: a zero variance claims a perfect measurement), full foot covariances (positive definite),
// ground-truth quaternions (unit norm, except on rows flagged gt_valid = 0, whose truth may be
// any finite numbers), timestamps (strictly increasing) and, when asked, gaps between
// consecutive samples. Fields
// quoted in a message are escaped and cut to 40 characters.
//
// Taken: LF, CR LF or lone CR line ends, a UTF-8 byte-order mark, spaces around fields. Whatever
// is accepted survives writeLog and a second read unchanged (fuzz/log_reader_fuzz.cpp checks it).
// The stream is read line by line and the rows are reserved from the file size, so a log costs
// about sizeof(LogRow) per row; running out of memory is a LogError saying so.
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
