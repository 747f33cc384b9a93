#pragma once
// The parameters the three filters of section 57.5 share (the ESKF, the invariant EKF and the
// TSIF: base, IMU biases and stance feet in one state), one block for the family; each filter's
// own Params adds only what is its alone. Read from the settings file's imu, feet, priors, limits
// and gating sections (estimation/estimators.cpp).

#include <Eigen/Core>
#include <cmath>
#include <stdexcept>
#include <string>

#include "estimation/engineering/gating.hpp"
#include "estimation/health.hpp"
#include "estimation/health_guard.hpp"
#include "model/imu_model.hpp"
#include "model/imu_noise.hpp"

namespace legkit::invariant {

struct FilterParams {
  model::ImuNoise imu = model::ImuNoise::go2();  // continuous densities (the simulator's)
  // A stance foot's slip random walk [m/sqrt(s)]. The simulator's feet do not slip; 1 mm/sqrt(s)
  // is a small allowance for a real robot's. (0.01 makes the ESKF visibly under-confident on
  // the default trot: ANEES 5.6 for 9 dof in the 20-run study of its NEES test, bounds
  // [7.24, 10.95].)
  double foot_stance_density = 1e-3;
  // A swing foot's random walk [m/sqrt(s)], the other end of the soft density of a held foot with
  // p_c < 1 (the filters' file comments, section 57.6): a swing foot moves ~0.1 m in 0.2 s, well
  // inside 2 * sqrt(0.2) = 0.9 m.
  double foot_swing_density = 2.0;
  // Whether stance feet may correct the heading (yaw and the gyro bias about the vertical):
  // false, the heading rule (the default: each filter's file comment); true, the plain filter.
  bool feet_correct_yaw = false;
  // How much of the rule a foot update gets (heading_rule.hpp): all of it while the robot turns
  // at heading_turn_rate or faster (the bias-corrected yaw rate low-passed over
  // heading_turn_time) or a foot is accused of slipping, none of it while it walks straight; 0
  // keeps the whole rule always. Measured on the physics scenarios' truth (world yaw rate of the
  // gyro, chapter 57.5 "Its share by the turn rate"): a straight trot's gait sways it by 0.11
  // rad/s (median; 0.34 at the 95th percentile), the 1 s low-pass leaves 0.009 (median), 0.015
  // (90th) and 0.047 at most on physics-trot, -walk, -slope, -step-down and -push, and 0.38-0.51
  // on the turns (physics-turn, physics-real). 0.05 rad/s is above every straight walk and a
  // tenth of the turns.
  double heading_turn_rate = 0.05;  // [rad/s]
  double heading_turn_time = 1.0;   // [s], more than two trot or walk gait cycles
  // Flat feet (settings feet.flat and feet.rotation_stance_density; each filter's "Flat feet"):
  // the ESKF, the InEKF and the TSIF also estimate each stance foot's orientation and use the
  // measured R_BF of its ContactMeasurement; at most two feet (a humanoid's). The linear KF uses
  // the feet as points.
  bool flat_feet = false;
  double foot_rotation_stance_density = 4e-3;  // [rad/sqrt(s)] (settings.hpp says why)
  // A sole's rotation random walk in swing [rad/sqrt(s)], the p_c = 0 end of its soft density
  // (57.6), as foot_swing_density is the position's. A physical bound, not fitted: an ankle turns
  // a swinging foot by a few tenths of a radian in a 0.2 s swing, inside 1 * sqrt(0.2) = 0.45 rad
  // (1 sigma). Not measured on a log: every touchdown places the sole afresh from its measurement
  // (R_F = R Z, its rows of P from Z and rot_cov), so this density decides only how much a foot
  // in contact with p_c < 1 keeps of its sole: on the iCub, during the 80 ms of touchdown
  // settling (p_c 0 until it ends).
  double foot_rotation_swing_density = 1.0;
  // Prior of the state at reset (standard deviations; attitude per axis).
  double sigma_attitude = 0.01;    // [rad]
  double sigma_velocity = 0.05;    // [m/s]
  double sigma_position = 0.01;    // [m]
  double sigma_gyro_bias = 0.002;  // [rad/s]
  double sigma_accel_bias = 0.02;  // [m/s^2]
  Eigen::Vector3d gravity = model::gravity();
  InputLimits limits;  // sensor ranges and the largest dt integrated (estimation/health.hpp)
  engineering::GatingParams gating;  // innovation gate of the foot updates (each filter's file)
};

// The family's contract: every density finite and non-negative, and positive where the filter
// weighs by its inverse (densities_positive: the TSIF, its white noise and feet); a zero bias
// random walk is a constant bias. Every prior sigma finite and positive, gravity finite, limits
// as checkLimits wants. Throws std::invalid_argument naming `who`, the field and its value.
inline void checkFilterParams(const FilterParams& p, const char* who, bool densities_positive) {
  const auto require = [who](double value, const char* what, bool positive) {
    if (std::isfinite(value) && (positive ? value > 0.0 : value >= 0.0)) return;
    throw std::invalid_argument(std::string(who) + ": " + what + " must be finite and " +
                                (positive ? "positive" : "non-negative") + ", got " +
                                std::to_string(value));
  };
  require(p.imu.gyro_noise_density, "gyro noise density", densities_positive);
  require(p.imu.accel_noise_density, "accelerometer noise density", densities_positive);
  require(p.imu.gyro_bias_random_walk, "gyro bias random walk", false);
  require(p.imu.accel_bias_random_walk, "accelerometer bias random walk", false);
  require(p.foot_stance_density, "foot_stance_density", densities_positive);
  require(p.foot_swing_density, "foot_swing_density", densities_positive);
  require(p.foot_rotation_stance_density, "foot_rotation_stance_density", false);
  require(p.foot_rotation_swing_density, "foot_rotation_swing_density", false);
  require(p.heading_turn_rate, "heading_turn_rate", false);
  require(p.heading_turn_time, "heading_turn_time", true);
  require(p.sigma_attitude, "prior sigma_attitude", true);
  require(p.sigma_velocity, "prior sigma_velocity", true);
  require(p.sigma_position, "prior sigma_position", true);
  require(p.sigma_gyro_bias, "prior sigma_gyro_bias", true);
  require(p.sigma_accel_bias, "prior sigma_accel_bias", true);
  if (!p.gravity.allFinite()) {
    throw std::invalid_argument(std::string(who) + ": gravity is not finite");
  }
  checkLimits(p.limits, who);
}

}  // namespace legkit::invariant
