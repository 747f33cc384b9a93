#include "estimation/contact/gait_clock.hpp"

#include <cmath>
#include <stdexcept>

namespace legkit::contact {

void checkSignals(const ContactSignals& signals, const char* detector) {
  const bool feet_ok = signals.num_feet >= 1 && signals.num_feet <= kMaxFeet;
  if (feet_ok && std::isfinite(signals.dt) && signals.dt >= 0.0) return;
  const std::string at = std::string(detector) + " at t = " + std::to_string(signals.t) + ": ";
  if (!feet_ok)
    throw std::invalid_argument(at + "num_feet = " + std::to_string(signals.num_feet) +
                                " outside [1, " + std::to_string(kMaxFeet) + "]");
  throw std::invalid_argument(at + "dt = " + std::to_string(signals.dt) +
                              " (must be finite and >= 0)");
}

GaitClockDetector::GaitClockDetector(const GaitSchedule& gait) : gait_(gait) {
  if (!(gait.period > 0.0) || !std::isfinite(gait.period))
    throw std::invalid_argument("gait-clock: period must be positive and finite");
  if (!(gait.duty > 0.0) || !std::isfinite(gait.duty))
    throw std::invalid_argument("gait-clock: duty must be positive and finite");
  if (gait.num_feet < 1 || gait.num_feet > kMaxFeet)
    throw std::invalid_argument("gait-clock: num_feet outside [1, kMaxFeet]");
  if (!std::isfinite(gait.start)) throw std::invalid_argument("gait-clock: start not finite");
  for (int i = 0; i < gait.num_feet; ++i)
    if (!std::isfinite(gait.offset[i]))
      throw std::invalid_argument("gait-clock: offset of foot " + std::to_string(i) +
                                  " not finite");
}

ContactEstimate GaitClockDetector::update(const ContactSignals& signals) {
  checkSignals(signals, "gait-clock");
  ContactEstimate out;
  out.t = signals.t;
  out.num_feet = signals.num_feet;
  for (int i = 0; i < signals.num_feet; ++i) {
    FootContact& f = out.feet[i];
    if (i >= gait_.num_feet) {
      f.problem = "foot not in the gait schedule";
      continue;
    }
    f.contact = plannedStance(gait_, i, signals.t);
    f.probability = f.contact ? 1.0 : 0.0;
  }
  return out;
}

}  // namespace legkit::contact
