// Method 3 of section 57.6: the Schmitt trigger, two thresholds with hysteresis and hold times:
//   c_i(t) = 1          if F_n,i > F_high has held for longer than T_on,
//            0          if F_n,i < F_low  has held for longer than T_off,
//            c_i(t - 1) otherwise.
// Noise that crosses one threshold cannot toggle the flag: it must cross the other one (a band of
// F_high - F_low = 30 N by default) and stay there for the hold time. The price is the delay: a
// touchdown is declared T_on after the force passes F_high (5 ms by default), a lift-off T_off
// after it falls below F_low. The rule of thumb of the chapter: T_on, T_off < 0.1 T_stance.
#pragma once

#include <array>
#include <string>

#include "estimation/contact/contact_detector.hpp"
#include "estimation/contact/grf_threshold.hpp"

namespace legkit::contact {

// The thresholds and hold times, and the force checks of the reader (ForceChecks,
// grf_threshold.hpp).
struct SchmittParams : ForceChecks {
  double f_high = 50.0, f_low = 20.0;  // F_high, F_low [N]
  double t_on = 0.005, t_off = 0.005;  // T_on, T_off [s]
};

// The kit's design for its Go2-class robot and foot sensors (what makeDetector uses): the
// chapter's F_high = 50 N is above the 37 N one foot carries while the 15.2 kg robot stands on
// four, so the chapter's defaults never see a stand. F_high = 25 N (two thirds of the standing
// load, a third of a trot's 75 N), F_low = 10 N (3.5 sigma above an unloaded sensor's 3 +- 2 N),
// T_on = T_off = 5 ms (< 0.1 x the trot's 300 ms stance). On the 10 s physics trot (seed 13):
// F1 0.991, touchdown 5 ms late, no chatter (tests/contact/detectors_physics_test.cpp).
SchmittParams go2SchmittParams();

// One foot's trigger. The time a threshold has held counts the sample intervals dt from the first
// sample beyond it (that sample's own dt included, as the chapter's code does); "longer than T"
// allows 1 ns for rounding, so that five 1 ms samples hold for exactly 5 ms, not 5 ms + 1 ulp.
class SchmittTrigger {
 public:
  // Throws std::invalid_argument unless f_low <= f_high (both finite) and t_on, t_off >= 0.
  explicit SchmittTrigger(const SchmittParams& params = {});

  // Feeds one reading, dt after the previous one; returns the state after it.
  bool update(double force, double dt);
  bool state() const { return state_; }
  // Back to "no contact" with no time held.
  void reset() {
    state_ = false;
    timer_ = 0.0;
  }
  // Holds the state and forgets the time held (a sample without a usable reading interrupts a
  // hold: the threshold must hold again from the next reading on).
  void interrupt() { timer_ = 0.0; }

 private:
  double f_high_, f_low_, t_on_, t_off_;
  double timer_ = 0.0;  // how long the threshold that would switch the state has held [s]
  bool state_ = false;
};

class SchmittDetector : public ContactDetector {
 public:
  // Throws std::invalid_argument for thresholds SchmittTrigger rejects, a saturation not above
  // f_high, a non-positive stuck_time or a positive negative_limit.
  explicit SchmittDetector(
      const SchmittParams& params = {}, ForceSource source = ForceSource::kSensor,
      const model::QuadrupedGeometry& geometry = model::QuadrupedGeometry::go2(),
      const model::QuadrupedInertia& inertia = model::QuadrupedInertia::go2());

  // "schmitt" on the sensor, "schmitt-torque" on the joint torques.
  std::string name() const override;
  void reset() override;
  // Per foot: the trigger's state, probability 0 or 1, force = F_n; or the reader's problem, and
  // then the trigger holds its state (SchmittTrigger::interrupt).
  ContactEstimate update(const ContactSignals& signals) override;

  const SchmittParams& params() const { return params_; }

 private:
  SchmittParams params_;
  FootForceReader reader_;
  std::array<SchmittTrigger, kMaxFeet> triggers_;
};

}  // namespace legkit::contact
