// The ground reaction at each foot estimated from the joint torques (section 57.6, method 2 for a
// robot without foot sensors). From the equation of motion
//   M(q) nudot + h(q, nu) = S^T tau + J_c^T lambda      (model/floating_base_dynamics.hpp)
// the three rows of leg l read, with the leg's own acceleration neglected,
//   h_l = tau_l + J_l^T lambda_l   =>   lambda_l = J_l^-T (h_l - tau_l) = -(J_l^T)^-1 (tau_l - h_l)
// where h_l are leg l's rows of the bias forces (gravity, Coriolis, centrifugal), J_l = R B_J
// the foot Jacobian's leg columns (world frame) and tau_l the torque that reaches the joint: the
// motor's less the joint's viscous damping D dq_l (QuadrupedInertia::damping), a passive force
// the model keeps out of h. Only leg l's own contact enters its rows, so each
// foot is solved alone from a 3x3 system. lambda_l is the force the ground exerts on the foot,
// world frame: its z component is the normal force on level ground.
//
// The state for h: base attitude R from the previous estimate when it is valid, else roll and
// pitch from the accelerometer (a standing robot measures R^T (0, 0, g); yaw is set to 0, which
// changes neither the z component nor the leg rows of h); omega from the gyro; v from the estimate
// or 0. What the model leaves out shows up as force: the leg's acceleration (a swing leg that
// brakes reads tens of newtons), joint friction, the torque noise mapped through
// J^-T. Measured (tests/contact/detectors_physics_test.cpp, seed 13): standing, within 0.56 N of
// the true normal force on average and the four summing to m g within 0.03 N on average; on the
// 10 s trot, |f_z - f_n| in stance has median 1.0 N and 95th percentile 17 N, and a
// swing foot reads 17 N (median) up to 65 N where the truth is 0. Near a straight knee J is
// singular and J^-T amplifies every torque error without bound: that foot gets the problem "leg
// singular" instead of a huge or NaN force.
//
// Cost: one h(q, nu) by RNEA for the whole robot (microseconds, bench/bench_contact.cpp) plus four
// 3x3 solves. No allocation.
#pragma once

#include <Eigen/Core>
#include <array>

#include "estimation/contact/contact_detector.hpp"
#include "model/floating_base_dynamics.hpp"

namespace legkit::contact {

struct FootForceParams {
  // A leg is singular when |det B_J| / (|c_0| |c_1| |c_2|) (the volume of the Jacobian's columns
  // relative to their lengths: 1 for orthogonal columns, 0 for a straight knee) is below this.
  double min_jacobian_ratio = 0.05;
  double gravity = 9.81;  // [m/s^2]
};

class FootForceFromTorque {
 public:
  // Throws std::invalid_argument for a robot QuadrupedDynamics rejects or min_jacobian_ratio
  // outside [0, 1).
  FootForceFromTorque(const model::QuadrupedGeometry& geometry,
                      const model::QuadrupedInertia& inertia, const FootForceParams& params = {});

  // Per leg (FL FR RL RR): the world-frame ground reaction lambda_l [N], or a NaN vector when it
  // cannot be estimated; then problems[l] (when given) says why, a static string:
  //   "no joint angles"            signals.has_joints is false
  //   "no joint torques"           signals.has_torque is false
  //   "joints not the quadruped's" signals.num_feet is not 4
  //   "base state not finite"     a NaN or infinite gyro, or base R or v when it is valid
  //   "joint state not finite"     a NaN or infinite q or dq of that leg
  //   "joint torque not finite"    a NaN or infinite tau of that leg
  //   "no attitude"                no valid base estimate and no usable accelerometer reading
  //   "leg singular"               the Jacobian ratio above is below min_jacobian_ratio
  // problems[l] is nullptr for a leg that has a force.
  std::array<Eigen::Vector3d, model::kNumLegs> estimate(
      const ContactSignals& signals,
      std::array<const char*, model::kNumLegs>* problems = nullptr) const;

  // The floating-base state the estimate uses for h (attitude, rates, joints) from the signals;
  // false (and x untouched) when there is no attitude to use.
  bool state(const ContactSignals& signals, model::FloatingBaseState& x) const;

  const FootForceParams& params() const { return params_; }

 private:
  model::QuadrupedDynamics dynamics_;
  FootForceParams params_;
  Eigen::Vector3d damping_;  // D per joint of a leg [N m s/rad]
};

// det(J) / (|c_0| |c_1| |c_2|) in [0, 1] for a 3x3 J with columns c_i (0 when a column is zero).
double jacobianRatio(const Eigen::Matrix3d& J);

}  // namespace legkit::contact
