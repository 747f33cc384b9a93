// The map-to-odom alignment (section 57.8, loose coupling): the proprioceptive filter runs
// undisturbed in its odom frame O; the exteroceptive poses (map frame M) estimate the slowly
// varying transform T_MO with a low-gain Kalman filter on SE(3). The controller keeps using the
// smooth odometry T_OB; a global goal uses mapPose(T_OB) = T_MO T_OB. A loop closure (a jump of
// the map) moves T_MO, never the odometry: this class only reads odometry poses.
//
// State and convention: T_MO = (R_MO, p_MO) with p_M = R_MO p_O + p_MO, and its covariance P of
// (dtheta, dp) in the map frame (the kit's, pose_measurement.hpp): R_MO = Exp(dtheta) R_MO_hat,
// p_MO = p_MO_hat + dp.
//
// Predict (random walk): P <- P + diag(s_r^2 I, s_p^2 I) dt, s_r = sigma_rotation_walk,
// s_p = sigma_position_walk; the estimate does not move. The walk has to cover both the map's
// drift and the odometry's (0.1-1.2 % of the distance travelled on the kit's trot).
//
// Update from one pose z (stamp t) and the odometry pose T_OB at the SAME stamp t:
//   Z = T_MB T_OB^-1:  Z_R = R_MB R_OB^T,  Z_p = p_MB - Z_R p_OB       (the measurement of T_MO)
//   innovation r = (Log(Z_R R_MO_hat^T), Z_p - p_MO_hat),  H = I_6.
// Measurement covariance. Write the pose's error (a, b) (cov C_z, map frame) and the odometry's
// (alpha, beta) (cov C_o, odom frame), both in the kit's convention, about the true poses. With
// R Exp(v) R^T = Exp(R v) (the adjoint of SO(3) is R), to first order
//   Z_R = Exp(a) R_MB R_OB^T Exp(-alpha) = Exp(a) Exp(-R_MO alpha) R_MO = Exp(a - R_MO alpha) R_MO.
// With phi = a - R_MO alpha and q = R_MO p_OB = p_MB - Z_p,
//   Z_p = p_MB + b - Exp(phi) R_MO (p_OB + beta) = p_MO + b - R_MO beta + [q]x phi,
// so the error of Z is
//   dtheta_Z = a - R_MO alpha,   dp_Z = b - R_MO beta + [q]x (a - R_MO alpha),
//   R_meas = J_z C_z J_z^T + J_o C_o J_o^T,
//   J_z = [[I, 0], [[q]x, I]],   J_o = -[[R_MO, 0], [[q]x R_MO, R_MO]]   (Z's R_MO and q).
// (J_o = -J_z diag(R_MO, R_MO), so R_meas = J_z (C_z + B C_o B^T) J_z^T, B = diag(R_MO, R_MO).)
// The lever arm q turns an attitude error of either pose into a position error of T_MO that
// grows with the distance from the odom origin. By default (include_odom_covariance = false)
// J_o C_o J_o^T is left out: the odometry's absolute covariance is mostly its drift, correlated
// from one pose to the next, which is what the random walk of T_MO already models; counting it as
// independent noise at every pose lowers the gain as the odometry's covariance grows (on the
// 330 s study it slowed the re-lock after the loop closure from seconds to about 30 s).
// Then S = P + R_meas, d^2 = r^T S^-1 r, K = P S^-1, T_MO <- (Exp(K_theta r) R_MO, p_MO + K_p r),
// P <- (I - K) P (I - K)^T + K R_meas K^T (Joseph form).
//
// Time constant. Per axis, with s_z the measurement's standard deviation and f the pose rate, the
// steady-state gain is k ~ s_w / (s_z sqrt f) (s_w the walk density), so an error decays as
// exp(-t / tau) with tau = s_z / (s_w sqrt f): 0.02 m, 0.005 m/sqrt(s), 10 Hz give tau = 1.3 s.
//
// Gating: d^2 against the chi-square quantile of 6 dof at the n-sigma probability
// (engineering/gating.hpp). A map jump (loop closure) fails the gate at every pose; once poses
// have failed without a break for jump_confirm_time, the filter takes them ungated (counted as
// jump_updates) until one passes the gate again: the jump is absorbed at the filter's own gain,
// over about tau, not in one step (the map pose the controller's planner sees stays smooth).
//
// Rejections, each counted (Counts) and never touching the state except where said: invalid flag,
// non-finite numbers, a covariance that is not positive definite, a stamp not after the previous
// pose's (out of order), a stamp older than the odometry history or after its newest sample, gated.
// The first pose that passes the checks initialises T_MO = Z, P = R_meas. update() does not
// allocate.
#pragma once

#include <limits>

#include "estimation/fusion/odom_history.hpp"
#include "estimation/fusion/pose_measurement.hpp"

namespace legkit::fusion {

struct MapOdomOptions {
  double sigma_rotation_walk = 0.0005;   // s_r: random-walk density of T_MO's angle [rad/sqrt(s)]
  double sigma_position_walk = 0.005;    // s_p: random-walk density of T_MO's position [m/sqrt(s)]
  bool gating = true;                    // chi-square gate on the 6-dof innovation
  double n_sigma = 3.0;                  // the gate's probability erf(n / sqrt 2) (3: 0.9973)
  double jump_confirm_time = 0.5;        // [s] failing the gate this long without a break: a jump
  bool include_odom_covariance = false;  // map the odometry's covariance into R_meas (see above)
};

// Throws std::invalid_argument naming the field (negative or non-finite sigmas, n_sigma <= 0,
// jump_confirm_time < 0).
void checkMapOdomOptions(const MapOdomOptions& options);

// The base in the map frame.
struct MapPose {
  lie::SO3d R_MB;
  Eigen::Vector3d p_MB = Eigen::Vector3d::Zero();
};

class MapOdomAlignment {
 public:
  enum class Outcome {
    kInitialised,    // the first usable pose: T_MO = Z
    kUsed,           // passed the gate, applied
    kJumpUpdate,     // failed the gate after a confirmed jump, applied ungated
    kGated,          // failed the gate
    kInvalid,        // the pose's valid flag is 0
    kNonFinite,      // NaN or inf in the pose, its covariance or the odometry pose
    kBadCovariance,  // the pose's covariance is not positive definite
    kOutOfOrder,     // stamp not after the previous pose's
    kTooOld,         // stamp older than the odometry history
    kInFuture,       // stamp after the odometry's newest sample (or the history is empty)
  };
  struct Counts {
    int initialised = 0, used = 0, jump_updates = 0, gated = 0, invalid = 0, non_finite = 0,
        bad_covariance = 0, out_of_order = 0, too_old = 0, in_future = 0;
    int rejected() const {
      return gated + invalid + non_finite + bad_covariance + out_of_order + too_old + in_future;
    }
  };

  explicit MapOdomAlignment(const MapOdomOptions& options = {});

  // The pose z with the odometry pose looked up at z.t in the history.
  Outcome update(const PoseMeasurement& z, const OdomHistory& odometry);
  // The pose z with the odometry pose at its stamp (odom_at_stamp.t must equal z.t: throws
  // std::invalid_argument otherwise, the classic mistake of pairing a pose with the newest
  // odometry).
  Outcome update(const PoseMeasurement& z, const OdomPose& odom_at_stamp);

  // T_MO T_OB: the base in the map frame (T_MO = identity until initialised).
  MapPose mapPose(const lie::SO3d& R_OB, const Eigen::Vector3d& p_OB) const;

  bool initialised() const { return initialised_; }
  const lie::SO3d& R_MO() const { return R_MO_; }
  const Eigen::Vector3d& p_MO() const { return p_MO_; }
  const Matrix6d& cov() const { return P_; }  // of (dtheta, dp), map frame
  double time() const { return t_; }          // stamp of the last pose that advanced the filter
  double gateThreshold() const { return threshold_; }
  double lastMahalanobis() const { return last_d2_; }  // d^2 of the last pose that reached the gate
  const Counts& counts() const { return counts_; }

  // The measurement Z = T_MB T_OB^-1 and its covariance R_meas (the derivation above).
  struct Observation {
    lie::SO3d R_MO;
    Eigen::Vector3d p_MO = Eigen::Vector3d::Zero();
    Matrix6d cov = Matrix6d::Zero();
  };
  static Observation observe(const PoseMeasurement& z, const OdomPose& odom,
                             bool include_odom_covariance);

 private:
  Outcome count(Outcome outcome);

  MapOdomOptions options_;
  double threshold_;
  bool initialised_ = false;
  lie::SO3d R_MO_;
  Eigen::Vector3d p_MO_ = Eigen::Vector3d::Zero();
  Matrix6d P_ = Matrix6d::Zero();
  double t_ = -std::numeric_limits<double>::infinity();
  double gated_since_ = std::numeric_limits<double>::quiet_NaN();  // NaN: the last pose passed
  double last_d2_ = std::numeric_limits<double>::quiet_NaN();
  Counts counts_;
};

const char* toString(MapOdomAlignment::Outcome outcome);

}  // namespace legkit::fusion
