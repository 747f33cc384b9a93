#include "estimation/contact/schmitt_trigger.hpp"

#include <cmath>
#include <stdexcept>

#include "estimation/contact/gait_clock.hpp"

namespace legkit::contact {

namespace {

constexpr double kTimeTolerance = 1e-9;  // [s] rounding allowance of "held for longer than T"

std::array<SchmittTrigger, kMaxFeet> triggersOf(const SchmittParams& p) {
  std::array<SchmittTrigger, kMaxFeet> t;
  t.fill(SchmittTrigger(p));
  return t;
}

}  // namespace

SchmittParams go2SchmittParams() {
  SchmittParams p;
  p.f_high = 25.0;
  p.f_low = 10.0;
  return p;
}

SchmittTrigger::SchmittTrigger(const SchmittParams& p)
    : f_high_(p.f_high), f_low_(p.f_low), t_on_(p.t_on), t_off_(p.t_off) {
  if (!(std::isfinite(p.f_high) && std::isfinite(p.f_low) && p.f_low <= p.f_high))
    throw std::invalid_argument("schmitt: need finite f_low <= f_high");
  if (!(p.t_on >= 0.0 && p.t_off >= 0.0 && std::isfinite(p.t_on) && std::isfinite(p.t_off)))
    throw std::invalid_argument("schmitt: t_on and t_off must be finite and >= 0");
}

bool SchmittTrigger::update(double force, double dt) {
  // Off: F > F_high held for > T_on switches on; on: F < F_low held for > T_off switches off.
  // Any reading that does not push toward the other state restarts the hold.
  const bool toward = state_ ? force < f_low_ : force > f_high_;
  if (!toward) {
    timer_ = 0.0;
    return state_;
  }
  timer_ += dt;
  if (timer_ > (state_ ? t_off_ : t_on_) + kTimeTolerance) {
    state_ = !state_;
    timer_ = 0.0;
  }
  return state_;
}

SchmittDetector::SchmittDetector(const SchmittParams& params, ForceSource source,
                                 const model::QuadrupedGeometry& geometry,
                                 const model::QuadrupedInertia& inertia)
    : params_(params),
      reader_(source, params, "schmitt", geometry, inertia),
      triggers_(triggersOf(params)) {
  if (!(params.saturation > params.f_high))
    throw std::invalid_argument("schmitt: saturation must be above f_high");
}

std::string SchmittDetector::name() const {
  return reader_.source() == ForceSource::kSensor ? "schmitt" : "schmitt-torque";
}

void SchmittDetector::reset() {
  reader_.reset();
  for (SchmittTrigger& s : triggers_) s.reset();
}

ContactEstimate SchmittDetector::update(const ContactSignals& signals) {
  ContactEstimate out = reader_.read(signals, "schmitt");
  for (int i = 0; i < out.num_feet; ++i) {
    FootContact& f = out.feet[i];
    if (f.problem != nullptr) {
      triggers_[i].interrupt();
      continue;
    }
    f.contact = triggers_[i].update(f.force, signals.dt);
    f.probability = f.contact ? 1.0 : 0.0;
  }
  return out;
}

}  // namespace legkit::contact
