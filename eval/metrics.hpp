// Accuracy of an estimated trajectory against the ground truth of a log.
//
// Errors at each row k (hat = estimate):
//   position  e_p = p_hat - p,  velocity  e_v = v_hat - v                         [m], [m/s]
//   roll/pitch (tilt): the angle between the estimated and true gravity directions seen from
//             the body, atan2(|a x b|, a.b) with a = R_hat^T z, b = R^T z. Blind to yaw.
//   yaw       psi_hat - psi wrapped to (-pi, pi], psi = atan2(R_10, R_00) the heading.
// Summaries: RMSE over all rows, sqrt(mean |e|^2); drift = |e_p| at the last row as a percentage
// of the distance travelled (the sum of |p_{k+1} - p_k| of the truth).
#pragma once

#include "eval/trajectory.hpp"
#include "io/log.hpp"

namespace legkit::eval {

struct Metrics {
  double position_rmse = 0.0;         // [m]
  double velocity_rmse = 0.0;         // [m/s]
  double final_position_error = 0.0;  // [m]
  double distance = 0.0;              // distance travelled by the truth [m]
  double drift_percent = 0.0;         // final position error / distance * 100
  double tilt_rmse_deg = 0.0;         // roll/pitch [deg]
  double yaw_rmse_deg = 0.0;          // [deg]
};

// Tilt (roll/pitch) and yaw errors of R_hat against R, in radians.
double tiltError(const Eigen::Matrix3d& R_hat, const Eigen::Matrix3d& R);
double yawError(const Eigen::Matrix3d& R_hat, const Eigen::Matrix3d& R);

// Compares an estimate with the log's ground truth row by row. Throws std::invalid_argument if
// the log has no ground truth, the sizes differ, or a row's time differs from the estimate's.
Metrics compare(const io::Log& truth, const Trajectory& estimate);

}  // namespace legkit::eval
