// The planned gait of a robot that has one (section 57.6, method 1): a periodic clock per foot.
// Before `start` every foot stands. From `start` on, foot i is planned in stance while its local
// phase frac((t - start) / period - offset_i) is below the duty factor; a foot whose clock says
// "swing" at `start` keeps standing until its first planned lift-off, so the robot never starts
// in the air. (The physics simulator's controller walks by the same rule, sim/gait.hpp; this copy
// is what a robot's own planner would publish, so estimation/ does not include sim/.)
#pragma once

#include <array>
#include <cmath>

#include "estimation/contact/contact_detector.hpp"

namespace legkit::contact {

struct GaitSchedule {
  double period = 0.5;  // [s]
  double duty = 0.6;    // planned stance fraction of the period; >= 1: never lifts
  std::array<double, kMaxFeet> offset{0.0, 0.5, 0.5, 0.0};  // per foot, in periods
  double start = 0.0;                                       // when the clock starts [s]
  int num_feet = 4;
};

// Where foot `foot` is in its planned cycle at time t, in [0, 1): 0 at the planned touchdown,
// stance while below duty, swing from duty to 1. A foot that has not lifted off yet (the stand
// before its first planned lift-off) reports 0: planned stance, as if it had just touched down.
inline double plannedPhase(const GaitSchedule& g, int foot, double t) {
  if (g.duty >= 1.0) return 0.0;
  const double first_liftoff =
      g.start + g.period * (g.duty + g.offset[foot] + std::ceil(-(g.duty + g.offset[foot])));
  if (t < first_liftoff) return 0.0;
  const double cycles = (t - g.start) / g.period - g.offset[foot];
  return cycles - std::floor(cycles);
}

// The schedule's answer: foot planned in stance at t.
inline bool plannedStance(const GaitSchedule& g, int foot, double t) {
  return plannedPhase(g, foot, t) < g.duty;
}

}  // namespace legkit::contact
