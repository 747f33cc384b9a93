#include "estimation/contact/grf_threshold.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "estimation/contact/gait_clock.hpp"

namespace legkit::contact {

FootForceReader::FootForceReader(ForceSource source, const ForceChecks& checks, const char* who,
                                 const model::QuadrupedGeometry& geometry,
                                 const model::QuadrupedInertia& inertia)
    : source_(source), checks_(checks) {
  if (!(checks.stuck_time > 0.0))
    throw std::invalid_argument(std::string(who) + ": stuck_time must be positive");
  if (!(checks.negative_limit <= 0.0))
    throw std::invalid_argument(std::string(who) + ": negative_limit must be <= 0");
  if (source == ForceSource::kJointTorque) torque_.emplace(geometry, inertia);
}

ContactEstimate FootForceReader::read(const ContactSignals& s, const char* who) {
  checkSignals(s, who);
  ContactEstimate out;
  out.t = s.t;
  out.num_feet = s.num_feet;
  if (source_ == ForceSource::kJointTorque) {
    std::array<const char*, model::kNumLegs> why{};
    const std::array<Eigen::Vector3d, model::kNumLegs> lambda = torque_->estimate(s, &why);
    for (int i = 0; i < s.num_feet; ++i) {
      if (i >= model::kNumLegs) {
        out.feet[i].force = std::numeric_limits<double>::quiet_NaN();
        out.feet[i].problem = "foot is not one of the quadruped's legs";
        continue;
      }
      out.feet[i].force = lambda[i].z();
      out.feet[i].problem = why[i];
    }
    return out;
  }
  for (int i = 0; i < s.num_feet; ++i) {
    const double f = s.feet[i].force;
    const char*& problem = out.feet[i].problem;
    out.feet[i].force = f;
    bool saturated = false;
    if (std::isnan(f)) {
      problem = "no force reading";
    } else if (!std::isfinite(f)) {
      problem = "force is not finite";
    } else if (f < checks_.negative_limit) {
      problem = "force negative";
    } else if (f >= checks_.saturation) {
      saturated = true;
      saturated_time_[i] += s.dt;
      if (saturated_time_[i] > checks_.stuck_time) problem = "force stuck at saturation";
    }
    if (!saturated) saturated_time_[i] = 0.0;
  }
  return out;
}

GrfThresholdDetector::GrfThresholdDetector(const GrfThresholdParams& params, ForceSource source,
                                           const model::QuadrupedGeometry& geometry,
                                           const model::QuadrupedInertia& inertia)
    : params_(params), reader_(source, params, "grf-threshold", geometry, inertia) {
  if (!std::isfinite(params.threshold))
    throw std::invalid_argument("grf-threshold: threshold not finite");
  if (!(params.saturation > params.threshold))
    throw std::invalid_argument("grf-threshold: saturation must be above the threshold");
}

std::string GrfThresholdDetector::name() const {
  return reader_.source() == ForceSource::kSensor ? "grf-threshold" : "grf-threshold-torque";
}

ContactEstimate GrfThresholdDetector::update(const ContactSignals& signals) {
  ContactEstimate out = reader_.read(signals, "grf-threshold");
  for (int i = 0; i < out.num_feet; ++i) {
    FootContact& f = out.feet[i];
    if (f.problem != nullptr) continue;
    f.contact = f.force > params_.threshold;  // c_i = [F_n,i > F_threshold]
    f.probability = f.contact ? 1.0 : 0.0;
  }
  return out;
}

}  // namespace legkit::contact
