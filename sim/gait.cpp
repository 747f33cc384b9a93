#include "sim/gait.hpp"

#include <cmath>
#include <limits>

namespace legkit::sim {

Gait Gait::stand() {
  Gait g;
  g.duty = 1.0;
  return g;
}

Gait Gait::trot(double frequency) {
  Gait g;
  g.period = 1.0 / frequency;
  g.duty = 0.6;  // at 2 Hz: 300 ms stance, 200 ms swing (the chapter's exercise 57.6.1 numbers)
  g.offset = {0.0, 0.5, 0.5, 0.0};
  return g;
}

Gait Gait::walk(double frequency) {
  Gait g;
  g.period = 1.0 / frequency;
  g.duty = 0.75;
  g.offset = {0.0, 0.5, 0.75, 0.25};  // swing order FL, RR, FR, RL
  return g;
}

Gait Gait::bound(double frequency) {
  Gait g;
  g.period = 1.0 / frequency;
  g.duty = 0.3;  // front stance, flight, rear stance, flight: 30 / 20 / 30 / 20 % of the period
  g.offset = {0.0, 0.0, 0.5, 0.5};
  return g;
}

namespace {

// Lift-off j (j >= 0) of leg `leg`: the j-th time at or after `start` where the local phase
// reaches the duty factor.
double liftoff(const Gait& g, int leg, int j) {
  const double first = g.duty + g.offset[leg];
  const double k0 = std::ceil(-first);
  return g.start + g.period * (first + k0 + j);
}

}  // namespace

double liftoffTime(const Gait& gait, int leg, int stance_index) {
  return liftoff(gait, leg, stance_index);
}

double touchdownTime(const Gait& gait, int leg, int stance_index) {
  return liftoff(gait, leg, stance_index - 1) + gait.swingDuration();
}

GaitPhase gaitPhase(const Gait& gait, int leg, double t) {
  const double inf = std::numeric_limits<double>::infinity();
  if (gait.alwaysStance()) return {true, 0, -inf, inf};
  const double lo0 = liftoff(gait, leg, 0);
  if (t < lo0) return {true, 0, -inf, lo0};
  int j = static_cast<int>(std::floor((t - lo0) / gait.period));
  if (t < liftoff(gait, leg, j)) --j;  // rounding of the division
  const double lo = liftoff(gait, leg, j);
  const double td = lo + gait.swingDuration();
  if (t < td) return {false, j, lo, td};
  return {true, j + 1, td, liftoff(gait, leg, j + 1)};
}

}  // namespace legkit::sim
