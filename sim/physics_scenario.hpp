// The scenarios of the physics simulator (sim/physics_simulator.hpp), as plain data: a gait and a
// command for the walking controller (sim/locomotion_controller.hpp), the terrain and the pushes.
//
//   physics-stand      all feet down, 10 s
//   physics-trot       2 Hz trot at 0.5 m/s forward, 60 s
//   physics-turn       2 Hz trot turning in place at 0.5 rad/s, 20 s
//   physics-walk       1.5 Hz walk (one foot in the air at a time) at 0.2 m/s, 20 s
//   physics-push       standing, pushed sideways (+y) with 60 N for 0.2 s at t = 3 s, 10 s
//   physics-step-down  2 Hz trot at 0.4 m/s off a 5 cm step at x = 0.6 m, 10 s
//   physics-slope      2 Hz trot at 0.4 m/s up a 0.16 rad (9.2 degree) ramp from x = 0.6 m to
//                      1.6 m (16.1 cm rise) onto a plateau, 10 s
//   physics-ice        2 Hz trot at 0.5 m/s over an ice patch (mu 0.1, 0.6 elsewhere) under the
//                      FR foot's path from x = 1 m to 4 m, naive controller (believes mu 0.6)
//   physics-ice-aware  the same with the friction-aware controller (|f_t| <= 0.08 f_n)
//   physics-ice-push   standing on ice everywhere (mu 0.1), friction-aware, pushed sideways
//                      with 50 N for 0.2 s at t = 3 s, 10 s
//   physics-real       2 Hz trot at 0.5 m/s turning at 0.4 rad/s, 30 s, on a robot with a real
//                      one's imperfections (realRobot(): links off the model, joint offsets,
//                      backlash, quantised and delayed encoders, a held IMU, compliant feet)
// Every scenario stands still for stand_time (stationary initialisation), then the gait clock
// starts and the speed and turn rate ramp up smoothly over ramp_duration.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sim/gait.hpp"
#include "sim/robot_imperfections.hpp"

namespace legkit::sim {

// A region of the ground with another friction coefficient: world x-y box [m].
struct FrictionPatch {
  Eigen::Vector2d min = Eigen::Vector2d::Zero(), max = Eigen::Vector2d::Zero();
  double friction = 0.6;
};

struct Terrain {
  // Sliding friction of the ground: the one that acts (MuJoCo takes the larger of two touching
  // geoms' frictions and the robot's geoms have 0), in (0, 2].
  double friction = 0.6;
  std::vector<FrictionPatch> patches;  // where several overlap, the last one listed holds
  // A step across the x axis at x = step_x: the ground is at z = 0 for x < step_x and at
  // z = step_height beyond (< 0: a step down, > 0: a step up; 0: flat).
  double step_x = 0.0;
  double step_height = 0.0;
  // A ramp across the x axis: from x = slope_start the ground rises at slope_angle (< 0: falls)
  // over a horizontal run of slope_length, then stays at the top's height (a plateau); 0: flat.
  // It adds to the step where both are present.
  double slope_start = 0.0;   // [m]
  double slope_angle = 0.0;   // [rad], |slope_angle| <= 0.35
  double slope_length = 1.0;  // horizontal run [m], > 0

  // Height of the ground at x [m]: the step plus the rise of the ramp so far.
  double height(double x) const {
    return (x < step_x ? 0.0 : step_height) +
           std::tan(slope_angle) * std::clamp(x - slope_start, 0.0, slope_length);
  }
  // Slope dz/dx of the ground at x (on the ramp: tan(slope_angle); 0 elsewhere).
  double grade(double x) const {
    const bool on_ramp = x > slope_start && x < slope_start + slope_length;
    return on_ramp ? std::tan(slope_angle) : 0.0;
  }
  // Flat ground: neither a step nor a ramp.
  bool level() const { return step_height == 0.0 && slope_angle == 0.0; }
};

// A force on the trunk (at its centre of mass), world frame, constant over [start, start +
// duration).
struct Push {
  double start = 0.0, duration = 0.0;               // [s]
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // [N]
};

struct PhysicsScenario {
  std::string name;
  Gait gait;  // its start is set to stand_time by the simulator
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  // heading frame (forward, left) [m/s]
  double yaw_rate = 0.0;                               // [rad/s]
  double height = 0.30;                                // base above the ground [m]
  double swing_height = 0.08;                          // foot lift at mid-swing [m]
  Terrain terrain;
  std::vector<Push> pushes;
  // The friction-aware controller: stance forces within |f_t| <= 0.08 f_n (else 0.6 f_n) and the
  // stance feet damped relative to the base (sim/locomotion_controller.hpp, kd_stance 30 N s/m).
  bool friction_aware = false;
  // The robot's own imperfections (sim/robot_imperfections.hpp): none but in physics-real.
  RobotImperfections robot;
  double stand_time = 1.0;     // still at the start [s]
  double ramp_duration = 1.0;  // speed and turn rate ramp up over this [s]
  double duration = 10.0;      // default length of a run [s]
};

// The scenario called `name` (one of physicsScenarioNames()); throws std::invalid_argument
// naming it and listing the known names otherwise.
PhysicsScenario physicsScenarioByName(const std::string& name);
std::vector<std::string> physicsScenarioNames();
// The imperfections physics-real gives its robot, each with the figure behind it.
RobotImperfections realRobot();

}  // namespace legkit::sim
