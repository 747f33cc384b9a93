// Slip detection (section 57.7): is a stance foot sliding on the ground?
//
// Per-foot velocity residual. A stance foot that does not slip gives the base velocity
//   v_leg,i = -R (w_b x p_i + v_body,i)      (57.3, estimation/leg_odometry/base_velocity.hpp)
// and the filter predicts v_hat. The residual r_i = v_leg,i - v_hat is compared with its own
// covariance. With the kit's error convention e = (dtheta, dv, dp), R = Exp(dtheta) R_hat,
// v = v_hat + dv (estimation/estimator.hpp):
//   v_leg(R) = -Exp(dtheta) R_hat u = v_leg(R_hat) + [R_hat u]_x dtheta,   u = w_b x p_i + v_body,i
// so, with v_leg,i(R) - v = -n_i (the kinematic noise of a foot that does not slip),
//   r_i = [v_leg,i]_x dtheta + dv - n_i,   H_i = [ [v_leg,i]_x   I   0 ]
//   S_i = H_i P H_i^T + R_i,   d2_i = r_i^T S_i^-1 r_i  ~  chi2_3 when the foot holds,
// P the filter's BaseCovariance and R_i from leg_odometry::baseVelocityCovariance. A filter
// without attitude state (BaseCovariance::has_attitude false) has H_i = [0 I 0]: only P's v block
// enters. v_hat is the estimate of x.t carried to the input's time by the IMU (+ (R a_m + g) dt).
// The foot exceeds the test when d2_i > chi2_3(alpha) (11.345 at alpha = 0.99, exercise 57.7.1)
// and is slipping once it has exceeded it at confirm_samples consecutive checks: at 1 kHz a test
// of level 0.99 alone flags 1 % of the samples of a foot that holds (about 10 false onsets per
// second and foot); three in a row bring the dry physics trot to 10 false alarms per minute for
// 2 ms of delay (tests/slip/slip_physics_test.cpp).
//
// Multi-foot consistency. Two feet that both hold agree: eps_ij = v_leg,i - v_leg,j with
// covariance R_i + R_j (the filter's state cancels). With three or more stance feet, a foot that
// disagrees with every other foot while all the others agree among themselves and with the filter
// (none exceeds its own test) is the outlier (SlipReport::outlier): evidence against it, as an
// exceeded test is. Without the second condition two feet sliding together would outvote the one
// that holds. With two feet (a trot's
// stance pair) a disagreement cannot say which foot moved: only the per-foot residuals decide.
//
// All feet slipping (57.7.2). If every foot slides together (a robot pushed on ice) the feet agree
// with each other, and a filter that trusts them follows them: v_hat moves with v_leg and the
// per-foot residuals stay small. What still disagrees is the IMU: from the last trusted estimate
// (v_a, P_vv at t_a, taken when no foot exceeded its test), the accelerometer alone gives
//   v_imu(t) = v_a + sum (R a_m + g) dt,
//   Cov = P_vv + (sigma_a^2 T + sigma_ba^2 T^2) I + T^2 [g]_x P_thth [g]_x^T,   T = t - t_a,
// and the legs' common velocity v_c (the mean v_leg,i of the feet that pass their own test, all of
// them if none does; covariance Cov_c the mean R_i, as the feet's errors of one instant are
// correlated) is tested the same way: d2_c = (v_c - v_imu)^T (Cov + Cov_c)^-1 (v_c - v_imu) above
// chi2_3(alpha) at confirm_samples consecutive checks (SlipReport::imu_disagrees) means every foot
// moves with the ground (SlipReport::all_slipping). The anchor is renewed every anchor_window
// (0.25 s) while nothing exceeds; while something does it is kept up to max_anchor_age (1 s).
// On physics-ice-push every foot slides from 3.093 s and the test fires at 3.116 s; it never fires
// on the dry physics trot (tests/slip/slip_physics_test.cpp).
// Its limit, in numbers (defaults, P_vv = 0.01^2 I): the test needs |v_c - v_imu| above about
// sqrt(11.345 (0.05^2 + 0.01^2 + 0.04^2 T + 0.05^2 T^2)) = 0.19 m/s per axis at T = 0.25 s, so a
// common slide that gains less than that within one anchor window (slower than about 0.75 m/s^2
// relative to the legs) stays hidden: the filter follows the legs and the next anchor inherits
// the drift (test "a common slide slower than the IMU window can show is not seen").
//
// Fixed-size, no allocation; check() is the hot path (closed-form 3x3 solves: one per foot, one
// per pair, one for the common test): 123 ns per foot on four feet (bench/bench_slip.cpp).
#pragma once

#include <Eigen/Core>
#include <array>

#include "estimation/estimate.hpp"
#include "estimation/estimator.hpp"
#include "estimation/leg_odometry/base_velocity.hpp"
#include "estimation/leg_odometry/contact_span.hpp"
#include "estimation/step_input.hpp"

namespace legkit::slip {

constexpr int kMaxFeet = leg_odometry::kMaxContacts;

// The alpha-quantile of the chi-square distribution with 3 degrees of freedom, alpha in (0, 1):
// the root of F(x) = erf(sqrt(x/2)) - sqrt(2x/pi) exp(-x/2) = alpha (chi2_3(0.99) = 11.345).
// Throws std::invalid_argument outside (0, 1).
double chi2Quantile3(double alpha);

struct SlipParams {
  double alpha = 0.99;  // chi-square test level of every test below (exercise 57.7.1)
  // Noise of v_leg,i (baseVelocityCovariance): the foot velocity relative to the body, per axis
  // [m/s] (encoder rates, the rolling of a round foot, contact compliance), and the gyro's. 0.05
  // is the dry physics trot's: from 60 ms after touchdown on, the ESKF's residual |r_i| has median
  // 0.06 m/s (a 3D residual of 0.05 per axis has median 0.077) and 95th percentile 0.12 m/s.
  double foot_velocity_sigma = 0.05;
  double gyro_sigma = 0.01;  // [rad/s]
  // Used when the caller has no covariance (an estimator without one): P_vv = sigma^2 I.
  double fallback_velocity_sigma = 0.05;  // [m/s]
  double max_propagation = 0.02;  // v_hat is moved to the input's time over at most this [s]
  // The IMU-only window of the all-feet test.
  double accel_sigma = 0.04;       // accelerometer white noise density [m/s^2/sqrt(Hz)]
  double accel_bias_sigma = 0.05;  // uncertainty of the accelerometer bias [m/s^2]
  double anchor_window = 0.25;     // the trusted anchor is renewed this often [s]
  double max_anchor_age = 1.0;     // the longest IMU-only window [s]
  double inflate = 100.0;          // alpha_inflate of SlipReaction::kInflate (R_i <- R_i alpha)
  // Consecutive checks a foot must exceed the test (or be the outlier) before it is slipping.
  int confirm_samples = 3;
};

struct FootSlip {
  int foot = -1;                                       // foot id
  Eigen::Vector3d v_leg = Eigen::Vector3d::Zero();     // v_leg,i, world [m/s]
  Eigen::Vector3d residual = Eigen::Vector3d::Zero();  // r_i = v_leg,i - v_hat [m/s]
  Eigen::Matrix3d R = Eigen::Matrix3d::Zero();         // R_i = Cov(v_leg,i) [m^2/s^2]
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();         // H_i P H_i^T + R_i [m^2/s^2]
  double d2 = 0.0;                                     // r_i^T S_i^-1 r_i
  bool exceeds = false;   // this check: d2 > chi2_3(alpha), or the multi-foot outlier
  bool slipping = false;  // exceeded at confirm_samples consecutive checks
};

struct SlipReport {
  double t = 0.0;
  int num_feet = 0;  // stance feet with a velocity (v_body) checked; feet[0..num_feet)
  std::array<FootSlip, kMaxFeet> feet{};
  bool all_slipping = false;   // every checked foot slipping, or the IMU-vs-legs test fired
  int outlier = -1;            // foot id of the multi-foot outlier, -1 if none
  int inconsistent_pairs = 0;  // pairs (i, j) with eps_ij beyond chi2_3(alpha)
  double common_d2 = 0.0;      // d2_c of the all-feet test (0 when it could not run)
  bool imu_disagrees = false;  // d2_c > chi2_3(alpha): the legs' common velocity against the IMU
  double threshold = 0.0;      // chi2_3(alpha)

  // Whether foot id `foot` was checked and found slipping.
  bool slipping(int foot) const;
  int numSlipping() const;
};

class SlipDetector {
 public:
  // Throws std::invalid_argument for alpha outside (0, 1), a negative or non-finite sigma (zero
  // foot_velocity_sigma), a non-positive anchor_window or max_anchor_age < anchor_window,
  // confirm_samples < 1 or inflate < 1.
  explicit SlipDetector(const SlipParams& params = {});

  // Forgets the IMU-only anchor and the feet's consecutive counts.
  void reset();
  // The stance feet of `in` that carry v_body, against the estimate x (the filter's estimate of
  // the previous step) and its covariance P. Feet without v_body are not checked.
  SlipReport check(const StepInput& in, const EstimateSample& x, const BaseCovariance& P);
  // The same for an estimator without a covariance (P_vv from fallback_velocity_sigma).
  SlipReport check(const StepInput& in, const EstimateSample& x);

  const SlipParams& params() const { return params_; }
  double threshold() const { return threshold_; }

 private:
  // The all-feet test (IMU against the legs) and its anchor; R is x's attitude.
  void checkCommon(const StepInput& in, const EstimateSample& x, const Eigen::Matrix3d& R,
                   const BaseCovariance& P, SlipReport& report);

  SlipParams params_;
  double threshold_;
  leg_odometry::FootVelocityNoise noise_;
  std::array<int, kMaxFeet> exceeded_{};  // consecutive checks exceeded, by foot id
  int common_exceeded_ = 0;               // the same for the all-feet test
  // The all-feet test's anchor: the last trusted velocity and what the IMU added since.
  bool anchored_ = false;
  double anchor_t_ = 0.0;
  Eigen::Vector3d v_imu_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d anchor_cov_ = Eigen::Matrix3d::Zero();  // P_vv at the anchor
  Eigen::Matrix3d anchor_att_ = Eigen::Matrix3d::Zero();  // P_thth at the anchor (world)
  double last_t_ = 0.0;
};

}  // namespace legkit::slip
