// The full analytic motion of a quadruped in one scenario: the base (sim/base_trajectory.hpp),
// every foot in the world, and from them the joint angles and rates a perfect encoder would read.
//
// Feet: each stance has a foothold fixed on flat ground (z = 0, so the foot-sphere centre sits
// foot_radius above it). Stance 0 is the initial stand under the start pose; the foothold of
// every later stance is the nominal foot position (below the hip, abduction offset outward)
// carried by the base's position and heading at the middle of that stance, so the legs swing
// symmetrically about the hips. In stance the foot does not move (unless a slip fault moves it);
// in swing it follows a quintic from lift-off to the next foothold (zero velocity and
// acceleration at touchdown) with a smooth lift of swing_height.
// Joints: q = IK(R^T (p_foot - p)); dq = J(q)^-1 * (body-frame foot velocity relative to the
// body), where that velocity is R^T (v_foot - v) - w x (R^T (p_foot - p)).
#pragma once

#include <Eigen/Core>
#include <array>

#include "model/quadruped.hpp"
#include "sim/base_trajectory.hpp"
#include "sim/faults.hpp"
#include "sim/scenario.hpp"

namespace legkit::sim {

struct FootState {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();  // foot point (sphere centre), world [m]
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  // its velocity, world [m/s]
  bool contact = true;                          // true contact (ideal timing)
};

struct JointState {
  Eigen::Vector3d q = Eigen::Vector3d::Zero();       // joint angles [rad]
  Eigen::Vector3d dq = Eigen::Vector3d::Zero();      // joint rates [rad/s]
  Eigen::Vector3d p_body = Eigen::Vector3d::Zero();  // foot in the body frame [m]
  Eigen::Vector3d v_body = Eigen::Vector3d::Zero();  // its velocity relative to the body [m/s]
};

class QuadrupedMotion {
 public:
  QuadrupedMotion(const Scenario& scenario, const model::QuadrupedKinematics& kinematics,
                  const SlipFault& slip = {});

  BaseState base(double t) const { return base_.at(t); }
  FootState foot(int leg, double t) const;
  // Joint state of one leg given the base state at the same instant. Throws std::domain_error
  // (from the IK) if the motion asks for a foot out of the leg's reach.
  JointState joints(int leg, const BaseState& base, const FootState& foot) const;

  // Foothold of stance `index` of `leg` (world, the foot point's position) before any slip.
  Eigen::Vector3d foothold(int leg, int index) const;

  const Scenario& scenario() const { return scenario_; }
  const model::QuadrupedKinematics& kinematics() const { return kinematics_; }

 private:
  // How far a slip has moved the foot of `leg` between `from` and `t` (stance only).
  Eigen::Vector3d slipDisplacement(int leg, double from, double t) const;
  Eigen::Vector3d slipVelocity(int leg, double t) const;

  Scenario scenario_;
  BaseTrajectory base_;
  model::QuadrupedKinematics kinematics_;
  SlipFault slip_;
  std::array<Eigen::Vector3d, model::kNumLegs> nominal_;  // nominal foot, body frame, on ground
};

}  // namespace legkit::sim
