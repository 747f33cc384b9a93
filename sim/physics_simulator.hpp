// The physics simulator: the kit's quadruped (model/mjcf.hpp) in MuJoCo, walked by the controller
// of sim/locomotion_controller.hpp, logging what a real robot would log (io/log.hpp, the same
// format as sim/simulator.hpp) plus the true contacts (the contact_truth group).
//
// World: the generated MJCF on a ground plane of the terrain's friction. With patches, a step or
// a ramp the ground is instead tiled with flush boxes (the patch edges, the step and the ramp's
// ends cut it into a grid; each tile has the friction of the patch over it, or the ground's, and
// its top face is the ground's surface there: level, or pitched to the ramp's grade), so a foot
// always stands on exactly one surface; the plane is then switched off (200 m x 200 m of tiles).
// MuJoCo takes the larger friction of two touching geoms: the robot's geoms have friction 0 (they
// never touch each other), so the ground's or the patch's friction is the one that acts. The robot
// starts standing still at the scenario's height, feet under the hips (IK) on level ground at
// z = 0, and settles for 0.5 s (controller running, nothing logged) so that the feet carry the
// weight at t = 0.
//
// Stepping: physics at physics_rate (Euler, Newton, elliptic cone, impratio 10). Every physics step
// runs mj_step1, the controller (on the state of that instant, or the closed loop's estimate, and
// the leg joints' bias forces h of that same state from model/floating_base_dynamics.hpp: the
// controller never reads MuJoCo), the pushes (xfrc_applied on the trunk), then mj_step2. A log row
// k at t_k = k / rate describes the state at t_k and the motion over [t_k, t_k + 1/rate) (rate
// divides physics_rate):
//   IMU       at the "imu" site (the base origin): w = the mean body rate the integrator applied
//             over the interval, a = its mean world acceleration (v_{k+1} - v_k) rate, so that
//             integrating the row from t_k reproduces the true velocity; a_m = R_k^T (a - g),
//             noise and bias random walks exactly as sim/simulator.hpp (model/imu_model.hpp)
//   encoders  q, dq at t_k + N(0, encoder_angle_sigma^2), N(0, encoder_rate_sigma^2)
//   torque    the motor torques applied over the first physics step (after the torque limit)
//             + N(0, torque_sigma^2)
//   force     foot force sensor: clamp(f_n + bias + N(0, sigma^2), 0, saturation)
//   contact   the TRUE contact at t_k: the foot sphere touches any geom with a normal force
//             above kContactThreshold (1 N)
//   ground truth at t_k: base pose and world velocity; per foot the contact flag, normal and
//             tangential force (mj_contactForce rotated with the contact frame, summed over the
//             foot's contacts), the foot point's world velocity and the slip speed (tangential
//             speed of the contact point on the foot, at the contact with the largest normal force)
// Random streams (IMU 1, encoders 2, torque 4, force sensors 5) are drawn from the seed as in
// sim/simulator.cpp. Deterministic: same options, identical log.
//
// Falls: the run stops at the first row where the trunk touches the ground, |roll| or |pitch|
// exceeds 1 rad, or the base is lower than half the scenario's height above the ground; the log
// holds the rows before it and status says when and why. Divergence: MuJoCo 2.2.2 answers a
// non-finite qpos, qvel or qacc by resetting the simulation with only a warning (and a non-finite
// ctrl by zeroing it); any of these warnings ends the run the same way, status.fell and
// status.diverged set, reason "MuJoCo reset the simulation: bad qacc at t = ... s".
#pragma once

#include <string>
#include <vector>

#include "io/log.hpp"
#include "model/imu_model.hpp"
#include "model/imu_noise.hpp"
#include "sim/base_state_source.hpp"
#include "sim/physics_scenario.hpp"

namespace legkit::sim {

struct ForceSensorModel {
  double sigma = 2.0;         // white noise [N]
  double bias = 3.0;          // constant offset [N]
  double saturation = 150.0;  // the reading never exceeds this [N]
};

constexpr double kContactThreshold = 1.0;  // normal force above which a foot is in contact [N]

struct PhysicsOptions {
  PhysicsScenario scenario = physicsScenarioByName("physics-trot");
  double duration = 60.0;        // [s], in (0, 3600]
  double rate = 1000.0;          // log row (IMU) rate [Hz]
  double physics_rate = 2000.0;  // physics step rate [Hz], in [500, 10000], a multiple of rate
  unsigned seed = 1;

  model::ImuNoise imu_noise = model::ImuNoise::go2();
  model::ImuBias initial_bias;
  double encoder_angle_sigma = 1.75e-4;  // [rad] (as sim/simulator.hpp)
  double encoder_rate_sigma = 0.01;      // [rad/s]
  double torque_sigma = 0.1;             // [N m]
  ForceSensorModel force_sensor;
  bool ground_truth = true;  // the ground_truth and contact_truth groups

  // The controller uses this source's R, p, v (and the row's gyro and encoders) once its
  // update() returns true; nullptr: the truth throughout. Not owned.
  BaseStateSource* closed_loop = nullptr;

  // The scenario called `name` with its default duration.
  static PhysicsOptions forScenario(const std::string& name);
  // No sensor noise and no biases (force sensor saturation kept).
  PhysicsOptions& noiseless();
};

struct PhysicsStatus {
  bool fell = false;   // the run failed (a fall, or a divergence): the log stops before time
  double time = 0.0;   // of the fall [s]
  std::string reason;  // "trunk touched the ground", "roll ...", "MuJoCo reset the simulation ..."
  bool diverged = false;  // the failure was MuJoCo's reset on bad numbers, not a fall
};

struct PhysicsResult {
  io::Log log;
  std::vector<model::ImuBias> bias;  // true IMU biases of each row
  PhysicsStatus status;
  // Tracking, over the rows after stand_time + ramp_duration (truth):
  double velocity_rmse = 0.0;  // RMS of |v_xy - commanded v_xy| (world) [m/s]
  Eigen::Vector2d mean_velocity = Eigen::Vector2d::Zero();  // mean heading-frame velocity [m/s]
  double mean_yaw_rate = 0.0;                               // [rad/s]
  double max_tilt = 0.0;  // largest angle between the body z axis and the vertical, all rows [rad]
};

// Runs the scenario. Throws std::invalid_argument naming the option and its value for a friction
// (ground or patch) outside (0, 2], a patch with min >= max or beyond +-100 m, a step higher than
// 0.2 m or beyond +-100 m, a ramp steeper than 0.35 rad, not longer than 0 m or beyond +-100 m, a
// step, ramp start or patch edge within 0.3 m of the starting feet (or a step or ramp behind
// them), a push force non-finite or above 500 N, a push time non-finite or negative or a push
// starting at or after the end of the run, a height outside (0.15, 0.40) m, a swing_height outside
// (0, 0.2] m, a |velocity| above 1.5 m/s, a |yaw_rate| above 2 rad/s, a gait period <= 0, duty
// outside (0, 1] or a non-finite offset, a duration outside (0, 3600] s or giving fewer than 2 rows
// (lround(duration * rate) < 2), a non-positive rate, a physics_rate outside [500, 10000] Hz or not
// a multiple of rate, or a negative noise figure (an unknown scenario name is
// physicsScenarioByName's error). A fall or a divergence is not an exception: see PhysicsStatus.
PhysicsResult simulatePhysics(const PhysicsOptions& options);

}  // namespace legkit::sim
