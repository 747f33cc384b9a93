#include "estimation/log_conditioning.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iomanip>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace legkit {

namespace {

// The median row interval [s] (0 for fewer than 2 rows).
double medianInterval(const std::vector<double>& t) {
  if (t.size() < 2) return 0.0;
  std::vector<double> dt(t.size() - 1);
  for (std::size_t k = 1; k < t.size(); ++k) dt[k - 1] = t[k] - t[k - 1];
  const auto middle = dt.begin() + static_cast<std::ptrdiff_t>(dt.size() / 2);
  std::nth_element(dt.begin(), middle, dt.end());
  return *middle;
}

std::vector<double> stamps(const std::vector<io::LogRow>& rows) {
  std::vector<double> t(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) t[k] = rows[k].t;
  return t;
}

}  // namespace

double stampJitter(const std::vector<double>& t) {
  const double gap = kStampGapFactor * medianInterval(t);
  double sum = 0.0;
  double sum_squares = 0.0;
  int count = 0;
  for (std::size_t k = 1; k < t.size(); ++k) {
    const double dt = t[k] - t[k - 1];
    if (dt > gap) continue;
    sum += dt;
    sum_squares += dt * dt;
    ++count;
  }
  if (count < 2) return 0.0;
  const double mean = sum / count;
  return std::sqrt(std::max(0.0, sum_squares / count - mean * mean)) / mean;
}

std::vector<double> smoothedStamps(const std::vector<double>& t, int half_window) {
  const auto n = static_cast<std::ptrdiff_t>(t.size());
  const double gap = kStampGapFactor * medianInterval(t);
  std::vector<double> out(t.size());
  std::ptrdiff_t segment_start = 0;
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (i > 0 && t[i] - t[i - 1] > gap) segment_start = i;
    std::ptrdiff_t segment_end = i;  // the last row before the next gap
    while (segment_end + 1 < n && segment_end < i + half_window &&
           t[segment_end + 1] - t[segment_end] <= gap) {
      ++segment_end;
    }
    const std::ptrdiff_t first = std::max(segment_start, i - half_window);
    const std::ptrdiff_t last = segment_end;
    // Least squares t = a + b x over x = j - i, evaluated at x = 0: t_mean - b x_mean.
    const auto count = static_cast<double>(last - first + 1);
    double x_mean = 0.0;
    double t_mean = 0.0;
    for (std::ptrdiff_t j = first; j <= last; ++j) {
      x_mean += static_cast<double>(j - i);
      t_mean += t[j];
    }
    x_mean /= count;
    t_mean /= count;
    double sxt = 0.0;
    double sxx = 0.0;
    for (std::ptrdiff_t j = first; j <= last; ++j) {
      const double x = static_cast<double>(j - i) - x_mean;
      sxt += x * (t[j] - t_mean);
      sxx += x * x;
    }
    out[i] = sxx > 0.0 ? t_mean - (sxt / sxx) * x_mean : t_mean;
    if (i > 0 && !(out[i] > out[i - 1])) {
      throw std::invalid_argument("the smoothed time stamps do not increase at row " +
                                  std::to_string(i) + " (its stamp " + std::to_string(t[i]) +
                                  " s): keep the log's own (frontend.timestamps: logged)");
    }
  }
  return out;
}

std::string ConditioningReport::describe() const {
  std::ostringstream os;
  os << "time stamps ";
  if (stamps_smoothed) {
    os << "smoothed (jitter " << std::lround(100.0 * jitter) << " % of the row interval; moved "
       << std::fixed << std::setprecision(1) << max_stamp_shift * 1e3 << " ms at most)";
  } else {
    os << "as logged (jitter " << std::lround(100.0 * jitter) << " %"
       << (smoothing_failure.empty() ? "" : "; not smoothed: " + smoothing_failure) << ")";
  }
  os << "; joint velocities "
     << (velocities_from_angles ? "differentiated from the angles" : "as logged");
  if (velocities_absent) os << " (the log has none)";
  if (held_imu_rows > 0) os << "; IMU held on " << held_imu_rows << " rows (integrated as held)";
  return os.str();
}

namespace {

// dq_k = (q_k - q_{k-1}) / (t_k - t_{k-1}); row 0 takes row 1's.
template <typename Angles, typename Velocities>
void differentiate(std::vector<io::LogRow>& rows, Angles angles, Velocities velocities) {
  for (std::size_t k = 1; k < rows.size(); ++k) {
    velocities(rows[k]) = (angles(rows[k]) - angles(rows[k - 1])) / (rows[k].t - rows[k - 1].t);
  }
  velocities(rows[0]) = velocities(rows[1]);
}

}  // namespace

ConditioningReport condition(io::Log& log, const LogConditioning& what) {
  ConditioningReport report;
  std::vector<io::LogRow>& rows = log.rows;
  std::vector<double> t = stamps(rows);
  report.jitter = stampJitter(t);
  for (std::size_t k = 1; k < rows.size(); ++k) {
    if (rows[k].gyro == rows[k - 1].gyro && rows[k].acc == rows[k - 1].acc) ++report.held_imu_rows;
  }
  report.stamps_smoothed =
      what.stamps == StampHandling::kSmoothed ||
      (what.stamps == StampHandling::kAuto && report.jitter > kStampJitterLimit);
  if (report.stamps_smoothed) {
    std::vector<double> smooth;
    try {
      smooth = smoothedStamps(t);
    } catch (const std::invalid_argument& e) {
      if (what.stamps == StampHandling::kSmoothed) throw;
      report.stamps_smoothed = false;  // auto: the log's own stamps, and the summary says why
      report.smoothing_failure = e.what();
    }
    for (std::size_t k = 0; k < smooth.size(); ++k) {
      report.max_stamp_shift = std::max(report.max_stamp_shift, std::abs(smooth[k] - t[k]));
      rows[k].t = smooth[k];
    }
  }
  const bool has_joints = log.layout.joints || log.layout.num_joints > 0;
  report.velocities_absent = has_joints && !log.layout.joint_velocity;
  if (report.velocities_absent && what.joint_velocities == JointVelocitySource::kLogged) {
    throw std::invalid_argument(
        "frontend.joint_velocities is 'logged', but the log has no joint velocity columns (dq_ "
        "or joint<k>_dq): set it to 'angles' or 'auto' to differentiate the angles");
  }
  report.velocities_from_angles =
      (what.joint_velocities == JointVelocitySource::kAngles || report.velocities_absent) &&
      has_joints && rows.size() >= 2;
  if (report.velocities_from_angles) {
    if (log.layout.joints) {
      differentiate(
          rows, [](io::LogRow& r) -> io::JointVector& { return r.q; },
          [](io::LogRow& r) -> io::JointVector& { return r.dq; });
    } else {
      differentiate(
          rows, [](io::LogRow& r) -> io::GenericJointVector& { return r.joint_q; },
          [](io::LogRow& r) -> io::GenericJointVector& { return r.joint_dq; });
    }
  }
  return report;
}

// The time base of a recorded log: a median period outside [10 us, 100 ms] means the
// timestamps are not in seconds; a step longer than max_gap (default: 10 median periods) is a
// hole in the log that no estimator should bridge. Throws std::invalid_argument naming the file
// and line (and `gap_option`, the way to give another bound).
void checkTimeBase(const io::Log& log, std::optional<double> max_gap,
                   const std::string& gap_option) {
  if (log.rows.size() < 2) {
    throw std::invalid_argument(log.source + ": " + std::to_string(log.rows.size()) +
                                " row(s): a run needs at least two (one interval to integrate)");
  }
  std::vector<double> dt(log.rows.size() - 1);
  for (std::size_t k = 1; k < log.rows.size(); ++k) dt[k - 1] = log.rows[k].t - log.rows[k - 1].t;
  std::vector<double> sorted = dt;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = sorted[sorted.size() / 2];
  if (median < 1e-5 || median > 0.1) {
    std::ostringstream os;
    os << log.source << ": the median time between samples is " << median
       << " s, outside [1e-05, 0.1] s: are the timestamps in seconds? (chapters/57.0)";
    throw std::invalid_argument(os.str());
  }
  const double bound = max_gap.value_or(10.0 * median);
  for (std::size_t k = 1; k < log.rows.size(); ++k) {
    if (dt[k - 1] <= bound) continue;
    std::ostringstream os;
    os << log.source << ":" << log.lineOfRow(k) << ": a gap of " << dt[k - 1]
       << " s after t = " << log.rows[k - 1].t << " s, more than " << bound << " s ("
       << (max_gap ? gap_option : "10 median sample periods; " + gap_option + " sets another bound")
       << ")";
    throw std::invalid_argument(os.str());
  }
}

}  // namespace legkit
