// An exteroceptive pose (section 57.8): what a SLAM, lidar-odometry or motion-capture system
// reports about the base, at the time it describes and the (later) time it reaches the estimator.
//
// Convention (the kit's, as in estimation/estimator.hpp's BaseCovariance): the pose of the base in
// the map frame M, with its error ordered (dtheta, dp) in the map frame:
//   R_meas = Exp(dtheta) R_true,   p_meas = p_true + dp,   (dtheta, dp) ~ N(0, cov).
// A degenerate stretch (a corridor) shows as a large variance along the unobserved axis.
#pragma once

#include <Eigen/Core>

#include "lie/so3.hpp"

namespace legkit::fusion {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct PoseMeasurement {
  double t = 0.0;                                  // the instant the pose describes (its stamp) [s]
  double t_arrival = 0.0;                          // when it reaches the estimator, t + latency [s]
  lie::SO3d R_MB;                                  // base attitude in the map frame
  Eigen::Vector3d p_MB = Eigen::Vector3d::Zero();  // base position in the map frame [m]
  Matrix6d cov = Matrix6d::Identity();             // of (dtheta, dp), map frame [rad^2, m^2]
  bool valid =
      true;  // false: the source says this pose is not to be used (it is counted, not used)
};

}  // namespace legkit::fusion
