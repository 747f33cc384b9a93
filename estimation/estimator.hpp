// The one interface every estimator of the kit implements, so that the evaluation harness, the
// command line and the estimator manager run any of them on the same log.
#pragma once

#include <string>

#include "estimation/estimate.hpp"
#include "estimation/step_input.hpp"

namespace legkit {

class Estimator {
 public:
  virtual ~Estimator() = default;
  virtual std::string name() const = 0;
  // Restarts from the state x0 (its time is the time of the first sample that follows).
  virtual void reset(const EstimateSample& x0) = 0;
  // Consumes one IMU sample and the contacts measured with it.
  virtual void step(const StepInput& in) = 0;
  virtual EstimateSample estimate() const = 0;
};

}  // namespace legkit
