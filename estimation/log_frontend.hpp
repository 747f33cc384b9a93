// Turns the rows of a log into estimator inputs (StepInput): the only place where a log's leg
// description meets a robot model.
//  - quadruped joints: a foot in contact becomes p_body = FK(q), v_body = J(q) dq, with
//    covariance J Cov(q) J^T + sigma_foot^2 I (encoder noise mapped through the leg, plus the
//    contact-point uncertainty of a round foot);
//  - robot-agnostic foot columns: p_body and its covariance are taken as the log gives them.
// Which feet are in stance comes either from the log's contact columns (input(row, dt); a log
// without them yields no contacts), or from a contact detector (section 57.6): signals() gives
// the detector what the robot measured, and input(row, dt, estimate, soft) turns its answer into
// stance feet weighted by their contact probability. estimation/contact_pipeline.hpp chains the
// two for a whole run.
#pragma once

#include <vector>

#include "estimation/contact/contact_detector.hpp"
#include "estimation/contact/soft_contact.hpp"
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

  // What a contact detector may see of row k: the force column of each foot (NaN without one),
  // the leg kinematics (FK and J of the joints; none for a log of foot columns, which carries
  // no foot velocity), the IMU, q, dq and tau when the log has them, and `base`, the estimate of
  // the previous step. Never the contact_ or gt_ columns.
  contact::ContactSignals signals(const io::LogRow& row, double dt,
                                  const contact::BaseFeedback& base) const;
  // The input of row k with the stance feet a detector decided: a foot is in stance when its
  // answer is usable, says contact and has p_c >= soft.min_probability; its covariance is the
  // soft one, R / (p_c + eps) + R_swing (1 - p_c) (contact/soft_contact.hpp), and its
  // ContactMeasurement::probability is p_c.
  StepInput input(const io::LogRow& row, double dt, const contact::ContactEstimate& contacts,
                  const contact::SoftContactParams& soft) const;

  const io::LogLayout& layout() const { return layout_; }

 private:
  // The input of row k without its feet.
  StepInput imuInput(const io::LogRow& row, double dt) const;
  // Foot `foot` of row k as a stance measurement, with the covariance of a certain contact.
  ContactMeasurement measurement(const io::LogRow& row, int foot) const;

  io::LogLayout layout_;
  model::QuadrupedKinematics kinematics_;
  FrontendNoise noise_;
};

}  // namespace legkit
