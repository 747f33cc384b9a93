#include "sim/scenario.hpp"

#include <stdexcept>

namespace legkit::sim {
namespace {

// Body oscillations of a trot-like gait: the body dips once per diagonal stance (twice per
// period), rolls and yaws once per period.
void trotOscillations(Scenario& s) {
  const double f = 1.0 / s.gait.period;
  s.bob_amplitude = 0.01, s.bob_frequency = 2.0 * f;
  s.roll_amplitude = 0.02, s.roll_frequency = f;
  s.pitch_amplitude = 0.015, s.pitch_frequency = 2.0 * f;
  s.yaw_amplitude = 0.01, s.yaw_frequency = f;
}

}  // namespace

std::vector<std::string> scenarioNames() {
  return {"stand", "walk", "trot", "turn", "lateral", "bound"};
}

Scenario scenarioByName(const std::string& name) {
  Scenario s;
  s.name = name;
  if (name == "stand") {
    s.gait = Gait::stand();
    s.bob_amplitude = 0.02, s.bob_frequency = 0.5;
    s.roll_amplitude = 0.05, s.roll_frequency = 0.3;
    s.pitch_amplitude = 0.05, s.pitch_frequency = 0.4;
    s.yaw_amplitude = 0.05, s.yaw_frequency = 0.2;
  } else if (name == "walk") {
    s.gait = Gait::walk(1.0);
    s.velocity = {0.3, 0.0};
    s.bob_amplitude = 0.005, s.bob_frequency = 4.0;
    s.roll_amplitude = 0.02, s.roll_frequency = 1.0;
    s.pitch_amplitude = 0.01, s.pitch_frequency = 2.0;
  } else if (name == "trot") {
    s.gait = Gait::trot(2.0);
    s.velocity = {0.5, 0.0};
    trotOscillations(s);
  } else if (name == "turn") {
    s.gait = Gait::trot(2.0);
    s.yaw_rate = 0.5;
    trotOscillations(s);
  } else if (name == "lateral") {
    s.gait = Gait::trot(2.0);
    s.velocity = {0.0, 0.25};
    trotOscillations(s);
  } else if (name == "bound") {
    s.gait = Gait::bound(2.0);
    s.velocity = {1.0, 0.0};
    s.ballistic_flight = true;
    s.pitch_amplitude = 0.05, s.pitch_frequency = 2.0;
    s.swing_height = 0.06;
  } else {
    std::string known;
    for (const std::string& n : scenarioNames()) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown scenario '" + name + "' (known: " + known + ")");
  }
  return s;
}

}  // namespace legkit::sim
