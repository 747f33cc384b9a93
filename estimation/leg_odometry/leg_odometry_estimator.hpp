// Leg odometry as a stand-alone estimator (section 57.3), the simplest use of the legs:
//   attitude  gyro integration, R_{k+1} = R_k Exp((w_m - b_g) dt)  (no correction: drifts)
//   velocity  in stance, the mean of the stance feet's v_i = -R (w_b x r_i + r_dot_i);
//             in flight (no foot down), the IMU step v += (R a_m + g) dt
//   position  p += (v_k + v_{k+1}) dt / 2
// b_g is 0, or the known bias initialise() gives (a still window's mean rate) until the next
// reset. It has no covariance and no bias estimate: the filters of sections 57.4-57.5 fuse the same
// measurements properly. Here it measures how good the legs' velocity is on its own.
#pragma once

#include "estimation/estimator.hpp"
#include "lie/so3.hpp"

namespace legkit::leg_odometry {

class LegOdometryEstimator final : public Estimator {
 public:
  explicit LegOdometryEstimator(const InputLimits& limits = {}) : limits_(limits) {
    checkLimits(limits, "LegOdometryEstimator");
  }
  std::string name() const override { return "leg-odometry"; }
  void reset(const EstimateSample& x0) override;
  // reset(s.x), then s.b_g as the known gyro bias (s.b_a is not used).
  void initialise(const InitialState& s) override;
  // Bad input and faults as estimation/estimator.hpp's contract says; a sample whose IMU reading
  // was not admitted takes its rate from the held one. A stance foot without v_body after the
  // first sample throws std::invalid_argument naming it and the time: leg odometry never runs
  // silently on the IMU alone (a run reports it as its failure, eval/runner.hpp). At a first
  // sample such feet leave the velocity at x0's.
  void step(const StepInput& in) override;
  EstimateSample estimate() const override;

 private:
  InputLimits limits_;
  lie::SO3d R_;
  Eigen::Vector3d b_g_ = Eigen::Vector3d::Zero();  // known gyro bias [rad/s]
  Eigen::Vector3d v_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d p_ = Eigen::Vector3d::Zero();
  double t_ = 0.0;
  model::ImuReading previous_;
  bool has_previous_ = false;
};

}  // namespace legkit::leg_odometry
