#include "eval/metrics.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace legkit::eval {

double tiltError(const Eigen::Matrix3d& R_hat, const Eigen::Matrix3d& R) {
  const Eigen::Vector3d a = R_hat.transpose().col(2);  // world z seen from the estimated body
  const Eigen::Vector3d b = R.transpose().col(2);      // and from the true body
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

double yawError(const Eigen::Matrix3d& R_hat, const Eigen::Matrix3d& R) {
  const double d = std::atan2(R_hat(1, 0), R_hat(0, 0)) - std::atan2(R(1, 0), R(0, 0));
  return std::remainder(d, 2.0 * M_PI);  // wrap to [-pi, pi]
}

Metrics compare(const io::Log& truth, const Trajectory& estimate) {
  if (!truth.layout.ground_truth) {
    throw std::invalid_argument("eval::compare: the log has no ground-truth columns (gt_*)");
  }
  if (truth.rows.size() != estimate.size() || estimate.empty()) {
    std::ostringstream os;
    os << "eval::compare: " << estimate.size() << " estimates for " << truth.rows.size()
       << " log rows";
    throw std::invalid_argument(os.str());
  }
  Metrics m;
  double sp = 0.0, sv = 0.0, st = 0.0, sy = 0.0;
  for (std::size_t k = 0; k < estimate.size(); ++k) {
    const io::LogRow& row = truth.rows[k];
    const EstimateSample& e = estimate[k];
    if (row.t != e.t) {
      std::ostringstream os;
      os << "eval::compare: estimate " << k << " is at t = " << e.t << " but log row " << k
         << " is at t = " << row.t;
      throw std::invalid_argument(os.str());
    }
    const Eigen::Matrix3d R = row.gt_q.toRotationMatrix();
    const Eigen::Matrix3d R_hat = e.q.toRotationMatrix();
    sp += (e.p - row.gt_p).squaredNorm();
    sv += (e.v - row.gt_v).squaredNorm();
    st += std::pow(tiltError(R_hat, R), 2);
    sy += std::pow(yawError(R_hat, R), 2);
    if (k > 0) m.distance += (row.gt_p - truth.rows[k - 1].gt_p).norm();
  }
  const double n = static_cast<double>(estimate.size());
  const double deg = 180.0 / M_PI;
  m.position_rmse = std::sqrt(sp / n);
  m.velocity_rmse = std::sqrt(sv / n);
  m.tilt_rmse_deg = std::sqrt(st / n) * deg;
  m.yaw_rmse_deg = std::sqrt(sy / n) * deg;
  m.final_position_error = (estimate.back().p - truth.rows.back().gt_p).norm();
  m.drift_percent = m.distance > 0.0 ? 100.0 * m.final_position_error / m.distance : 0.0;
  return m;
}

}  // namespace legkit::eval
