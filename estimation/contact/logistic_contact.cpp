#include "estimation/contact/logistic_contact.hpp"

#include <cmath>
#include <stdexcept>

namespace legkit::contact {

ContactFeatures contactFeatures(const ContactSignals& signals, int foot, const GaitSchedule* gait) {
  const FootSignals& f = signals.feet[foot];
  ContactFeatures x;
  x.force = f.force;
  if (f.has_kinematics && signals.base.valid) {
    // v_foot = v + R (omega x B_p_f + B_v_f): the base's motion carried to the foot, plus the
    // leg's.
    const Eigen::Vector3d v_foot =
        signals.base.v + signals.base.R * (signals.gyro.cross(f.p_body) + f.v_body);
    x.foot_speed = v_foot.norm();
  }
  x.phase = gait != nullptr ? plannedPhase(*gait, foot, signals.t) : 0.0;
  return x;
}

double contactProbability(const LogisticModel& model, const ContactFeatures& x) {
  const Eigen::Vector3d raw(x.force, x.foot_speed, x.phase);
  double z = model.w[0];  // b
  for (int i = 0; i < 3; ++i)
    if (model.w[i + 1] != 0.0) z += model.w[i + 1] * (raw[i] - model.mean[i]) / model.scale[i];
  return 1.0 / (1.0 + std::exp(-z));  // sigma(z); NaN stays NaN
}

LogisticContactDetector::LogisticContactDetector(const LogisticModel& model,
                                                 const std::optional<GaitSchedule>& gait,
                                                 const LogisticParams& params)
    : model_(model), gait_(gait), params_(params) {
  if (!model.w.allFinite() || !model.mean.allFinite() || !model.scale.allFinite() ||
      !(model.scale.array() > 0.0).all())
    throw std::invalid_argument(
        "probabilistic: the logistic model needs finite weights and means and positive scales");
  if (model.usesPhase() && !gait)
    throw std::invalid_argument(
        "probabilistic: the model uses the gait phase but no gait schedule was given");
  if (!(params.hysteresis >= 0.0 && params.hysteresis < 0.5))
    throw std::invalid_argument("probabilistic: hysteresis must be in [0, 0.5)");
  // The weights in raw units, so that update() needs no division: a_i = w_i / scale_i,
  // b' = b - sum a_i mean_i.
  a_ = model.w.tail<3>().cwiseQuotient(model.scale);
  b_ = model.w[0] - a_.dot(model.mean);
}

void LogisticContactDetector::reset() {
  contact_.fill(false);
}

ContactEstimate LogisticContactDetector::update(const ContactSignals& signals) {
  if (signals.num_feet < 1 || signals.num_feet > kMaxFeet)
    throw std::invalid_argument("probabilistic at t = " + std::to_string(signals.t) +
                                ": num_feet = " + std::to_string(signals.num_feet) +
                                " outside [1, " + std::to_string(kMaxFeet) + "]");
  if (!std::isfinite(signals.dt) || signals.dt < 0.0)
    throw std::invalid_argument("probabilistic at t = " + std::to_string(signals.t) + ": dt = " +
                                std::to_string(signals.dt) + " (must be finite and >= 0)");
  ContactEstimate out;
  out.t = signals.t;
  out.num_feet = signals.num_feet;
  const GaitSchedule* gait = gait_ ? &*gait_ : nullptr;
  for (int i = 0; i < signals.num_feet; ++i) {
    FootContact& c = out.feet[i];
    const ContactFeatures x = contactFeatures(signals, i, gait);
    if (model_.usesForce()) {
      if (std::isnan(x.force)) {
        c.problem = "force is NaN";
        continue;
      }
      c.force = x.force;
    }
    if (model_.usesFootSpeed()) {
      if (!signals.feet[i].has_kinematics) {
        c.problem = "no leg kinematics";
        continue;
      }
      if (!signals.base.valid) {
        c.problem = "no base estimate";
        continue;
      }
      if (!std::isfinite(x.foot_speed)) {
        c.problem = "foot speed not finite";
        continue;
      }
    }
    double z = b_;  // b' + a . x over the features the model uses
    if (model_.usesForce()) z += a_[0] * x.force;
    if (model_.usesFootSpeed()) z += a_[1] * x.foot_speed;
    if (model_.usesPhase()) z += a_[2] * x.phase;
    const double p_c = 1.0 / (1.0 + std::exp(-z));
    if (!std::isfinite(p_c)) {  // an infinite force: sigma of inf - inf
      c.problem = "force is NaN";
      continue;
    }
    c.probability = p_c;
    if (p_c > 0.5 + params_.hysteresis) contact_[i] = true;
    if (p_c < 0.5 - params_.hysteresis) contact_[i] = false;
    c.contact = contact_[i];
  }
  return out;
}

}  // namespace legkit::contact
