#include "estimation/imu/log_drift.hpp"

#include <cmath>
#include <stdexcept>

#include "estimation/imu/dead_reckoning.hpp"
#include "estimation/imu/input_checks.hpp"

namespace legkit::imu {

std::vector<DriftSample> deadReckoningDriftOnLog(const io::Log& log, const model::ImuBias& b_hat,
                                                 double report_every) {
  detail::requirePositiveStep(report_every, "deadReckoningDriftOnLog (report_every)");
  if (!log.layout.ground_truth)
    throw std::invalid_argument("deadReckoningDriftOnLog: the log has no ground-truth columns");
  if (log.rows.size() < 2)
    throw std::invalid_argument("deadReckoningDriftOnLog: the log needs at least two rows");

  const io::LogRow& first = log.rows.front();
  const auto truthOf = [](const io::LogRow& r) {
    return NavState{lie::SO3d::fromQuaternion(r.gt_q), r.gt_v, r.gt_p};
  };
  NavState x = truthOf(first);
  std::vector<DriftSample> out;
  double next_report = 0.0;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const io::LogRow& row = log.rows[k];
    const double t = row.t - first.t;
    if (t >= next_report - 1e-9) {
      const NavState truth = truthOf(row);
      const double deg = truth.R.rminus(x.R).norm() * 180.0 / M_PI;
      out.push_back({t, (x.p - truth.p).norm(), (x.v - truth.v).norm(), deg});
      next_report += report_every;
    }
    if (k + 1 == log.rows.size()) break;
    const double dt = log.rows[k + 1].t - row.t;  // deadReckoningStep rejects dt <= 0
    x = deadReckoningStep(x, model::ImuReading{row.gyro, row.acc}, b_hat, dt);
  }
  return out;
}

}  // namespace legkit::imu
