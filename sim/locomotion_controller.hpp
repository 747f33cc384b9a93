// The walking controller of the physics simulator (sim/physics_simulator.hpp). It lives in sim/:
// no estimator ever sees it; it only turns a state (the truth, or an estimate in closed loop) and
// a command into joint torques, the way a robot's own locomotion controller would.
//
// Gait: clock-driven (sim/gait.hpp). A leg whose clock says "stance" is a stance leg, whether or
// not its foot is on the ground yet; the others swing.
//
// Stance: the desired base wrench w = (F, T) (world frame, about the base origin) comes from
//   F = m (a_des - g), with
//     height     a_z = kp_z (z_ground + h - p_z) - kd_z v_z
//     forward    a_x = kv_x (v_x* - v_x) + ki_x int (v_x* - v_x) dt        (heading frame)
//     lateral    a_y = -kp_y y_err + kd_y (v_y* - v_y),  y_err = int (v_y - v_y*) dt
//     standing   (a gait that never lifts a foot) a_xy = -kp_y e - kd_y v_xy, e = p - centre of the
//                feet (heading frame): the base stays over its feet, wherever a push left them
//   T = kp_R .* Log(R_des R^T) + kd_R .* (omega_des - R omega)    (R_des = Rz(yaw*), world)
// and is split over the n stance feet by weighted least squares (WLS, closed form, Eigen LDLT):
//   f = argmin (A f - w)^T S (A f - w) + alpha |f|^2,   A = [I ... I; [r_1]x ... [r_n]x],
// r_i = foot_i - p, S = diag(1, 1, 1, 100, 100, 50): roll and pitch torque weighted 100x the
// forces (without it the trunk rocks), yaw 50x. A foot cannot pull: while some f_i has a negative
// normal component, the foot with the most negative one is dropped and the split redone over the
// others (an active set, at most four solves). Each f_i (the ground's force on foot i) is then
// clamped: f_n <= f_max and |f_t| <= mu_assumed f_n (the friction cone the controller believes in:
// 0.6, the nominal ground, for the naive controller; 0.08 for the friction-aware one), and F's
// horizontal part is limited to mu_assumed F_z before the split, so that the normal forces do not
// balance tangential forces the clamp would remove. Limitation: "normal" and "tangential" here are
// about the world z axis, not the ground's normal. On level ground they coincide; on a ramp of
// angle theta the cone the controller enforces is tilted by theta from the true one, so a force
// it keeps inside mu_assumed can lie outside the true cone (on the uphill side) by about theta:
// the 0.16 rad slope scenario stays well inside mu 0.6, a steep ramp with low friction would not.
// Joint torques tau_i = J_i^T (-f_i - kd_st (v_rel - v_rel*)_xy) + h_i, J_i = R B_J_i(q_i) the
// world-frame foot Jacobian of the leg's joints, h_i the leg joints' bias forces (gravity and
// Coriolis), supplied by the caller. The damping term acts on the foot's horizontal velocity
// relative to the base, v_rel, against the one a planted foot has under the command,
// v_rel* = -(v* + omega* x r_i): zero while the foot sticks and the base follows the command; when
// the feet slide (ice) it carries them along with the base instead of leaving them behind, so a
// pushed robot on ice slides as a whole rather than tipping over its stuck feet. Off by default
// (kd_st = 0): the physics simulator's friction-aware controller sets kd_st = 30 N s/m.
//
// Swing: Cartesian PD on the foot point, tau_i = J_i^T (kp_s (p_d - p_f) + kd_s (v_d - v_f)) + h_i,
// along a quintic from the lift-off point to a Raibert foothold (horizontal parts)
//   p_td = p + v T + Rz(psi + omega* T) n_i + k_r (v - v*),   T = t_touchdown - t + T_stance / 2,
// n_i the nominal foot under the hip (body frame), psi the heading: where the hip will be at the
// middle of the next stance, plus the speed-error correction. The lift is swing_height
// 64 s^3 (1 - s)^3 (as in sim/quadruped_motion.hpp). Each leg remembers the ground height it
// stood on at its last lift-off: that is its foothold height, and z_ground is their mean.
//
// Gains (ControllerGains, defaults): kp_z 100 1/s^2, kd_z 20 1/s, kv_x 6 1/s, ki_x 6 1/s^2,
// kp_y 30 1/s^2, kd_y 8 1/s, kp_R (150, 300, 60) N m/rad, kd_R (8, 16, 6) N m s/rad,
// kp_s 600 N/m, kd_s 20 N s/m, kd_st 0, k_r 0.1 s, f_max 250 N, alpha 1e-4. No heap
// allocation per call.
#pragma once

#include <Eigen/Core>
#include <array>

#include "io/log.hpp"
#include "model/floating_base_dynamics.hpp"
#include "model/quadruped.hpp"
#include "sim/gait.hpp"

namespace legkit::sim {

// What the controller believes about the robot: the floating-base state of model/ (base R, p, v
// world, omega body, joint angles and rates), so that its leg bias forces come straight from
// model::QuadrupedDynamics.
using ControllerState = model::FloatingBaseState;

// What the robot is asked to do.
struct LocomotionCommand {
  Gait gait;                                           // its start is when stepping begins
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  // heading frame (forward, left) [m/s]
  double yaw_rate = 0.0;                               // [rad/s]
  double height = 0.30;                                // base above the ground [m]
  double swing_height = 0.08;                          // foot lift at mid-swing [m]
  double ramp_duration = 1.0;  // speed and turn rate ramp up smoothly from gait.start [s]
  double mu_assumed = 0.6;     // friction cone the stance forces respect
};

struct ControllerGains {
  double kp_z = 100.0, kd_z = 20.0;            // height [1/s^2], [1/s]
  double kv_x = 6.0, ki_x = 6.0;               // forward speed [1/s], [1/s^2]
  double kp_y = 30.0, kd_y = 8.0;              // lateral [1/s^2], [1/s]
  Eigen::Vector3d kp_R{150.0, 300.0, 60.0};    // attitude, world axes [N m/rad]
  Eigen::Vector3d kd_R{8.0, 16.0, 6.0};        // [N m s/rad]
  Eigen::Matrix<double, 6, 1> wrench_weight =  // S of the WLS
      (Eigen::Matrix<double, 6, 1>() << 1, 1, 1, 100, 100, 50).finished();
  double alpha = 1e-4;                       // force regularisation of the WLS
  double f_max = 250.0;                      // normal force limit per foot [N]
  double kp_swing = 600.0, kd_swing = 20.0;  // swing foot PD [N/m], [N s/m]
  double kd_stance = 0.0;  // stance foot damping, velocity relative to the base [N s/m]
  double k_raibert = 0.1;  // foothold speed-error gain [s]
};

class LocomotionController {
 public:
  // mass: the whole robot's [kg]; initial: the state at t = 0 (sets the heading, the ground).
  LocomotionController(const model::QuadrupedKinematics& kinematics, double mass,
                       const LocomotionCommand& command, const ControllerState& initial,
                       const ControllerGains& gains = {});

  // Joint torques (index 3 * leg + joint) at time t. leg_bias: gravity + Coriolis of the leg
  // joints at the state s. Calls must come with non-decreasing t (the integral terms advance by
  // the difference, counted from t = 0 only: a robot may settle at negative times first and start
  // at t = 0 with zero integrals).
  io::JointVector torques(double t, const ControllerState& s, const io::JointVector& leg_bias);

  // The stance flags and ground forces (world, on each foot) of the last call.
  const std::array<bool, model::kNumLegs>& stance() const { return stance_; }
  const std::array<Eigen::Vector3d, model::kNumLegs>& forces() const { return f_; }

 private:
  Eigen::Matrix<double, 6, 1> desiredWrench(double t, double dt, const ControllerState& s);
  void distribute(const ControllerState& s, const Eigen::Matrix<double, 6, 1>& wrench);
  Eigen::Vector3d foothold(int leg, double t, double touchdown, const ControllerState& s) const;

  model::QuadrupedKinematics kinematics_;
  double mass_;
  LocomotionCommand command_;
  ControllerGains gains_;
  std::array<Eigen::Vector3d, model::kNumLegs> nominal_;  // nominal foot under the hip, body xy

  double t_last_;
  double yaw_des_;               // integral of the commanded yaw rate [rad]
  double v_error_integral_ = 0;  // forward speed error integral [m]
  double lateral_error_ = 0;     // lateral drift off the commanded path [m]
  Eigen::Vector3d v_cmd_world_ = Eigen::Vector3d::Zero();  // commanded base velocity, world
  double yaw_rate_cmd_ = 0;                                // commanded yaw rate (ramped)
  std::array<double, model::kNumLegs> ground_;             // ground height under each leg [m]
  std::array<Eigen::Vector3d, model::kNumLegs> lift_off_;  // foot point at the last lift-off
  std::array<bool, model::kNumLegs> stance_;
  std::array<Eigen::Vector3d, model::kNumLegs> foot_p_, foot_v_;  // world, this call
  std::array<Eigen::Matrix3d, model::kNumLegs> J_;                // world foot Jacobians
  std::array<Eigen::Vector3d, model::kNumLegs> f_;
};

}  // namespace legkit::sim
