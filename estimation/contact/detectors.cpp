#include "estimation/contact/detectors.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "estimation/contact/fallback_detector.hpp"
#include "estimation/contact/gait_clock.hpp"

namespace legkit::contact {

std::vector<std::string> detectorNames() {
  return {"gait-clock",    "grf-threshold",  "grf-threshold-torque",
          "schmitt",       "schmitt-torque", "momentum-observer",
          "probabilistic", "kinematic",      "fallback"};
}

void scaleForcesToRobot(DetectorContext& c, double mass, int num_feet) {
  if (!(mass > 0.0 && std::isfinite(mass))) {
    throw std::invalid_argument("the robot's mass must be positive and finite");
  }
  if (num_feet < 1 || num_feet > kMaxFeet) {
    throw std::invalid_argument("a robot of " + std::to_string(num_feet) + " feet (1 to " +
                                std::to_string(kMaxFeet) + ")");
  }
  // s = (m g / n) / (m_go2 g / 4): the robot's standing foot load in units of the Go2's
  const double s = (mass / num_feet) / (model::QuadrupedInertia::go2().totalMass() / 4.0);
  for (SchmittParams* p : {&c.schmitt, &c.schmitt_torque}) {
    p->f_high *= s;
    p->f_low *= s;
    p->saturation *= s;
    p->negative_limit *= s;
  }
  c.grf.threshold *= s;
  c.grf.saturation *= s;
  c.grf.negative_limit *= s;
  c.momentum.threshold *= s;
  c.momentum.release *= s;
}

std::unique_ptr<ContactDetector> makeDetector(const std::string& name, const DetectorContext& c) {
  if (name == "gait-clock") {
    if (!c.gait) throw std::invalid_argument("contact detector gait-clock needs a gait schedule");
    return std::make_unique<GaitClockDetector>(*c.gait);
  }
  if (name == "grf-threshold" || name == "grf-threshold-torque") {
    const ForceSource source =
        name == "grf-threshold" ? ForceSource::kSensor : ForceSource::kJointTorque;
    return std::make_unique<GrfThresholdDetector>(c.grf, source, c.geometry, c.inertia);
  }
  if (name == "schmitt")
    return std::make_unique<SchmittDetector>(c.schmitt, ForceSource::kSensor, c.geometry,
                                             c.inertia);
  if (name == "schmitt-torque")
    return std::make_unique<SchmittDetector>(c.schmitt_torque, ForceSource::kJointTorque,
                                             c.geometry, c.inertia);
  if (name == "momentum-observer")
    return std::make_unique<MomentumObserver>(c.geometry, c.inertia, c.momentum);
  if (name == "probabilistic") {
    if (!c.logistic)
      throw std::invalid_argument(
          "contact detector probabilistic needs a trained logistic model "
          "(eval/contact_training.hpp: trainContactModel)");
    return std::make_unique<LogisticContactDetector>(*c.logistic, c.gait, c.probabilistic);
  }
  if (name == "kinematic") {
    KinematicParams k = c.kinematic;
    k.foot_radius = c.geometry.foot_radius;
    return std::make_unique<KinematicDetector>(k);
  }
  if (name == "fallback") {
    std::vector<std::unique_ptr<ContactDetector>> chain;
    for (const char* n : {"schmitt", "momentum-observer", "kinematic"})
      chain.push_back(makeDetector(n, c));
    if (c.gait) chain.push_back(makeDetector("gait-clock", c));
    return std::make_unique<FallbackDetector>(std::move(chain));
  }
  std::string known;
  for (const std::string& n : detectorNames()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown contact detector '" + name + "' (known: " + known + ")");
}

}  // namespace legkit::contact
