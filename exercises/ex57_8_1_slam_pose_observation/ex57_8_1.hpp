// Exercise 57.8.1: a 10 Hz SLAM pose as an observation of the map-to-odom transform T_MO, with its
// noise model and its latency (loose coupling, section 57.8).
//
// Frames: O = the proprioceptive filter's odom frame, M = the SLAM map, B = the base. Every
// uncertainty is the kit's (dtheta, dp) in the pose's reference frame, angle first:
//   R = Exp(dtheta) R_hat,   p = p_hat + dp,   (dtheta, dp) ~ N(0, cov).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "estimation/fusion/pose_measurement.hpp"
#include "lie/so3.hpp"

namespace ex57_8_1 {

using legkit::fusion::Matrix6d;
using legkit::fusion::PoseMeasurement;

// A pose of B (or of O) in a reference frame, with the covariance of its (dtheta, dp) error in that
// reference frame.
struct Pose {
  lie::SO3d R;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Matrix6d cov = Matrix6d::Zero();
};

// (a) + (b): the measurement of T_MO that one SLAM pose z (T_MB at its stamp z.t) gives together
// with the odometry pose T_OB at the SAME instant:
//   T_MO = T_MB (T_OB)^-1:   R_MO = R_MB R_OB^T,   p_MO = p_MB - R_MO p_OB,
// and its covariance, to first order, from z.cov (map frame) and T_OB.cov (odom frame), the two
// errors independent. The result's cov is of T_MO's (dtheta, dp) in the map frame. z.valid is not
// looked at (the caller gates).
Pose mapOdomMeasurement(const PoseMeasurement& z, const Pose& T_OB);

// (c): the last `capacity` odometry poses by time (a ring buffer: storage allocated once, in the
// constructor; a push over capacity drops the oldest).
class OdomHistory {
 public:
  explicit OdomHistory(std::size_t capacity);

  // Appends the odometry pose at time t. Throws std::invalid_argument unless t is finite and later
  // than the newest pose (and for a history of capacity 0).
  void push(double t, const Pose& T_OB);

  // The odometry pose at time t, interpolated between the two poses around t:
  //   s = (t - t0) / (t1 - t0),  R = R0 Exp(s Log(R0^T R1)),  p = p0 + s (p1 - p0),
  //   cov = (1 - s) cov0 + s cov1;
  // at a stored time exactly that pose. Never extrapolated: throws std::out_of_range for t before
  // the oldest pose still held or after the newest (or NaN, or an empty history).
  Pose at(double t) const;

 private:
  struct Stamped {
    double t = 0.0;
    Pose pose;
  };
  std::vector<Stamped> ring_;  // capacity entries; the oldest at head_ once full
  std::size_t head_ = 0;       // where the next push goes
  std::size_t size_ = 0;       // how many are held
};

// (d) is in the tests: the same SLAM pose against the odometry at its stamp and at its arrival.

}  // namespace ex57_8_1
