// The one interface every estimator of the kit implements, so that the evaluation harness, the
// command line and the estimator manager run any of them on the same log.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "estimation/estimate.hpp"
#include "estimation/step_input.hpp"

namespace legkit {

// The uncertainty an estimator claims for its base state, in one convention shared by every
// filter so that NEES and 3-sigma bounds mean the same thing for all of them:
//   e = (dtheta, dv, dp),  R = Exp(dtheta) R_hat,  v = v_hat + dv,  p = p_hat + dp
// (attitude error in the world frame, then world velocity and position errors). A filter whose
// own error is defined differently (the InEKF's right-invariant xi, the ESKF's body-frame angle)
// maps its covariance into this one to first order.
struct BaseCovariance {
  Eigen::Matrix<double, 9, 9> P = Eigen::Matrix<double, 9, 9>::Identity();
  // False when attitude is an input, not a state (the linear KF): then only the (dv, dp) block,
  // rows and columns 3..8, is meaningful and NEES has 6 degrees of freedom instead of 9.
  bool has_attitude = true;
};

class Estimator {
 public:
  virtual ~Estimator() = default;
  virtual std::string name() const = 0;
  // Restarts from the state x0 (its time is the time of the first sample that follows).
  virtual void reset(const EstimateSample& x0) = 0;
  // Consumes one IMU sample and the contacts measured with it.
  virtual void step(const StepInput& in) = 0;
  virtual EstimateSample estimate() const = 0;
  // The covariance of estimate(), for filters; none for estimators that do not keep one.
  virtual std::optional<BaseCovariance> covariance() const { return std::nullopt; }
};

}  // namespace legkit
