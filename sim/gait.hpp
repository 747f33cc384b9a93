// A periodic gait clock: which feet are on the ground when, with ideal (instantaneous) contact
// changes. Before `start` every foot stands; from `start` on, leg i is in stance while its local
// phase frac((t - start) / period - offset_i) is below the duty factor. A leg whose clock says
// "swing" at `start` keeps standing until its first lift-off, so the robot never starts mid-air.
#pragma once

#include <array>

#include "model/quadruped.hpp"

namespace legkit::sim {

struct Gait {
  double period = 0.5;  // [s] (2 Hz)
  double duty = 0.6;    // stance fraction of the period; 1: never lifts
  std::array<double, model::kNumLegs> offset{0.0, 0.5, 0.5, 0.0};  // phase offsets, FL FR RL RR
  double start = 0.0;  // first instant the clock runs [s]

  static Gait stand();                        // every foot always down
  static Gait trot(double frequency = 2.0);   // diagonal pairs, 60 % stance
  static Gait walk(double frequency = 1.0);   // one foot at a time, 75 % stance
  static Gait bound(double frequency = 2.0);  // front pair, then rear pair; flights

  bool alwaysStance() const { return duty >= 1.0; }
  double swingDuration() const { return (1.0 - duty) * period; }
};

// Where leg `leg` is in its sequence of contacts at time t. Stance 0 is the initial stand (from
// -infinity to the first lift-off); swing j runs from lift-off j to touchdown j, after which
// stance j + 1 begins and lasts until lift-off j + 1.
struct GaitPhase {
  bool stance = true;
  int index = 0;       // stance index, or swing index
  double begin = 0.0;  // start of this stance (touchdown) or swing (lift-off) [s]; stance 0: -inf
  double end = 0.0;    // its end [s] (lift-off, or touchdown)
};

GaitPhase gaitPhase(const Gait& gait, int leg, double t);

// Touchdown and lift-off of stance j >= 1 of leg `leg`.
double touchdownTime(const Gait& gait, int leg, int stance_index);
double liftoffTime(const Gait& gait, int leg, int stance_index);

}  // namespace legkit::sim
