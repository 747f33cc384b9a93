// Accuracy of an estimated trajectory against the ground truth of a log.
//
// Errors at each row k (hat = estimate):
//   position  e_p = p_hat - p,  velocity  e_v = v_hat - v                         [m], [m/s]
//   roll/pitch (tilt): the angle between the estimated and true gravity directions seen from
//             the body, atan2(|a x b|, a.b) with a = R_hat^T z, b = R^T z. Blind to yaw.
//   yaw       psi_hat - psi wrapped to (-pi, pi], psi = atan2(R_10, R_00) the heading.
// Summaries: RMSE over the rows with a valid truth (all of them unless the log flags some),
// sqrt(mean |e|^2); drift = |e_p| at the last such row as a percentage
// of the distance travelled by the truth (below: not inflated by jitter).
// Trajectory benchmarks as the odometry literature reports them (Sturm et al. 2012, Zhang and
// Scaramuzza 2018), with poses T = (R, p):
//   ATE  absolute trajectory error: the RMSE over the rows of |p_k - (R_a p_hat_k + t_a)|, the
//        estimate moved by a transform (R_a, t_a) found one of three ways:
//        first pose  T_a = T_0 T_hat_0^-1 puts the first estimated pose on the true one
//                    (ate_rmse);
//        SE(3)       the rigid transform that minimises sum_k |p_k - (R p_hat_k + t)|^2 (Umeyama
//                    1991 without scale, as evo_ape -a): with c and c_hat the centroids and
//                    U D V^T the SVD of sum_k (p_k - c)(p_hat_k - c_hat)^T, R = U S V^T with
//                    S = diag(1, 1, det(U V^T)), t = c - R c_hat (ate_se3_rmse);
//        4-DoF       the same fit with R a rotation about world z: yaw and position are what an
//                    IMU-based estimator cannot observe (the VIO convention, "posyaw" in Zhang
//                    and Scaramuzza 2018): on coordinates centred on c and c_hat,
//                    psi = atan2(sum_k x_hat y - y_hat x, sum_k x_hat x + y_hat y),
//                    R = R_z(psi), t = c - R c_hat (ate_4dof_rmse).
//        The two least-squares fits use every valid row and need 3 of them.
//   RPE  relative pose error over a distance d: for every row i, j is the first row at which the
//        truth has travelled d further; E = (T_i^-1 T_j)^-1 (T_hat_i^-1 T_hat_j) compares the
//        two relative motions; the RMSE of its translation |t_E| (also as % of d) and of its
//        rotation angle.
// A real robot's truth (motion capture) differs from a simulated one in three ways, each handled:
//  - rows flagged gt_valid = 0 (a dropout) are masked out of every metric: RMSEs, ATE (aligned on
//    the first valid row, or fitted to the valid rows), RPE (both rows of a pair valid), drift
//    (the last valid row); their number is reported. With no valid row at all every metric is
//    NaN.
//  - a truth with the pose only (gt_velocity = false): the velocity is the pose differentiated,
//    v_k = (p_b - p_a) / (t_b - t_a) with a, b the valid rows farthest from k within a window of
//    w seconds centred on k (a central difference; one-sided near the ends and at dropouts), and
//    Metrics says so (velocity_differentiated, velocity_method).
//  - jitter: the distance travelled sums |p_k - p_anchor| only once it reaches d_min, and then
//    moves the anchor to p_k (the truth resampled every d_min along its path), so that a still
//    truth jittering by millimetres travels 0 m, not metres; a path is undercounted by less than
//    d_min. RPE's distances are measured the same way.
// Whatever cannot be computed is "not computed", never 0: an RPE without a single pair
// (computed = false, its errors NaN), the drift of a truth that never moved d_min (NaN), a
// fitted ATE on fewer than 3 valid rows (NaN); summary.json writes a NaN as null.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "eval/trajectory.hpp"
#include "io/log.hpp"

namespace legkit::eval {

constexpr double kNotComputed = std::numeric_limits<double>::quiet_NaN();

struct RelativeError {
  double distance = 0.0;  // d [m]
  int pairs = 0;          // number of (i, j) pairs; 0 if the (valid) run is shorter than d
  bool computed = false;  // pairs > 0; if not, the three errors are NaN ("n/c")
  double translation_rmse = kNotComputed;     // [m]
  double translation_percent = kNotComputed;  // translation_rmse / d * 100
  double rotation_rmse_deg = kNotComputed;    // [deg]
};

// The default w of the central difference that gives a pose-only truth its velocity [s]
// (`legkit run`: the settings' frontend.truth_velocity_window).
constexpr double kTruthVelocityWindow = 0.05;

// How compare treats the truth (the file comment above says why).
struct TruthOptions {
  double velocity_window = kTruthVelocityWindow;  // w for a pose-only truth [s]
  double distance_step = 0.01;                    // d_min of the distance travelled [m]
};

struct Metrics {
  double position_rmse = 0.0;         // [m]
  double velocity_rmse = 0.0;         // [m/s]
  double final_position_error = 0.0;  // [m]
  double distance = 0.0;              // distance travelled by the truth, steps >= d_min [m]
  double drift_percent = 0.0;         // final position error / distance * 100 (NaN: distance 0)
  double tilt_rmse_deg = 0.0;         // roll/pitch [deg]
  double yaw_rmse_deg = 0.0;          // [deg]
  double ate_rmse = 0.0;              // aligned on the first pose [m]
  double ate_se3_rmse = 0.0;          // after the least-squares SE(3) alignment [m]
  double ate_4dof_rmse = 0.0;         // after the least-squares yaw and position alignment [m]
  std::vector<RelativeError> rpe;     // one per requested distance
  int scored_rows = 0;                // rows with a valid truth
  int masked_rows = 0;                // rows with gt_valid = 0, left out of every metric
  int velocity_rows = 0;  // rows whose truth has a velocity (all valid ones, unless differentiated)
  bool velocity_differentiated = false;  // the truth's velocity is its pose differentiated
  std::string velocity_method;           // where the truth's velocity came from, in words
};

// The truth's world velocity at each row: the log's gt_v, or (gt_velocity = false) the pose's
// central difference over `window` seconds on valid rows. available[k] is false on masked rows
// and on valid rows without another valid row in their window.
struct TruthVelocity {
  std::vector<Eigen::Vector3d> v;  // [m/s], zero where not available
  std::vector<bool> available;
  bool differentiated = false;
  std::string method;  // in words, as Metrics::velocity_method
};
TruthVelocity truthVelocity(const io::Log& truth, double window = kTruthVelocityWindow);

// Tilt (roll/pitch) and yaw errors of R_hat against R, in radians.
double tiltError(const Eigen::Matrix3d& R_hat, const Eigen::Matrix3d& R);
double yawError(const Eigen::Matrix3d& R_hat, const Eigen::Matrix3d& R);

// Compares an estimate with the log's ground truth row by row. Throws std::invalid_argument if
// the log has no ground truth, the sizes differ, or a row's time differs from the estimate's.
// RPE is computed over each of rpe_distances [m].
Metrics compare(const io::Log& truth, const Trajectory& estimate,
                const std::vector<double>& rpe_distances = {1.0, 5.0},
                const TruthOptions& options = {});

}  // namespace legkit::eval
