#include "estimation/fusion/pose_log.hpp"

#include <Eigen/Cholesky>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string_view>

#include "io/csv_text.hpp"
#include "io/input_file.hpp"
#include "io/log_error.hpp"

namespace legkit::fusion {
namespace {

using io::numberText;
using io::shown;
using io::trim;

using io::LogError;

constexpr int kNumColumns = 31;
constexpr int kCovFirst = 9;  // index of c00
constexpr int kValid = 30;

std::vector<std::string> makeColumns() {
  std::vector<std::string> c = {"t", "t_arrival", "px", "py", "pz", "qw", "qx", "qy", "qz"};
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) c.push_back("c" + std::to_string(i) + std::to_string(j));
  }
  c.push_back("valid");
  return c;
}

// The number of comma-separated fields of a line; the first kNumColumns are stored, trimmed.
int splitFields(std::string_view line, std::array<std::string_view, kNumColumns>& fields) {
  int n = 0;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    if (n < kNumColumns) {
      fields[n] = trim(line.substr(
          start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
    }
    ++n;
    if (comma == std::string_view::npos) return n;
    start = comma + 1;
  }
}

// The first problem of a pose as the reader defines them (empty: none), with the column it is in.
struct Problem {
  std::string column;
  std::string what;
};

Problem checkPose(const PoseMeasurement& z, double previous_t, bool has_previous) {
  const auto& cols = poseLogColumns();
  if (!std::isfinite(z.t)) return {"t", "expected a finite number"};
  if (!std::isfinite(z.t_arrival)) return {"t_arrival", "expected a finite number"};
  if (has_previous && !(z.t > previous_t)) {
    return {"t", "expected a time after the previous pose's " + numberText(previous_t) + ", got " +
                     numberText(z.t)};
  }
  if (!(z.t_arrival >= z.t)) {
    return {"t_arrival", "expected t_arrival >= t (a pose cannot arrive before it is taken), got " +
                             numberText(z.t_arrival) + " < " + numberText(z.t)};
  }
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(z.p_MB(i))) return {cols[2 + i], "expected a finite number"};
  }
  if (!z.R_MB.matrix().allFinite()) return {"qw", "expected a finite rotation"};
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) {
      if (!std::isfinite(z.cov(i, j)) || z.cov(i, j) != z.cov(j, i)) {
        return {"c" + std::to_string(i) + std::to_string(j),
                "expected a finite, symmetric covariance entry"};
      }
    }
  }
  // Eigen reports success for a factor that overflowed to inf or NaN (entries near 1e300): a
  // finite factor is part of positive definite here, as in estimation/health_guard.cpp.
  const Eigen::LLT<Matrix6d> llt(z.cov);
  if (llt.info() != Eigen::Success || !llt.matrixLLT().allFinite()) {
    return {"c00",
            "expected a positive definite covariance (c00..c55 fail a Cholesky factorisation)"};
  }
  return {};
}

class Reader {
 public:
  Reader(std::istream& in, const std::string& source) : lines_(in, source), source_(source) {}

  std::vector<PoseMeasurement> read() {
    std::vector<PoseMeasurement> poses;
    std::string_view line;
    bool have_header = false;
    while (lines_.next(line)) {
      if (!line.empty() && line.front() == '#') continue;
      have_header = true;
      break;
    }
    if (!have_header) fail(lines_.number(), "", "no header line (the file is empty)");
    checkHeader(line);
    std::array<std::string_view, kNumColumns> fields;
    while (lines_.next(line)) {
      if (line.empty()) {
        // One final line end leaves an empty last line; a blank line before more data is an error.
        const int blank = lines_.number();
        std::string_view rest;
        while (lines_.next(rest)) {
          if (!rest.empty()) fail(blank, "", "blank line inside the data");
        }
        break;
      }
      const int n = splitFields(line, fields);
      if (n != kNumColumns) {
        fail(lines_.number(), "",
             "expected " + std::to_string(kNumColumns) + " fields, got " + std::to_string(n));
      }
      poses.push_back(parseRow(fields, poses.empty() ? nullptr : &poses.back()));
    }
    if (poses.empty()) fail(lines_.number(), "", "no data rows after the header");
    return poses;
  }

 private:
  [[noreturn]] void fail(int line, const std::string& column, const std::string& what) const {
    throw LogError(source_, line, column, what);
  }

  void checkHeader(std::string_view line) {
    std::array<std::string_view, kNumColumns> fields;
    const int n = splitFields(line, fields);
    const auto& cols = poseLogColumns();
    for (int i = 0; i < std::min(n, kNumColumns); ++i) {
      if (fields[i] != cols[i]) {
        fail(lines_.number(), "",
             "header field " + std::to_string(i + 1) + ": expected '" + cols[i] + "', got " +
                 shown(fields[i]) +
                 " (the header is t,t_arrival,px,py,pz,qw,qx,qy,qz,c00..c55,valid)");
      }
    }
    if (n != kNumColumns) {
      fail(lines_.number(), "",
           "expected a header of " + std::to_string(kNumColumns) + " columns, got " +
               std::to_string(n));
    }
  }

  double number(int column, std::string_view text) const {
    const std::string& name = poseLogColumns()[column];
    if (text.empty()) fail(lines_.number(), name, "expected a number, the field is empty");
    const char* first = text.data();
    const char* last = text.data() + text.size();
    if (*first == '+') ++first;
    double value = 0.0;
    const auto [end, ec] = std::from_chars(first, last, value);
    if (ec == std::errc::result_out_of_range) {
      const double magnitude = std::abs(std::strtod(std::string(text).c_str(), nullptr));
      fail(lines_.number(), name,
           "expected a finite number, got " + shown(text) +
               (magnitude < 1.0 ? " (underflow: too small to represent)"
                                : " (overflow: too large to represent)"));
    }
    if (ec != std::errc() || end != last)
      fail(lines_.number(), name, "expected a number, got " + shown(text));
    if (!std::isfinite(value))
      fail(lines_.number(), name, "expected a finite number, got " + shown(text));
    return value;
  }

  PoseMeasurement parseRow(const std::array<std::string_view, kNumColumns>& f,
                           const PoseMeasurement* previous) const {
    std::array<double, kNumColumns> v{};
    for (int i = 0; i < kNumColumns; ++i) v[i] = number(i, f[i]);
    PoseMeasurement z;
    z.t = v[0];
    z.t_arrival = v[1];
    z.p_MB = Eigen::Vector3d(v[2], v[3], v[4]);
    const Eigen::Quaterniond q(v[5], v[6], v[7], v[8]);
    const double norm = q.norm();
    if (!(std::abs(norm - 1.0) <= 1e-6)) {
      fail(lines_.number(), "qw",
           "expected a unit quaternion qw..qz, its norm is " + numberText(norm));
    }
    z.R_MB = lie::SO3d::fromQuaternion(q);
    int k = kCovFirst;
    for (int i = 0; i < 6; ++i) {
      for (int j = i; j < 6; ++j, ++k) {
        z.cov(i, j) = v[k];
        z.cov(j, i) = v[k];
      }
    }
    if (v[kValid] != 0.0 && v[kValid] != 1.0) {
      fail(lines_.number(), "valid", "expected a valid flag 0 or 1, got " + shown(f[kValid]));
    }
    z.valid = v[kValid] == 1.0;
    const Problem problem = checkPose(z, previous ? previous->t : 0.0, previous != nullptr);
    if (!problem.what.empty()) fail(lines_.number(), problem.column, problem.what);
    return z;
  }

  io::LineSource lines_;
  const std::string& source_;
};

}  // namespace

const std::vector<std::string>& poseLogColumns() {
  static const std::vector<std::string> columns = makeColumns();
  return columns;
}

std::vector<PoseMeasurement> readPoseLog(std::istream& in, const std::string& source) {
  if (!in.rdbuf()) throw LogError(source, 0, "", "no stream to read");
  try {
    auto poses = Reader(in, source).read();
    if (in.bad()) throw LogError(source, 0, "", "read error");
    return poses;
  } catch (const std::bad_alloc&) {
    throw LogError(source, 0, "", "the pose file is too large for this machine's memory");
  }
}

std::vector<PoseMeasurement> readPoseLog(const std::string& path) {
  if (const std::string why = io::notARegularFile(path); !why.empty()) {
    throw LogError(path, 0, "", why);
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw LogError(path, 0, "", "cannot open the file for reading");
  return readPoseLog(in, path);
}

void writePoseLog(std::ostream& out, const std::vector<PoseMeasurement>& poses,
                  const std::vector<std::string>& comments, const std::string& destination) {
  if (poses.empty()) throw LogError(destination, 0, "", "no poses to write (a file needs a row)");
  for (std::size_t k = 0; k < comments.size(); ++k) {
    if (comments[k].find_first_of("\r\n") != std::string::npos) {
      throw LogError(destination, static_cast<int>(k + 1), "",
                     "a comment may not contain a line end");
    }
  }
  const int first_row_line = static_cast<int>(comments.size()) + 2;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const Problem problem = checkPose(poses[k], k > 0 ? poses[k - 1].t : 0.0, k > 0);
    if (!problem.what.empty()) {
      throw LogError(destination, first_row_line + static_cast<int>(k), problem.column,
                     "pose " + std::to_string(k) + ": " + problem.what);
    }
  }
  for (const auto& c : comments) out << "# " << c << '\n';
  const auto& cols = poseLogColumns();
  for (int i = 0; i < kNumColumns; ++i) out << (i ? "," : "") << cols[i];
  out << '\n';
  for (const auto& z : poses) {
    Eigen::Quaterniond q = z.R_MB.quaternion().normalized();
    if (q.w() < 0) q.coeffs() = -q.coeffs();  // one sign for one rotation
    out << numberText(z.t) << ',' << numberText(z.t_arrival);
    for (int i = 0; i < 3; ++i) out << ',' << numberText(z.p_MB(i));
    out << ',' << numberText(q.w()) << ',' << numberText(q.x()) << ',' << numberText(q.y()) << ','
        << numberText(q.z());
    for (int i = 0; i < 6; ++i) {
      for (int j = i; j < 6; ++j) out << ',' << numberText(z.cov(i, j));
    }
    out << ',' << (z.valid ? '1' : '0') << '\n';
  }
  out.flush();
  if (!out) throw LogError(destination, 0, "", "write error (disk full or stream closed?)");
}

void writePoseLog(const std::string& path, const std::vector<PoseMeasurement>& poses,
                  const std::vector<std::string>& comments) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw LogError(path, 0, "", "cannot open the file for writing");
  writePoseLog(out, poses, comments, path);
  out.close();
  if (!out) throw LogError(path, 0, "", "write error when closing the file");
}

}  // namespace legkit::fusion
