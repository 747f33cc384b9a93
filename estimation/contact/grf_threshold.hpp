// Method 2 of section 57.6: contact when the normal ground reaction exceeds a threshold,
//   c_i = 1 if F_n,i > F_threshold, else 0      (typically F_threshold = 20-50 N).
// Zero delay, but where the force crosses the threshold slowly (touchdown, lift-off) its noise
// crosses it back and forth and the flag chatters (schmitt_trigger.hpp is the cure).
//
// The force comes from a foot sensor (FootSignals::force) or is estimated from the joint torques
// (foot_force.hpp, its world z component). Either way a bad reading is that foot's problem, never
// a silent "no contact" (FootForceReader below).
#pragma once

#include <array>
#include <optional>
#include <string>

#include "estimation/contact/contact_detector.hpp"
#include "estimation/contact/foot_force.hpp"
#include "model/quadruped.hpp"
#include "model/quadruped_inertia.hpp"

namespace legkit::contact {

enum class ForceSource {
  kSensor,       // FootSignals::force, a foot sensor's normal force
  kJointTorque,  // the z component of FootForceFromTorque's estimate
};

// The force sanity checks both force detectors share.
struct ForceChecks {
  double saturation = 150.0;  // the sensor's full scale [N]
  // A reading at or above saturation for longer than this is a stuck sensor, not a contact [s]
  // (a stance lasts a fraction of a second while walking; standing, the load per foot is far
  // below full scale).
  double stuck_time = 1.0;
  // A sensor reading below this is a fault, not a light contact [N] (a foot sensor reads >= 0
  // up to its noise). Not applied to a force estimated from torques, which is legitimately
  // negative while a swing leg accelerates.
  double negative_limit = -10.0;
};

// Reads one normal force per foot from the chosen source and checks it. Per foot, in this order:
//   sensor source:  "no force reading"            NaN (the log has no force column, or lost it)
//                   "force is not finite"         +-infinity
//                   "force negative"              below negative_limit
//                   "force stuck at saturation"   >= saturation for longer than stuck_time (a
//                                                 shorter saturation is a valid, large reading)
//   torque source:  FootForceFromTorque's reasons ("no joint torques", "leg singular", ...), and
//                   "foot is not one of the quadruped's legs" for a foot id beyond 3.
// Keeps the time each foot has been saturated: call it once per sample, in order.
class FootForceReader {
 public:
  // The torque source needs the robot's geometry and inertia; the sensor source ignores them.
  // Throws std::invalid_argument, its message starting with `who` (the detector's name), for a
  // non-positive stuck_time or a positive negative_limit.
  FootForceReader(ForceSource source, const ForceChecks& checks, const char* who,
                  const model::QuadrupedGeometry& geometry = model::QuadrupedGeometry::go2(),
                  const model::QuadrupedInertia& inertia = model::QuadrupedInertia::go2());

  // The estimate both force detectors start from: signals checked (checkSignals, naming `who`),
  // t and num_feet, and per foot its force and problem (nullptr when the reading is usable); the
  // detector then sets contact and probability of the feet without a problem.
  ContactEstimate read(const ContactSignals& signals, const char* who);
  void reset() { saturated_time_.fill(0.0); }

  ForceSource source() const { return source_; }

 private:
  ForceSource source_;
  ForceChecks checks_;
  std::optional<FootForceFromTorque> torque_;  // only for kJointTorque
  std::array<double, kMaxFeet> saturated_time_{};
};

// The threshold, and the force checks of the reader (ForceChecks above).
struct GrfThresholdParams : ForceChecks {
  double threshold = 30.0;  // F_threshold [N]
};

class GrfThresholdDetector : public ContactDetector {
 public:
  // Throws std::invalid_argument for a non-finite threshold, a saturation not above the
  // threshold, a non-positive stuck_time or a positive negative_limit.
  explicit GrfThresholdDetector(
      const GrfThresholdParams& params = {}, ForceSource source = ForceSource::kSensor,
      const model::QuadrupedGeometry& geometry = model::QuadrupedGeometry::go2(),
      const model::QuadrupedInertia& inertia = model::QuadrupedInertia::go2());

  // "grf-threshold" on the sensor, "grf-threshold-torque" on the joint torques.
  std::string name() const override;
  void reset() override { reader_.reset(); }
  // contact = F_n > threshold, probability 0 or 1, force = F_n; or the reader's problem.
  ContactEstimate update(const ContactSignals& signals) override;

 private:
  GrfThresholdParams params_;
  FootForceReader reader_;
};

}  // namespace legkit::contact
