// Accuracy of an estimated trajectory against the ground truth of a log.
//
// Errors at each row k (hat = estimate):
//   position  e_p = p_hat - p,  velocity  e_v = v_hat - v                         [m], [m/s]
//   roll/pitch (tilt): the angle between the estimated and true gravity directions seen from
//             the body, atan2(|a x b|, a.b) with a = R_hat^T z, b = R^T z. Blind to yaw.
//   yaw       psi_hat - psi wrapped to (-pi, pi], psi = atan2(R_10, R_00) the heading.
// Summaries: RMSE over all rows, sqrt(mean |e|^2); drift = |e_p| at the last row as a percentage
// of the distance travelled (the sum of |p_{k+1} - p_k| of the truth).
// Trajectory benchmarks as the odometry literature reports them (Sturm et al. 2012, Zhang and
// Scaramuzza 2018), with poses T = (R, p):
//   ATE  absolute trajectory error: the estimate is first moved by the rigid transform that puts
//        its first pose on the true first pose, T_a = T_0 T_hat_0^-1; then the RMSE of
//        |p_k - p_a,k| over all rows.
//   RPE  relative pose error over a distance d: for every row i, j is the first row at which the
//        truth has travelled d further; E = (T_i^-1 T_j)^-1 (T_hat_i^-1 T_hat_j) compares the
//        two relative motions; the RMSE of its translation |t_E| (also as % of d) and of its
//        rotation angle.
#pragma once

#include <vector>

#include "eval/trajectory.hpp"
#include "io/log.hpp"

namespace legkit::eval {

struct RelativeError {
  double distance = 0.0;             // d [m]
  int pairs = 0;                     // number of (i, j) pairs; 0 if the run is shorter than d
  double translation_rmse = 0.0;     // [m]
  double translation_percent = 0.0;  // translation_rmse / d * 100
  double rotation_rmse_deg = 0.0;    // [deg]
};

struct Metrics {
  double position_rmse = 0.0;         // [m]
  double velocity_rmse = 0.0;         // [m/s]
  double final_position_error = 0.0;  // [m]
  double distance = 0.0;              // distance travelled by the truth [m]
  double drift_percent = 0.0;         // final position error / distance * 100
  double tilt_rmse_deg = 0.0;         // roll/pitch [deg]
  double yaw_rmse_deg = 0.0;          // [deg]
  double ate_rmse = 0.0;              // [m]
  std::vector<RelativeError> rpe;     // one per requested distance
};

// Tilt (roll/pitch) and yaw errors of R_hat against R, in radians.
double tiltError(const Eigen::Matrix3d& R_hat, const Eigen::Matrix3d& R);
double yawError(const Eigen::Matrix3d& R_hat, const Eigen::Matrix3d& R);

// Compares an estimate with the log's ground truth row by row. Throws std::invalid_argument if
// the log has no ground truth, the sizes differ, or a row's time differs from the estimate's.
// RPE is computed over each of rpe_distances [m].
Metrics compare(const io::Log& truth, const Trajectory& estimate,
                const std::vector<double>& rpe_distances = {1.0, 5.0});

}  // namespace legkit::eval
