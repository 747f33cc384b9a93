// The motions the simulator knows, as plain data: a gait and an analytic base motion.
//
//   stand    all feet down; after the start the body sways (height, roll, pitch) over fixed feet
//   walk     1 Hz walk, one foot in the air at a time, 0.3 m/s forward
//   trot     2 Hz trot (diagonal pairs, 300 ms stance, 200 ms swing), 0.5 m/s forward (default)
//   turn     2 Hz trot turning in place at 0.5 rad/s
//   lateral  2 Hz trot stepping sideways (to the left) at 0.25 m/s
//   bound    2 Hz bound, 1 m/s: front pair, flight, rear pair, flight; in flight the base is
//            ballistic (acceleration exactly g), so the accelerometer reads only bias and noise
//
// Every motion starts with `stand_time` seconds of standing still (for stationary
// initialisation), then speed, turn rate and body oscillations ramp up smoothly over
// `ramp_duration` while the gait clock runs.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "sim/gait.hpp"

namespace legkit::sim {

struct Scenario {
  std::string name;
  Gait gait;  // its start is set to stand_time by the motion (sim/quadruped_motion.hpp)
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  // world-frame horizontal speed [m/s]
  double yaw_rate = 0.0;                               // [rad/s]
  double height = 0.30;                                // base height above the ground [m]
  double swing_height = 0.08;                          // foot lift at mid-swing [m]
  // Small body oscillations (amplitudes [m] or [rad]) at these frequencies [Hz].
  double bob_amplitude = 0.0, bob_frequency = 0.0;
  double roll_amplitude = 0.0, roll_frequency = 0.0;
  double pitch_amplitude = 0.0, pitch_frequency = 0.0;
  double yaw_amplitude = 0.0, yaw_frequency = 0.0;
  bool ballistic_flight = false;  // bound: vertical motion with true flight phases
  double stand_time = 1.0;        // still at the start [s]
  double ramp_duration = 1.0;     // speed and oscillations ramp up over this [s]
};

// The scenario called `name` (one of scenarioNames()); throws std::invalid_argument otherwise,
// listing the known names.
Scenario scenarioByName(const std::string& name);
std::vector<std::string> scenarioNames();

}  // namespace legkit::sim
