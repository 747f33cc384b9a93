#include "estimation/imu/allan.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <new>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "estimation/health.hpp"
#include "io/csv_text.hpp"
#include "io/input_file.hpp"
#include "io/log_error.hpp"
#include "io/log_reader.hpp"

namespace legkit::imu {

std::vector<int> allanFactors(std::size_t samples, double ratio) {
  if (!(ratio > 1.0) || !std::isfinite(ratio))
    throw std::invalid_argument("allanFactors: the ratio must be a number > 1");
  const auto m_max = static_cast<double>(samples / 4);
  std::vector<int> factors;
  for (int k = 0;; ++k) {
    const double m = std::round(std::pow(ratio, k));
    if (m > m_max) break;
    if (factors.empty() || static_cast<int>(m) > factors.back())
      factors.push_back(static_cast<int>(m));
  }
  return factors;
}

std::vector<AllanPoint> allanDeviation(const Eigen::Ref<const Eigen::VectorXd>& y, double tau0,
                                       const std::vector<int>& factors) {
  const Eigen::Index n = y.size();
  if (!(tau0 > 0.0) || !std::isfinite(tau0))
    throw std::invalid_argument("allanDeviation: tau0 must be a positive number of seconds");
  // Phase x_i = tau0 sum_{k<i} (y_k - mean): the mean drops out of every second difference and
  // keeps x small, so the differences keep their digits.
  const double mean = y.mean();
  Eigen::VectorXd x(n + 1);
  x(0) = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) x(i + 1) = x(i) + (y(i) - mean) * tau0;

  std::vector<AllanPoint> curve;
  curve.reserve(factors.size());
  for (const int m : factors) {
    if (m < 1 || m > n / 4)
      throw std::invalid_argument("allanDeviation: averaging factor " + std::to_string(m) +
                                  " outside 1.." + std::to_string(n / 4));
    const Eigen::Index terms = n + 1 - 2 * m;  // second differences in the record
    // sum (x_{i+2m} - 2 x_{i+m} + x_i)^2 over i = 0 .. N - 2m (NIST SP 1065)
    const double sum =
        (x.segment(2 * m, terms) - 2.0 * x.segment(m, terms) + x.head(terms)).squaredNorm();
    AllanPoint p;
    p.m = m;
    p.tau = m * tau0;
    p.adev = std::sqrt(sum / (2.0 * p.tau * p.tau * static_cast<double>(terms)));
    p.clusters = static_cast<double>(n) / m;
    const double half = 1.0 / std::sqrt(p.clusters);  // the simple 1-sigma rule, n >= 4
    p.lo = p.adev * (1.0 - half);
    p.hi = p.adev * (1.0 + half);
    curve.push_back(p);
  }
  return curve;
}

namespace {

// Least-squares slope of log adev against log tau over the points within a factor of 2 of
// curve[i]'s tau (NaN with fewer than two).
double localSlope(const std::vector<AllanPoint>& curve, std::size_t i) {
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  int count = 0;
  for (const AllanPoint& p : curve) {
    if (p.tau < curve[i].tau / 2.0 * (1.0 - 1e-9) || p.tau > curve[i].tau * 2.0 * (1.0 + 1e-9))
      continue;
    if (!(p.adev > 0.0)) continue;
    const double lx = std::log(p.tau), ly = std::log(p.adev);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
    ++count;
  }
  const double denominator = count * sxx - sx * sx;
  if (count < 2 || !(denominator > 0.0)) return kNaN;
  return (count * sxy - sx * sy) / denominator;
}

}  // namespace

SlopeLine fitSlopeLine(const std::vector<AllanPoint>& curve, double slope, double tau_read,
                       double slope_tolerance) {
  SlopeLine line;
  line.slope = slope;
  line.tau_read = tau_read;
  double weight = 0.0, log_level = 0.0, error = 0.0;
  for (std::size_t i = 0; i < curve.size(); ++i) {
    const AllanPoint& p = curve[i];
    if (!(std::abs(localSlope(curve, i) - slope) <= slope_tolerance)) continue;
    // On the line: log sigma = log level + slope log(tau / tau_read).
    log_level += p.clusters * (std::log(p.adev) - slope * std::log(p.tau / tau_read));
    error += p.clusters / std::sqrt(p.clusters);
    weight += p.clusters;
    line.tau_first = line.points == 0 ? p.tau : line.tau_first;
    line.tau_last = p.tau;
    ++line.points;
  }
  if (line.points > 0) {
    line.level = std::exp(log_level / weight);
    line.relative_error = error / weight;
  }
  return line;
}

model::ImuNoise AllanAnalysis::noise() const {
  // Per sensor the largest axis; NaN (std::max keeps its first argument) if any axis has none.
  const auto largest = [this](int first, const SlopeLine AxisNoise::*line) {
    double out = -1.0;
    for (int a = first; a < first + 3; ++a) {
      const double level = (axes[a].*line).level;
      if (!std::isfinite(level)) return kNaN;
      out = std::max(out, level);
    }
    return out;
  };
  model::ImuNoise noise;
  noise.gyro_noise_density = largest(0, &AxisNoise::white);
  noise.accel_noise_density = largest(3, &AxisNoise::white);
  noise.gyro_bias_random_walk = largest(0, &AxisNoise::random_walk);
  noise.accel_bias_random_walk = largest(3, &AxisNoise::random_walk);
  return noise;
}

std::string AllanAnalysis::moved() const {
  using Limits = model::ImuNoiseLimits;
  for (int a = 0; a < ImuRecording::kAxes; ++a) {
    const bool gyro = a < 3;
    const struct {
      const SlopeLine& line;
      const char* what;
      double limit;
      const char* unit;
    } checks[] = {{axes[a].white, "white noise density",
                   gyro ? Limits::gyro_noise_density : Limits::accel_noise_density,
                   gyro ? "rad/s/sqrt(Hz)" : "m/s^2/sqrt(Hz)"},
                  {axes[a].random_walk, "bias random walk",
                   gyro ? Limits::gyro_bias_random_walk : Limits::accel_bias_random_walk,
                   gyro ? "rad/s^2/sqrt(Hz)" : "m/s^3/sqrt(Hz)"}};
    for (const auto& c : checks) {
      if (c.line.found() && c.line.level > c.limit) {
        std::ostringstream why;
        why << ImuRecording::kAxisNames[a] << " reads a " << c.what << " of " << c.line.level << " "
            << c.unit << " (from tau " << c.line.tau_first << " to " << c.line.tau_last
            << " s), where an IMU at rest shows at most " << c.limit;
        return why.str();
      }
    }
  }
  return {};
}

AllanAnalysis analyseImu(const ImuRecording& recording, const AllanOptions& options) {
  AllanAnalysis analysis;
  analysis.tau0 = recording.tau0;
  analysis.samples = recording.samples();
  if (analysis.samples < 8)
    throw std::invalid_argument("an Allan deviation needs at least 8 samples, " + recording.source +
                                " has " + std::to_string(analysis.samples));
  const std::vector<int> factors = allanFactors(analysis.samples, options.ratio);
  Eigen::VectorXd y(static_cast<Eigen::Index>(analysis.samples));
  for (int a = 0; a < ImuRecording::kAxes; ++a) {
    AxisNoise& axis = analysis.axes[a];
    y = recording.axis(a);
    axis.curve = allanDeviation(y, recording.tau0, factors);
    axis.white = fitSlopeLine(axis.curve, -0.5, 1.0, options.slope_tolerance);
    axis.random_walk = fitSlopeLine(axis.curve, 0.5, 3.0, options.slope_tolerance);
    // The minimum counts only where the curve turns up again after it (a flat bottom, not the
    // end of a curve that is still falling).
    const auto lowest =
        std::min_element(axis.curve.begin(), axis.curve.end(),
                         [](const AllanPoint& a, const AllanPoint& b) { return a.adev < b.adev; });
    if (lowest != axis.curve.end() && lowest + 1 != axis.curve.end() &&
        lowest != axis.curve.begin()) {
      axis.tau_min = lowest->tau;
      axis.bias_instability = lowest->adev / 0.664;  // sqrt(2 ln 2 / pi) = 0.664 (IEEE 952)
    }
  }
  return analysis;
}

// ----------------------------------------------------------------------------------------------
// Reading

namespace {

using io::shown;
using io::trim;

constexpr std::array<const char*, 7> kPlainHeader = {"t", "gx", "gy", "gz", "ax", "ay", "az"};

// A reading beyond a sensor's full scale is not a resting IMU's (a 2000 deg/s gyro, a 16 g
// accelerometer: estimation/health.hpp's InputLimits, which the filters hold their input to).
// Without this check a value near 1e300 overflows the Allan sums into "not found" and B = 0.
void checkFullScale(const double* reading, const std::string& path, int line,
                    const std::array<const char*, ImuRecording::kAxes>& columns) {
  const InputLimits limits;
  for (int a = 0; a < ImuRecording::kAxes; ++a) {
    const bool gyro = a < 3;
    const double full_scale = gyro ? limits.gyro_max : limits.accel_max;
    if (std::abs(reading[a]) > full_scale) {
      throw io::LogError(path, line, columns[a],
                         std::string(gyro ? "a rate of " : "a specific force of ") +
                             std::to_string(reading[a]) + (gyro ? " rad/s" : " m/s^2") +
                             " is beyond an IMU's full scale (" + std::to_string(full_scale) +
                             (gyro ? " rad/s, 2000 deg/s" : " m/s^2, 16 g") +
                             "): not a resting IMU's reading");
    }
  }
}

bool isPlainHeader(std::string_view line) {
  std::size_t column = 0;
  while (true) {
    const std::size_t comma = line.find(',');
    const std::string_view name = trim(line.substr(0, comma));
    if (column >= kPlainHeader.size() || name != kPlainHeader[column]) return false;
    ++column;
    if (comma == std::string_view::npos) break;
    line.remove_prefix(comma + 1);
  }
  return column == kPlainHeader.size();
}

// Checks the timestamps of rows first_line, first_line + 1, ...: strictly increasing, each step
// within kMinStepRatio .. kMaxStepRatio of the median step. Returns the mean step.
double uniformStep(const std::vector<double>& t, const std::string& file, std::size_t first_line) {
  if (t.size() < 2) throw io::LogError(file, 0, "", "fewer than two samples: no sample period");
  std::vector<double> steps(t.size() - 1);
  for (std::size_t k = 1; k < t.size(); ++k) {
    steps[k - 1] = t[k] - t[k - 1];
    if (!(steps[k - 1] > 0.0))
      throw io::LogError(file, static_cast<int>(first_line + k), "t",
                         "time does not increase (" + std::to_string(t[k]) + " s after " +
                             std::to_string(t[k - 1]) + " s)");
  }
  std::vector<double> sorted = steps;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = sorted[sorted.size() / 2];
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const double ratio = steps[k] / median;
    if (ratio > kMaxStepRatio || ratio < kMinStepRatio)
      throw io::LogError(file, static_cast<int>(first_line + k + 1), "t",
                         (ratio > kMaxStepRatio ? "a gap: " : "an uneven step: ") +
                             std::to_string(steps[k]) + " s since the previous sample, " +
                             std::to_string(ratio) + " times the median step " +
                             std::to_string(median) +
                             " s (the Allan deviation needs uniform samples: each step within "
                             "0.5..1.5 median steps)");
  }
  return (t.back() - t.front()) / static_cast<double>(t.size() - 1);
}

ImuRecording readPlain(std::istream& in, const std::string& path, std::size_t header_line) {
  ImuRecording rec;
  rec.source = path;
  std::vector<double> t;
  std::string text;
  std::size_t line = header_line;
  while (std::getline(in, text)) {
    ++line;
    std::string_view rest = text;
    double value[7];
    for (std::size_t c = 0; c < 7; ++c) {
      const std::size_t comma = rest.find(',');
      if ((comma == std::string_view::npos) != (c == 6))
        throw io::LogError(
            path, static_cast<int>(line), "",
            c < 6 ? "expected 7 fields (t,gx,gy,gz,ax,ay,az), found " + std::to_string(c + 1)
                  : "more than 7 fields (t,gx,gy,gz,ax,ay,az)");
      const std::string_view field = trim(rest.substr(0, comma));
      const char* end = field.data() + field.size();
      const auto [ptr, ec] = std::from_chars(field.data(), end, value[c]);
      if (field.empty() || ec != std::errc() || ptr != end || !std::isfinite(value[c]))
        throw io::LogError(path, static_cast<int>(line), kPlainHeader[c],
                           "expected a finite number, found " + shown(field));
      if (comma != std::string_view::npos) rest.remove_prefix(comma + 1);
    }
    if (!t.empty() && !(value[0] > t.back()))
      throw io::LogError(path, static_cast<int>(line), "t",
                         "time does not increase (" + shown(trim(text.substr(0, text.find(',')))) +
                             " after " + std::to_string(t.back()) + " s)");
    checkFullScale(value + 1, path, static_cast<int>(line),
                   {kPlainHeader[1], kPlainHeader[2], kPlainHeader[3], kPlainHeader[4],
                    kPlainHeader[5], kPlainHeader[6]});
    t.push_back(value[0]);
    rec.values.insert(rec.values.end(), value + 1, value + 7);
  }
  if (in.bad()) throw io::LogError(path, static_cast<int>(line), "", "read error");
  rec.tau0 = uniformStep(t, path, header_line + 1);
  return rec;
}

}  // namespace

ImuRecording readImuRecording(const std::string& path) {
  if (const std::string why = io::notARegularFile(path); !why.empty()) {
    throw io::LogError(path, 0, "", why);
  }
  std::ifstream in(path);
  if (!in) throw io::LogError(path, 0, "", "cannot open the file");
  std::string text;
  std::size_t line = 0;
  while (std::getline(in, text)) {
    ++line;
    std::string_view header = text;
    if (line == 1 && header.substr(0, 3) == "\xEF\xBB\xBF") header.remove_prefix(3);
    if (!trim(header).empty() && header.front() == '#') continue;
    if (isPlainHeader(trim(header))) {
      // Streamed at 56 bytes a sample: a recording larger than the memory is said, not a bare
      // std::bad_alloc (the kit's log format below has the same message from its reader).
      try {
        return readPlain(in, path, line);
      } catch (const std::bad_alloc&) {
        throw io::LogError(path, 0, "",
                           "the recording is too large for this machine's memory (56 bytes a "
                           "sample): analyse a part of it");
      }
    }
    break;
  }
  // Not the plain header: the kit's log, with every check of its reader.
  in.close();
  const io::Log log = io::readLog(path);
  ImuRecording rec;
  rec.source = path;
  std::vector<double> t;
  t.reserve(log.rows.size());
  rec.values.reserve(log.rows.size() * ImuRecording::kAxes);
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const io::LogRow& row = log.rows[k];
    const double reading[ImuRecording::kAxes] = {row.gyro.x(), row.gyro.y(), row.gyro.z(),
                                                 row.acc.x(),  row.acc.y(),  row.acc.z()};
    checkFullScale(reading, path, log.lineOfRow(k), ImuRecording::kAxisNames);
    t.push_back(row.t);
    rec.values.insert(rec.values.end(), reading, reading + ImuRecording::kAxes);
  }
  rec.tau0 = uniformStep(t, path, log.lineOfRow(0));
  return rec;
}

}  // namespace legkit::imu
