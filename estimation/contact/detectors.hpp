// Every contact detector of section 57.6 by name, for the run pipeline, the studies and the
// command line (`legkit run --contact <name>`). Library legkit_contact_factory: it sits above
// legkit_contact (this kit's sensor and kinematic detectors) and legkit_contact_learned (the
// momentum observer and the logistic contact probability), so that neither depends on the other.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "estimation/contact/contact_detector.hpp"
#include "estimation/contact/gait_schedule.hpp"
#include "estimation/contact/grf_threshold.hpp"
#include "estimation/contact/kinematic_detector.hpp"
#include "estimation/contact/logistic_contact.hpp"
#include "estimation/contact/momentum_observer.hpp"
#include "estimation/contact/schmitt_trigger.hpp"
#include "model/quadruped.hpp"
#include "model/quadruped_inertia.hpp"

namespace legkit::contact {

// What the detectors may need to know about the robot, and each one's parameters.
struct DetectorContext {
  model::QuadrupedGeometry geometry = model::QuadrupedGeometry::go2();
  model::QuadrupedInertia inertia = model::QuadrupedInertia::go2();
  std::optional<GaitSchedule> gait;       // the planned gait, when the robot has one
  std::optional<LogisticModel> logistic;  // a trained model (eval/contact_training.hpp)

  GrfThresholdParams grf;                      // "grf-threshold" and "grf-threshold-torque"
  SchmittParams schmitt = go2SchmittParams();  // "schmitt" (on the foot sensor)
  // "schmitt-torque": the chapter's 50 / 20 N. The force from joint torques reads tens of newtons
  // on a braking swing leg; 50 N keeps those out (precision 0.999 on the physics trot, where 25 N
  // gives 0.84) at the price of the stand (tests/contact/detectors_physics_test.cpp).
  SchmittParams schmitt_torque;
  KinematicParams kinematic;  // its foot_radius is replaced by geometry.foot_radius
  MomentumObserverParams momentum;
  LogisticParams probabilistic;
};

// The detector called `name`, one of detectorNames():
//   "gait-clock"            GaitClockDetector (needs context.gait)
//   "grf-threshold"         GrfThresholdDetector on the foot sensor
//   "grf-threshold-torque"  GrfThresholdDetector on the force from joint torques
//   "schmitt"               SchmittDetector on the foot sensor
//   "schmitt-torque"        SchmittDetector on the force from joint torques
//   "momentum-observer"     MomentumObserver
//   "probabilistic"         LogisticContactDetector (needs context.logistic; context.gait when the
//                           model uses the phase)
//   "kinematic"             KinematicDetector
//   "fallback"              the recommended chain, FallbackDetector of schmitt > momentum-observer
//                           > kinematic (> gait-clock when context.gait is set): the foot sensor
//                           first, then the joint torques through the whole-body dynamics, then
//                           kinematics alone, then the plan. Its name() is the chain,
//                           "schmitt>momentum-observer>kinematic>gait-clock". The chain is lazy
//                           (fallback_detector.hpp): while the sensors are healthy it costs the
//                           sensor Schmitt alone. schmitt-torque is left out: at the chapter's
//                           50 / 20 N it never switches on under a standing Go2's 37 N a foot
//                           (F1 0.68 mean over the physics scenarios of `legkit study contact`,
//                           the momentum observer 0.963); it stays selectable by name.
// Throws std::invalid_argument for an unknown name (listing the known ones), a detector whose
// context is missing (naming what is missing), or parameters the detector rejects.
std::unique_ptr<ContactDetector> makeDetector(const std::string& name,
                                              const DetectorContext& context);

// The force thresholds of every force-reading detector (schmitt, grf, momentum) are a design for
// the kit's 15.2 kg Go2: 25 / 10 N of go2SchmittParams are two thirds and a quarter of the 37 N one
// foot carries while it stands on four. A foot sensor's full scale and noise grow with the load
// it is built for, so another robot's are the same fractions of its own standing foot load,
// m g / n_feet: the iCub of data/icub-walking (33.1 kg on 2 feet, 162 N) gets 109 / 44 N and a
// 653 N full scale (its paper used 150 / 120 N); the 74.6 kg B2 gets 123 / 49 N. The built-in
// Go2's context is returned unchanged (its load is the reference). Throws std::invalid_argument
// unless mass > 0 (finite) and 1 <= num_feet <= kMaxFeet.
void scaleForcesToRobot(DetectorContext& context, double mass, int num_feet);

// The names makeDetector knows, in the order above.
std::vector<std::string> detectorNames();

}  // namespace legkit::contact
