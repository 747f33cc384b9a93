// Pure IMU dead reckoning (section 57.1) behind the common Estimator interface: the baseline
// that shows why legs are needed. No bias is estimated, no contact is used: the gyro bias is 0, or
// the one initialise() gives (a still window's mean rate), held until the next reset.
#pragma once

#include "estimation/estimator.hpp"
#include "estimation/imu/nav_state.hpp"

namespace legkit::imu {

class DeadReckoningEstimator final : public Estimator {
 public:
  explicit DeadReckoningEstimator(const InputLimits& limits = {}) : limits_(limits) {
    checkLimits(limits, "DeadReckoningEstimator");
  }
  std::string name() const override { return "imu-dead-reckoning"; }
  void reset(const EstimateSample& x0) override;
  // reset(s.x), then s.b_g as the known gyro bias (s.b_a is not used: the accelerometer bias of a
  // stand cannot be told from its tilt, engineering/stationary_init.hpp).
  void initialise(const InitialState& s) override;
  // Holds the previous admitted IMU sample over dt (zero-order hold), then stores this one; bad
  // input and faults as estimation/estimator.hpp's contract says.
  void step(const StepInput& in) override;
  EstimateSample estimate() const override;

 private:
  InputLimits limits_;
  NavState x_;
  Eigen::Vector3d b_g_ = Eigen::Vector3d::Zero();  // known gyro bias [rad/s]
  double t_ = 0.0;
  model::ImuReading previous_;
  bool has_previous_ = false;
};

}  // namespace legkit::imu
