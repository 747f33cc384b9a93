#include "eval/metrics.hpp"

#include <Eigen/Geometry>
#include <algorithm>
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

namespace {

struct Pose {
  Eigen::Matrix3d R;
  Eigen::Vector3d p;
  Pose operator*(const Pose& o) const { return {R * o.R, R * o.p + p}; }
  Pose inverse() const { return {R.transpose(), -(R.transpose() * p)}; }
};

Pose truePose(const io::LogRow& row) {
  return {row.gt_q.toRotationMatrix(), row.gt_p};
}
Pose estimatedPose(const EstimateSample& e) {
  return {e.q.toRotationMatrix(), e.p};
}

double ateRmse(const io::Log& truth, const Trajectory& estimate) {
  const Pose T_a = truePose(truth.rows.front()) * estimatedPose(estimate.front()).inverse();
  double s = 0.0;
  for (std::size_t k = 0; k < estimate.size(); ++k) {
    s += (truth.rows[k].gt_p - (T_a * estimatedPose(estimate[k])).p).squaredNorm();
  }
  return std::sqrt(s / static_cast<double>(estimate.size()));
}

RelativeError rpe(const io::Log& truth, const Trajectory& estimate,
                  const std::vector<double>& travelled, double d) {
  RelativeError r;
  r.distance = d;
  double st = 0.0, sr = 0.0;
  std::size_t j = 0;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    j = std::max(j, i);
    while (j < estimate.size() && travelled[j] - travelled[i] < d) ++j;
    if (j == estimate.size()) break;
    const Pose motion = truePose(truth.rows[i]).inverse() * truePose(truth.rows[j]);
    const Pose motion_hat = estimatedPose(estimate[i]).inverse() * estimatedPose(estimate[j]);
    const Pose E = motion.inverse() * motion_hat;
    st += E.p.squaredNorm();
    sr += std::pow(Eigen::AngleAxisd(E.R).angle(), 2);
    ++r.pairs;
  }
  if (r.pairs > 0) {
    r.translation_rmse = std::sqrt(st / r.pairs);
    r.translation_percent = 100.0 * r.translation_rmse / d;
    r.rotation_rmse_deg = std::sqrt(sr / r.pairs) * 180.0 / M_PI;
  }
  return r;
}

}  // namespace

Metrics compare(const io::Log& truth, const Trajectory& estimate,
                const std::vector<double>& rpe_distances) {
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
  m.ate_rmse = ateRmse(truth, estimate);
  std::vector<double> travelled(estimate.size(), 0.0);  // distance along the truth to row k
  for (std::size_t k = 1; k < estimate.size(); ++k) {
    travelled[k] = travelled[k - 1] + (truth.rows[k].gt_p - truth.rows[k - 1].gt_p).norm();
  }
  for (const double d : rpe_distances) m.rpe.push_back(rpe(truth, estimate, travelled, d));
  return m;
}

}  // namespace legkit::eval
