// The fixed-lag smoother on Ceres (section 57.8, tight coupling; VILENS's factor graph in a
// window): the IMU, the legs and the exteroceptive poses in one least-squares problem over the
// keyframes of the last `window` seconds.
//
// Keyframes. One every keyframe_dt (0.1 s: the 10 Hz update), at the IMU sample that reaches
// t_last + keyframe_dt, each with the blocks of fusion::Keyframe: R (on lie::ceres::SO3Manifold,
// R <- R Exp(delta)), v, p, b_g, b_a and the legs' velocity bias b_v (held at zero and constant
// when velocity_bias is off). Between consecutive keyframes: an ImuFactor (Forster
// preintegration), a LegOdometryFactor (the stance legs' body-frame base velocity, from
// leg_odometry::meanVelocity, preintegrated), and bias random-walk factors for b_g, b_a (and b_v).
// An interval with a sample without a stance foot gets no leg factor (counted).
//
// Poses and latency. A pose is applied at its stamp z.t, never at its arrival: addPose() attaches
// a PoseFactor to the keyframe nearest z.t. When z.t is not that keyframe's time (more than half
// an IMU sample away), the measurement is carried to the keyframe by the smoother's own motion
// between the two instants, from the propagated states it kept for every sample in the window
// (R_k = R_z R(t_z)^T R(t_k), p_k = p_z - (p(t_z) - p(t_k)); that motion's own error, a
// velocity error times at most keyframe_dt / 2, is not added to the pose's covariance). The
// pose enters the next window solve; one stamped more than half a keyframe interval after the
// newest keyframe waits for the keyframe nearest it. A pose stamped more than half a keyframe
// interval before the oldest keyframe in the window (or whose carrying motion has left the
// history of the last window + 2 keyframe_dt of samples) is rejected and counted
// (Stats::poses_rejected); one flagged invalid is counted (poses_invalid); one stamped after the
// newest sample throws. Time gaps in the IMU stream are not handled (no restart: a caller with a
// gap initialises again).
//
// Marginalisation. After each solve, while the window is longer than `window`, the oldest
// keyframe is marginalised (estimation/fusion/marginalization.hpp): its factors are linearised at
// the solved values and eliminated by the Schur complement into a linear prior on the keyframe
// after it. The prior keeps that linearisation point and its Jacobian for as long as it lives
// (first-estimate Jacobians): the factors inside the window are re-linearised at every
// iteration, the prior never is. The first keyframe gets a prior of the same form from
// initialise().
//
// One Levenberg-Marquardt solve per new keyframe (a few iterations, sparse normal Cholesky, one
// thread). keyframeCovariance() is the marginal covariance of the newest keyframe's (R, v, p)
// from the Gauss-Newton information of the whole window at the current values (prior included),
// mapped to BaseCovariance's convention (world-frame attitude error first).
//
// Ceres stays in the .cpp: this header is safe to include anywhere.
#pragma once

#include <Eigen/Core>
#include <memory>

#include "estimation/estimate.hpp"
#include "estimation/estimator.hpp"
#include "estimation/fusion/pose_measurement.hpp"
#include "estimation/step_input.hpp"
#include "model/imu_model.hpp"
#include "model/imu_noise.hpp"

namespace legkit::fusion {

struct SmootherOptions {
  double keyframe_dt = 0.1;   // [s] time between keyframes
  double window = 2.0;        // [s] span of the keyframes kept in the problem
  bool velocity_bias = true;  // estimate the legs' velocity bias b_v (VILENS); off: b_v = 0
  model::ImuNoise imu = model::ImuNoise::go2();
  // White noise of the stance feet's velocity relative to the body, as a density
  // [m/s/sqrt(Hz)] (one sample has sigma / sqrt(dt) per axis, shared by the feet in stance);
  // the gyro's white noise enters the leg velocity on top of it through w x r.
  double leg_velocity_sigma = 0.002;
  double bias_v_walk = 1e-3;                   // random walk of b_v [m/s/sqrt(s)]
  Eigen::Vector3d gravity = model::gravity();  // world frame [m/s^2]
  // Prior of the first keyframe (standard deviations).
  double prior_sigma_tilt = 0.02;  // roll, pitch [rad] when InitialState::sigma_tilt is NaN
  double prior_sigma_yaw = 0.01;   // [rad]
  double prior_sigma_v = 0.05;     // [m/s]
  double prior_sigma_p = 0.01;     // [m]
  double prior_sigma_bg = 0.005;   // [rad/s]
  double prior_sigma_ba = 0.05;    // [m/s^2]
  double prior_sigma_bv = 0.05;    // [m/s]
  int max_iterations = 5;          // Levenberg-Marquardt iterations per window solve
};

class FixedLagSmoother {
 public:
  struct Stats {
    int solves = 0;
    double last_solve_s = 0.0;      // wall time of the last window solve [s]
    double last_solve_cpu_s = 0.0;  // its CPU time on the solving thread [s]
    int last_iterations = 0;        // its Levenberg-Marquardt iterations
    int keyframes = 0;              // in the window now
    int marginalised = 0;           // keyframes marginalised so far
    int poses_used = 0;
    int poses_rejected = 0;         // older than the window
    int poses_invalid = 0;          // flagged invalid by their source
    int leg_intervals_skipped = 0;  // keyframe intervals without a leg factor (a flight sample)
  };

  // Throws std::invalid_argument naming the option for a non-positive keyframe_dt, a window
  // shorter than two keyframes, a non-positive noise density or prior sigma, or max_iterations < 1.
  explicit FixedLagSmoother(SmootherOptions o = {});
  ~FixedLagSmoother();
  FixedLagSmoother(FixedLagSmoother&&) noexcept;
  FixedLagSmoother& operator=(FixedLagSmoother&&) noexcept;

  // Starts over: the first keyframe at s.x (time s.x.t) with the biases of s and the prior of the
  // options (s.sigma_tilt for roll and pitch when given). Throws as checkInitialState does.
  void initialise(const InitialState& s);
  // One IMU sample with the contacts measured with it. The first sample after initialise() is not
  // integrated; afterwards the previous sample is held over dt (the kit's estimators' rule).
  // Throws std::invalid_argument before initialise(), or for input checkStepInput refuses.
  void addStep(const StepInput& in);
  // A pose, any time after it arrived; attached at z.t (see above). Throws
  // std::invalid_argument before initialise(), for a stamp after the newest sample, or for a pose
  // PoseFactor refuses (non-finite, covariance not positive definite).
  void addPose(const PoseMeasurement& z);

  // The newest keyframe propagated to the newest sample.
  EstimateSample estimate() const;
  // The marginal covariance of the newest keyframe's (R, v, p), BaseCovariance's convention.
  BaseCovariance keyframeCovariance() const;
  // The newest keyframe's state and time.
  EstimateSample keyframeEstimate() const;
  Eigen::Vector3d velocityBias() const;
  Eigen::Vector3d gyroBias() const;
  Eigen::Vector3d accelBias() const;
  const Stats& stats() const;
  const SmootherOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace legkit::fusion
