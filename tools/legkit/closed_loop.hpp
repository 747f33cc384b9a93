// Closing the loop through an estimator: the physics simulator's controller asks a
// sim::BaseStateSource for the base state it acts on; this one feeds each log row, as it is
// written, to one of the kit's estimators (through the same front end as `legkit run`) and hands
// back that estimator's R, p and v instead of the truth. Exercise 57.X: what does a wrong
// estimate do to the robot?
//   legkit sim --scenario physics-trot --closed-loop "Invariant EKF"
#pragma once

#include <memory>
#include <string>

#include "estimation/estimator.hpp"
#include "estimation/log_frontend.hpp"
#include "sim/base_state_source.hpp"

namespace legkit::tools {

class EstimatorBaseState : public sim::BaseStateSource {
 public:
  // name: one of estimatorNames() (throws std::invalid_argument otherwise); layout: the layout of
  // the log the simulator writes (the front end reads joints and contact flags by it); noise: the
  // front end's, matched to the simulated encoders.
  EstimatorBaseState(const std::string& name, const io::LogLayout& layout,
                     const FrontendNoise& noise);

  // Steps the estimator with this row and returns its estimate. The first row resets it to the
  // row's ground truth when the log carries one (as `legkit run` starts every estimator), else to
  // rest at the origin, tilted as the accelerometer says.
  bool update(const io::LogRow& row, sim::BaseEstimate& out) override;

  const Estimator& estimator() const { return *estimator_; }

 private:
  std::unique_ptr<Estimator> estimator_;
  io::LogLayout layout_;
  LogFrontend frontend_;
  bool started_ = false;
  double t_previous_ = 0.0;
};

// The front-end layout of a physics log: joints, torques, foot forces, the (true) contact flags,
// and ground truth when the simulator writes it.
io::LogLayout physicsLogLayout(bool ground_truth);

}  // namespace legkit::tools
