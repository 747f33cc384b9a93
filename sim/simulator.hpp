// The ground-truth simulator: samples a scenario's analytic motion at the IMU rate and writes
// exactly the log a real robot would record (io/log.hpp), plus the true base pose and velocity.
// Deterministic: the same options (and seed) give the same log, bit for bit.
//
// Sensors, per row:
//   IMU       a_m = R^T (a - g) + b_a + n_a, w_m = w + b_g + n_g, biases as random walks
//             (model/imu_model.hpp with model::ImuNoise; Go2 densities by default)
//   encoders  q + N(0, encoder_angle_sigma^2), dq + N(0, encoder_rate_sigma^2)
//   contact   the gait's ideal contact flags (shifted by the contact-offset fault)
//   force     normal ground-reaction force: an approximation, not dynamics. The force that moves
//             the base, m (a - g), is shared equally among the feet in contact; a foot's normal
//             force is the vertical part of its share (zero in swing and flight).
//   torque    tau = -J(q)^T R^T f_i with f_i that same share: the static torque that would hold
//             it (leg inertia ignored).
//   feet      (optional, the robot-agnostic columns) p = FK(q_measured) per foot, covariance
//             sigma_q^2 J J^T + foot_position_sigma^2 I (encoder noise through the Jacobian,
//             plus kinematic-model error); only its diagonal with FootCovariance::kDiagonal.
// Three independent random streams (IMU, encoders, dropouts) are drawn from the seed, so turning
// one noise source off does not change the others.
#pragma once

#include <vector>

#include "io/log.hpp"
#include "model/imu_model.hpp"
#include "model/imu_noise.hpp"
#include "model/quadruped.hpp"
#include "sim/faults.hpp"
#include "sim/scenario.hpp"

namespace legkit::sim {

struct SimOptions {
  Scenario scenario = scenarioByName("trot");
  double duration = 60.0;  // [s]
  double rate = 1000.0;    // IMU (and log row) rate [Hz]
  unsigned seed = 1;

  model::ImuNoise imu_noise = model::ImuNoise::go2();
  model::ImuBias initial_bias;           // biases at t = 0
  double encoder_angle_sigma = 1.75e-4;  // [rad] (about 0.01 deg, the chapter's encoder figure)
  double encoder_rate_sigma = 0.01;      // [rad/s]
  double mass = 15.0;                    // for the approximate force and torque [kg]

  bool torque = true;  // which optional column groups to write
  bool force = true;
  bool contact = true;
  bool ground_truth = true;
  io::FootCovariance foot_columns = io::FootCovariance::kNone;  // body-frame foot columns
  double foot_position_sigma = 1e-3;  // kinematic-model error in those columns' covariance [m]

  Faults faults;

  // No IMU noise, no bias, no encoder noise: readings are the exact kinematic quantities.
  SimOptions& noiseless();
};

struct SimResult {
  io::Log log;
  std::vector<model::ImuBias> bias;  // the true IMU biases of each log row (not in the log)
};

// Throws std::invalid_argument for bad options (non-positive duration or rate, bad fault) and
// std::domain_error if the scenario asks a leg for a foot out of reach.
SimResult simulate(const SimOptions& options,
                   const model::QuadrupedKinematics& kinematics = model::QuadrupedKinematics());

}  // namespace legkit::sim
