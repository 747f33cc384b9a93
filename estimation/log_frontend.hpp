// Turns the rows of a log into estimator inputs (StepInput): the only place where a log's leg
// description meets a robot model.
//  - quadruped joints: a foot in contact becomes p_body = FK(q), v_body = J(q) dq, with
//    covariance J Cov(q) J^T + sigma_foot^2 I (encoder noise mapped through the leg, plus the
//    contact-point uncertainty of a round foot);
//  - robot-agnostic foot columns: p_body and its covariance are taken as the log gives them.
// Which feet are in stance comes from the log's contact columns. A log without them yields no
// contacts (contact detection, section 57.6, will fill that gap).
#pragma once

#include <vector>

#include "estimation/step_input.hpp"
#include "io/log.hpp"
#include "model/quadruped.hpp"

namespace legkit {

struct FrontendNoise {
  double encoder_angle_sigma = 1.75e-4;  // [rad] per joint (about 0.01 deg)
  double foot_point_sigma = 0.005;       // contact point on a round foot [m]
};

class LogFrontend {
 public:
  LogFrontend(const io::LogLayout& layout, const model::QuadrupedKinematics& kinematics,
              const FrontendNoise& noise = {});

  // The input of row k of a log (dt measured from row k-1, 0 for k = 0).
  StepInput input(const io::LogRow& row, double dt) const;
  // Every row of `log` as an input, dt measured between rows (for tests and benchmarks that
  // replay a log with the conversion kept out of what they measure).
  std::vector<StepInput> inputs(const io::Log& log) const;

 private:
  io::LogLayout layout_;
  model::QuadrupedKinematics kinematics_;
  FrontendNoise noise_;
};

}  // namespace legkit
