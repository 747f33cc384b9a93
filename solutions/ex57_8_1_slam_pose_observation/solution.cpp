// Reference solution to exercise 57.8.1.
#include <cmath>
#include <stdexcept>
#include <string>

#include "ex57_8_1.hpp"

namespace ex57_8_1 {

// T_MO = T_MB (T_OB)^-1. With R_MB = Exp(a) R_MB_hat, p_MB = p_MB_hat + b (the SLAM's error, map
// frame) and R_OB = Exp(c) R_OB_hat, p_OB = p_OB_hat + d (the odometry's, odom frame), to first
// order:
//   dtheta_MO = a - R_MO c
//   dp_MO     = b - R_MO d + [q]x dtheta_MO,   q = R_MO p_OB (the base's offset from O, in M),
// so cov_MO = J_s cov_s J_s^T + J_o cov_o J_o^T with
//   J_s = [ I     0 ]      J_o = [ -R_MO          0     ]
//         [ [q]x  I ],           [ -[q]x R_MO   -R_MO  ].
// A filter whose state is T_MO (the kit's estimation/fusion/map_odom.hpp) then sees this
// measurement directly: innovation (Log(R_MO,meas R_MO_hat^T), p_MO,meas - p_MO_hat), H = I_6,
// measurement covariance cov_MO. The lever arm q makes an attitude error of either pose a position
// error of T_MO that grows with the distance from the odom origin.
Pose mapOdomMeasurement(const PoseMeasurement& z, const Pose& T_OB) {
  Pose T_MO;
  T_MO.R = z.R_MB * T_OB.R.inverse();
  const Eigen::Matrix3d R_MO = T_MO.R.matrix();
  const Eigen::Vector3d q = R_MO * T_OB.p;
  T_MO.p = z.p_MB - q;

  const Eigen::Matrix3d q_x = lie::hat3(q);
  Matrix6d J_s = Matrix6d::Identity();
  J_s.block<3, 3>(3, 0) = q_x;
  Matrix6d J_o = Matrix6d::Zero();
  J_o.block<3, 3>(0, 0) = -R_MO;
  J_o.block<3, 3>(3, 0) = -q_x * R_MO;
  J_o.block<3, 3>(3, 3) = -R_MO;
  T_MO.cov = J_s * z.cov * J_s.transpose() + J_o * T_OB.cov * J_o.transpose();
  return T_MO;
}

OdomHistory::OdomHistory(std::size_t capacity) : ring_(capacity) {}

void OdomHistory::push(double t, const Pose& T_OB) {
  if (ring_.empty()) throw std::invalid_argument("OdomHistory::push: the history has capacity 0");
  if (!std::isfinite(t)) throw std::invalid_argument("OdomHistory::push: the time is not finite");
  if (size_ > 0) {
    const double t_newest = ring_[(head_ + ring_.size() - 1) % ring_.size()].t;
    if (!(t > t_newest))
      throw std::invalid_argument("OdomHistory::push: time " + std::to_string(t) +
                                  " is not after the newest pose's " + std::to_string(t_newest));
  }
  ring_[head_] = Stamped{t, T_OB};
  head_ = (head_ + 1) % ring_.size();
  if (size_ < ring_.size()) ++size_;
}

Pose OdomHistory::at(double t) const {
  const std::size_t n = ring_.size();
  // The k-th oldest pose held (k = 0 the oldest).
  const auto entry = [&](std::size_t k) -> const Stamped& {
    return ring_[(head_ + n - size_ + k) % n];
  };
  if (size_ == 0) throw std::out_of_range("OdomHistory::at: the history is empty");
  const double t_oldest = entry(0).t, t_newest = entry(size_ - 1).t;
  if (!(t >= t_oldest && t <= t_newest))
    throw std::out_of_range("OdomHistory::at: time " + std::to_string(t) + " is outside the " +
                            "history [" + std::to_string(t_oldest) + ", " +
                            std::to_string(t_newest) + "]");
  // Binary search for the first pose at or after t.
  std::size_t lo = 0, hi = size_ - 1;
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    if (entry(mid).t < t)
      lo = mid + 1;
    else
      hi = mid;
  }
  const Stamped& b = entry(lo);
  if (b.t == t) return b.pose;  // also the oldest (lo == 0 only when t is its time)
  const Stamped& a = entry(lo - 1);
  const double s = (t - a.t) / (b.t - a.t);
  Pose out;
  out.R = a.pose.R.interpolate(b.pose.R, s);  // R0 Exp(s Log(R0^T R1))
  out.p = a.pose.p + s * (b.pose.p - a.pose.p);
  out.cov = (1.0 - s) * a.pose.cov + s * b.pose.cov;
  return out;
}

}  // namespace ex57_8_1
