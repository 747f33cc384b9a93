#include "io/log_reader.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <new>
#include <string_view>
#include <vector>

#include "io/csv_text.hpp"
#include "io/input_file.hpp"
#include "io/log_columns.hpp"
#include "io/log_error.hpp"

namespace legkit::io {
namespace {

// Splits one line at commas (no quoting: the format has only numbers and plain names).
void splitFields(std::string_view line, std::vector<std::string_view>& fields) {
  fields.clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      fields.push_back(trim(line.substr(start)));
      return;
    }
    fields.push_back(trim(line.substr(start, comma - start)));
    start = comma + 1;
  }
}

class Reader {
 public:
  Reader(std::string source, const ReadOptions& options)
      : source_(std::move(source)), options_(options) {}

  // size: the stream's size in bytes when known (0 if not), to reserve the rows at once.
  Log read(std::istream& in, std::size_t size) {
    LineSource lines(in, source_);
    try {
      return read(lines, size);
    } catch (const std::bad_alloc&) {
      fail(lines.number(), "",
           "the log is too large for this machine's memory (" +
               (size > 0 ? std::to_string(size) + " bytes, " : std::string()) +
               std::to_string(rows_read_) + (rows_read_ == 1 ? " row" : " rows") +
               " read; a row takes " + std::to_string(sizeof(LogRow)) + " bytes in memory)");
    }
  }

 private:
  Log read(LineSource& lines, std::size_t size) {
    Log log;
    log.source = source_;
    std::string_view line;
    bool have_header = false;
    while (lines.next(line)) {
      if (!line.empty() && line.front() == '#') {
        std::string_view comment = line.substr(1);
        if (!comment.empty() && comment.front() == ' ') comment.remove_prefix(1);
        log.comments.emplace_back(comment);
        continue;
      }
      have_header = true;
      break;
    }
    if (!have_header) fail(lines.number(), "", "no header line (the file is empty)");
    header_line_ = lines.number();
    if (trim(line).empty()) {
      fail(header_line_, "",
           "blank line where the header was expected (comment lines start with '#')");
    }
    parseHeader(line, log.layout);

    std::vector<std::string_view> fields;
    while (lines.next(line)) {
      if (log.rows.size() == 1 && size > lines.bytes()) {
        // Every row of a log has about the same length: reserve them all at once, so that the
        // vector never holds twice its size while it grows.
        log.rows.reserve(size / (line.size() + 1) * 11 / 10 + 16);
      }
      if (line.empty()) {
        // A final newline leaves one empty "line" only at the very end; a blank line inside the
        // data is an error.
        std::string_view rest;
        const int blank = lines.number();
        while (lines.next(rest)) {
          if (!rest.empty()) fail(blank, "", "blank line inside the data");
        }
        break;
      }
      splitFields(line, fields);
      log.rows.push_back(parseRow(lines.number(), fields));
      rows_read_ = log.rows.size();
      checkTime(lines.number(), log.rows);
    }
    if (log.rows.empty()) fail(lines.number(), "", "no data rows after the header");
    return log;
  }

  [[noreturn]] void fail(int line, const std::string& column, const std::string& what) const {
    throw LogError(source_, line, column, what);
  }

  void parseHeader(std::string_view line, LogLayout& layout) {
    std::vector<std::string_view> names;
    splitFields(line, names);
    std::vector<bool> seen_name;
    for (std::size_t i = 0; i < names.size(); ++i) {
      const std::string name(names[i]);
      if (name.size() > 40 || name.find_first_of("\\'") != std::string::npos ||
          std::any_of(name.begin(), name.end(), [](char c) {
            return static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f;
          })) {
        fail(header_line_, "",
             "unknown column " + shown(name) + " (header field " + std::to_string(i + 1) + ")");
      }
      if (name.empty()) {
        fail(header_line_, "", "header field " + std::to_string(i + 1) + " is empty");
      }
      const std::optional<Column> column = columnNamed(name);
      if (!column && genericJointBeyondRange(name)) {
        fail(header_line_, name,
             "generic joint index out of range: at most " + std::to_string(kMaxJoints) +
                 " joints, joint0_ .. joint" + std::to_string(kMaxJoints - 1) + "_");
      }
      if (!column) {
        fail(header_line_, name,
             "unknown column (header field " + std::to_string(i + 1) +
                 "); the known columns are listed in io/log_columns.hpp");
      }
      for (const Column& c : columns_) {
        if (c.field == column->field && c.foot == column->foot && c.index == column->index) {
          fail(header_line_, name,
               c.name == name ? "appears twice in the header"
                              : "duplicates column '" + c.name + "'");
        }
      }
      columns_.push_back(*column);
    }
    layout = deduceLayout();
    layout_ = layout;
    layout_has_quaternion_ = layout.ground_truth;
    // Every column the layout implies must be there (a group is all or nothing).
    for (const Column& want : columnsOf(layout)) {
      if (!has(want.field, want.foot, want.index)) fail(header_line_, want.name, missingWhy(want));
    }
  }

  // joint<digits>_q or joint<digits>_dq whose number is kMaxJoints or more.
  static bool genericJointBeyondRange(const std::string& name) {
    const std::string_view prefix = "joint";
    if (name.compare(0, prefix.size(), prefix) != 0) return false;
    std::size_t end = prefix.size();
    while (end < name.size() && name[end] >= '0' && name[end] <= '9') ++end;
    const std::string_view suffix = std::string_view(name).substr(end);
    if (end == prefix.size() || (suffix != "_q" && suffix != "_dq")) return false;
    const std::size_t digits = end - prefix.size();
    return digits > 9 || std::stoi(name.substr(prefix.size(), digits)) >= kMaxJoints;
  }

  bool has(Field field, int foot = -1, int index = -1) const {
    for (const Column& c : columns_) {
      if (c.field == field && (foot < 0 || c.foot == foot) && (index < 0 || c.index == index)) {
        return true;
      }
    }
    return false;
  }

  std::string missingWhy(const Column& want) const {
    switch (want.field) {
      case Field::kTime:
      case Field::kGyro:
      case Field::kAcc:
        return "missing required column";
      case Field::kQ:
        return "missing: joint columns need q_ for all 12 joints (and dq_ for all 12 or none)";
      case Field::kDq:
        return "missing: joint velocity columns need dq_ for all 12 joints (or none: the front "
               "end then differentiates the angles)";
      case Field::kTau:
        return "missing: the torque group needs all 12 tau_ columns";
      case Field::kForce:
        return "missing: the force group needs one column per foot";
      case Field::kContact:
        return "missing: the contact group needs one column per foot";
      case Field::kFootP:
      case Field::kFootVar:
      case Field::kFootCov:
        return "missing: each foot needs _px _py _pz and either _var_x.._z or _cov_xx.._zz";
      case Field::kFootV:
        return "missing: foot velocity columns need _vx _vy _vz for every foot";
      case Field::kJointQ:
      case Field::kJointDq: {
        const Field other = want.field == Field::kJointQ ? Field::kJointDq : Field::kJointQ;
        if (has(other, -1, want.index)) {
          return "missing: each generic joint needs both joint<k>_q and joint<k>_dq (or the log "
                 "gives no joint<k>_dq at all: the front end then differentiates the angles)";
        }
        return "missing: generic joints are numbered 0 .. " +
               std::to_string(layout_.num_joints - 1) + " without a gap (joint" +
               std::to_string(layout_.num_joints - 1) + "_ is there, joint" +
               std::to_string(want.index) + "_ is not)";
      }
      case Field::kGtP:
      case Field::kGtQ:
        return "missing: the ground-truth group needs all of gt_px..gt_qz (gt_vx..gt_vz and "
               "gt_valid are optional)";
      case Field::kGtV:
        return "missing: the ground-truth group needs all of gt_vx, gt_vy, gt_vz, or none of "
               "them for a truth with the pose only";
      case Field::kGtValid:
        return "missing";  // optional: never implied by a layout the reader deduces
      case Field::kGtContact:
      case Field::kGtFn:
      case Field::kGtFt:
      case Field::kGtVf:
      case Field::kGtSlip:
        return "missing: the contact-truth group needs gt_contact, gt_fn, gt_ft, gt_vf (x, y, z) "
               "and gt_slip for every foot";
    }
    return "missing";
  }

  LogLayout deduceLayout() const {
    LogLayout layout;
    layout.joints = has(Field::kQ) || has(Field::kDq);
    layout.torque = has(Field::kTau);
    layout.force = has(Field::kForce);
    layout.contact = has(Field::kContact);
    layout.ground_truth = has(Field::kGtP) || has(Field::kGtQ) || has(Field::kGtV);
    // Without a ground truth, gt_velocity keeps its default (it only means something with one).
    layout.gt_velocity = !layout.ground_truth || has(Field::kGtV);
    layout.gt_valid = has(Field::kGtValid);
    if (layout.gt_valid && !layout.ground_truth) {
      fail(header_line_, "gt_valid",
           "a validity flag needs the ground-truth columns gt_px..gt_qz, and the log has none");
    }
    layout.foot_velocity = has(Field::kFootV);
    for (const Column& c : columns_) {
      if (c.field == Field::kJointQ || c.field == Field::kJointDq) {
        layout.num_joints = std::max(layout.num_joints, c.index + 1);
      }
    }
    // Angles without velocities: the front end differentiates them.
    layout.joint_velocity =
        has(Field::kDq) || has(Field::kJointDq) || (!layout.joints && layout.num_joints == 0);
    layout.contact_truth = has(Field::kGtContact) || has(Field::kGtFn) || has(Field::kGtFt) ||
                           has(Field::kGtVf) || has(Field::kGtSlip);
    const bool var = has(Field::kFootVar);
    const bool cov = has(Field::kFootCov);
    if (var && cov) {
      fail(header_line_, "", "foot columns mix _var_ and _cov_; use one form for every foot");
    }
    layout.foot_columns = var   ? FootCovariance::kDiagonal
                          : cov ? FootCovariance::kFull
                                : FootCovariance::kNone;
    int feet = 0;  // one past the highest foot id any per-foot column mentions
    for (const Column& c : columns_) {
      if (c.field == Field::kForce || c.field == Field::kContact || c.field == Field::kFootP ||
          c.field == Field::kFootVar || c.field == Field::kFootCov || c.field == Field::kFootV ||
          c.field == Field::kGtContact || c.field == Field::kGtFn || c.field == Field::kGtFt ||
          c.field == Field::kGtVf || c.field == Field::kGtSlip) {
        feet = std::max(feet, c.foot + 1);
      }
    }
    if (layout.foot_columns == FootCovariance::kNone && has(Field::kFootP)) {
      fail(header_line_, "foot0_var_x", "missing: foot position columns need their variances");
    }
    if (layout.foot_velocity && layout.foot_columns == FootCovariance::kNone) {
      fail(header_line_, "foot0_px",
           "missing: foot velocity columns (foot<k>_vx..) need the foot position columns "
           "(foot<k>_px.. with variances)");
    }
    if (layout.num_joints > 0 && (layout.joints || layout.foot_columns != FootCovariance::kNone)) {
      fail(header_line_, "",
           std::string("the log describes its legs twice: generic joint columns (joint<k>_q, "
                       "joint<k>_dq) and ") +
               (layout.joints ? "quadruped joint columns (q_, dq_)"
                              : "body-frame foot columns (foot<k>_p..)") +
               "; give one of the two");
    }
    if (layout.joints && layout.foot_columns != FootCovariance::kNone) {
      fail(header_line_, "",
           "the log describes its legs twice: joint columns (q_, dq_) and body-frame foot columns "
           "(foot<k>_p..); give one of the two");
    }
    if (!layout.joints && layout.foot_columns == FootCovariance::kNone && layout.num_joints == 0) {
      fail(header_line_, "q_FL_0",
           "missing: a log needs joint columns (q_FL_0..q_RR_2, dq_FL_0..dq_RR_2), body-frame "
           "foot columns (foot0_px.. with variances) or generic joint columns (joint0_q, "
           "joint0_dq, ..)");
    }
    if (layout.torque && !layout.joints) {
      fail(header_line_, "q_FL_0", "missing: torque columns need the joint columns");
    }
    if (layout.joints) {
      if (feet > kNumLegs) {
        fail(header_line_, "",
             "a log with joint columns has 4 feet, but a column names foot " +
                 std::to_string(feet - 1));
      }
      layout.num_feet = kNumLegs;
    } else {
      layout.num_feet = std::max(feet, 1);
    }
    return layout;
  }

  LogRow parseRow(int line, const std::vector<std::string_view>& fields) const {
    if (fields.size() < columns_.size()) {
      fail(line, columns_[fields.size()].name,
           "too few fields: " + std::to_string(fields.size()) + " of " +
               std::to_string(columns_.size()) + ", this column and those after it are missing");
    }
    if (fields.size() > columns_.size()) {
      fail(line, "",
           "too many fields: " + std::to_string(fields.size()) + ", the header has " +
               std::to_string(columns_.size()));
    }
    LogRow row;
    for (std::size_t i = 0; i < columns_.size(); ++i) {
      const Column& column = columns_[i];
      const double value = parseNumber(line, column.name, fields[i]);
      checkValue(line, column, value, fields[i]);
      setValue(row, column, value);
    }
    checkCovariances(line, row, layout_);
    // A row whose truth is flagged missing (gt_valid = 0) may hold any finite gt values.
    if (layout_has_quaternion_ && row.gt_valid) {
      const double norm = row.gt_q.norm();
      if (std::abs(norm - 1.0) > 1e-6) {
        fail(line, "gt_qw",
             "expected a unit quaternion gt_qw..gt_qz, its norm is " + numberText(norm));
      }
    }
    return row;
  }

  double parseNumber(int line, const std::string& column, std::string_view text) const {
    if (text.empty()) fail(line, column, "expected a number, the field is empty");
    double value = 0.0;
    const char* first = text.data();
    const char* last = text.data() + text.size();
    if (*first == '+') ++first;  // from_chars takes no plus sign; other tools write one
    const auto [end, ec] = std::from_chars(first, last, value);
    if (ec == std::errc::result_out_of_range) {
      // from_chars says the same for both ends of the range; strtod tells them apart.
      const double magnitude = std::abs(std::strtod(std::string(text).c_str(), nullptr));
      fail(line, column,
           "expected a finite number, got " + shown(text) +
               (magnitude < 1.0 ? " (underflow: too small to represent)"
                                : " (overflow: too large to represent)"));
    }
    if (ec != std::errc() || end != last) {
      fail(line, column, "expected a number, got " + shown(text));
    }
    if (!std::isfinite(value)) {
      fail(line, column, "expected a finite number, got " + shown(text));
    }
    return value;
  }

  void checkValue(int line, const Column& column, double value, std::string_view text) const {
    if ((column.field == Field::kContact || column.field == Field::kGtContact) && value != 0.0 &&
        value != 1.0) {
      fail(line, column.name, "expected a contact flag 0 or 1, got " + shown(text));
    }
    if (column.field == Field::kGtValid && value != 0.0 && value != 1.0) {
      fail(
          line, column.name,
          "expected a validity flag 0 (the truth is missing on this row) or 1, got " + shown(text));
    }
    const bool magnitude = column.field == Field::kGtFn || column.field == Field::kGtFt ||
                           column.field == Field::kGtSlip;
    if (magnitude && !(value >= 0.0)) {
      fail(line, column.name,
           "expected a magnitude >= 0, got " + shown(text) +
               " (a true normal force, tangential force or slip speed is never negative)");
    }
    const bool variance = column.field == Field::kFootVar ||
                          (column.field == Field::kFootCov &&
                           (column.index == 0 || column.index == 3 || column.index == 5));
    if (variance && !(value > 0.0)) {
      fail(line, column.name,
           "expected a variance > 0, got " + shown(text) +
               " (a zero variance claims a perfect measurement, which no filter can take)");
    }
  }

  // A full foot covariance must be symmetric positive definite. It is symmetric by construction
  // (the file gives the upper triangle) and its diagonal is already known to be positive
  // (checkValue), so it is positive definite exactly when its correlation matrix is: every
  // correlation strictly inside (-1, 1) and a positive determinant. Correlations stay in [-1, 1]
  // whatever the scales; a Cholesky factorisation of the raw matrix does not: 1e-300 next to
  // 1e200 overflows to inf, inf * 0 makes a NaN pivot, and a NaN passes a "pivot <= 0" test.
  void checkCovariances(int line, const LogRow& row, const LogLayout& layout) const {
    if (layout.foot_columns != FootCovariance::kFull) return;
    for (int k = 0; k < layout.num_feet; ++k) {
      checkCovariance(line, k, row.feet[static_cast<std::size_t>(k)].cov);
    }
  }

  void checkCovariance(int line, int foot, const Eigen::Matrix3d& cov) const {
    const std::string prefix = "foot" + std::to_string(foot) + "_cov_";
    const std::string what =
        "foot " + std::to_string(foot) + " covariance is not positive definite";
    const Eigen::Vector3d sigma = cov.diagonal().cwiseSqrt();
    struct Pair {
      int i, j;
      const char* name;
      double r;
    };
    std::array<Pair, 3> pairs = {{{0, 1, "xy", 0.0}, {0, 2, "xz", 0.0}, {1, 2, "yz", 0.0}}};
    for (Pair& p : pairs) {
      // Two divisions: sigma_i * sigma_j may underflow; an overflow here means |r| > 1 anyway.
      p.r = cov(p.i, p.j) / sigma(p.i) / sigma(p.j);
      if (!(std::abs(p.r) < 1.0)) {
        const std::string a(1, "xyz"[p.i]), b(1, "xyz"[p.j]);
        fail(line, prefix + p.name,
             what + ": |cov_" + p.name + "| must be below sqrt(cov_" + a + a + " cov_" + b + b +
                 "), the correlation is " + numberText(p.r));
      }
    }
    // det of the correlation matrix, as the product of its last two Cholesky pivots' factors.
    const double rxy = pairs[0].r, rxz = pairs[1].r, ryz = pairs[2].r;
    const double det =
        (1.0 - rxy * rxy) * (1.0 - rxz * rxz) - (ryz - rxy * rxz) * (ryz - rxy * rxz);
    if (!(det > 0.0)) {
      fail(line, prefix + "xx",
           what + ": correlations xy " + numberText(rxy) + ", xz " + numberText(rxz) + ", yz " +
               numberText(ryz) + " give no valid covariance (determinant of the correlation " +
               "matrix " + numberText(det) + ")");
    }
  }

  void checkTime(int line, const std::vector<LogRow>& rows) const {
    if (rows.size() < 2) return;
    const double t_prev = rows[rows.size() - 2].t;
    const double t = rows.back().t;
    if (!(t > t_prev)) {
      fail(line, "t",
           "timestamps must strictly increase: " + numberText(t) + " follows " +
               numberText(t_prev) + " on line " + std::to_string(line - 1));
    }
    if (options_.max_gap && t - t_prev > *options_.max_gap) {
      fail(line, "t",
           "gap of " + numberText(t - t_prev) + " s after t = " + numberText(t_prev) + " on line " +
               std::to_string(line - 1) + ", more than the allowed " +
               numberText(*options_.max_gap) + " s");
    }
  }

  std::string source_;
  ReadOptions options_;
  int header_line_ = 0;
  bool layout_has_quaternion_ = false;
  LogLayout layout_;
  std::vector<Column> columns_;  // in header order
  std::size_t rows_read_ = 0;
};

}  // namespace

Log readLog(std::istream& in, const std::string& source, const ReadOptions& options) {
  Log log = Reader(source, options).read(in, 0);
  if (in.bad()) throw LogError(source, 0, "", "read error");
  return log;
}

Log readLog(const std::string& path, const ReadOptions& options) {
  if (const std::string why = notARegularFile(path); !why.empty()) throw LogError(path, 0, "", why);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw LogError(path, 0, "", "cannot open the file for reading");
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  Log log = Reader(path, options).read(in, error ? 0 : static_cast<std::size_t>(size));
  if (in.bad()) throw LogError(path, 0, "", "read error");
  return log;
}

}  // namespace legkit::io
