// Pure IMU dead reckoning (section 57.1) behind the common Estimator interface: the baseline
// that shows why legs are needed. No bias is estimated (b_hat = 0), no contact is used.
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
  // Holds the previous admitted IMU sample over dt (zero-order hold), then stores this one; bad
  // input and faults as estimation/estimator.hpp's contract says.
  void step(const StepInput& in) override;
  EstimateSample estimate() const override;

 private:
  InputLimits limits_;
  NavState x_;
  double t_ = 0.0;
  model::ImuReading previous_;
  bool has_previous_ = false;
};

}  // namespace legkit::imu
