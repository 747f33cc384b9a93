// Floating-base dynamics of the kit's quadruped: the mass matrix M(q) by the composite rigid body
// algorithm (CRBA) and the bias forces h(q, nu) by recursive Newton-Euler (RNEA), in the spatial
// algebra of model/spatial.hpp. Appendix: chapters/00-floating-base-dynamics.md.
//
// The equation of motion (chapter 57's prerequisite, written for the velocity nu):
//   M(q) nudot + h(q, nu) = S^T tau + J_c^T lambda
// with the terms
//   M             the 18x18 mass matrix, symmetric positive definite: the kinetic energy is
//                 T = 1/2 nu^T M nu;
//   h             the bias forces, gravity plus the velocity-product (Coriolis and centrifugal)
//                 terms: what the joints and the base would have to supply for nudot = 0;
//   S^T tau       the 12 motor torques; S = [0_{12x6} 1_{12}] selects the joints: no motor acts
//                 on the base, which is why its 6 rows have no tau (it is "floating");
//   J_c^T lambda  the contact forces lambda (world frame, 3 per foot in contact), mapped through
//                 the foot Jacobian J_c of footJacobian() (foot velocity = J_c nu, so by virtual
//                 power a foot force lambda does the generalized work J_c^T lambda).
//
// Coordinates, in MuJoCo's order so that the mapping to a MuJoCo model with a free joint
// (model/mjcf.hpp) is the identity: configuration (p, R, q), velocity
//   nu = (v, omega, dq), 18 numbers:
//   v     velocity of the base origin (the IMU frame's origin), WORLD frame  (MuJoCo qvel[0..2]),
//   omega angular velocity of the base, BODY frame                          (MuJoCo qvel[3..5]),
//   dq    the 12 joint rates in the kit's joint order (3 * leg + joint)     (MuJoCo qvel[6..17]).
// So M is MuJoCo's mj_fullM(qM) and h its qfrc_bias, entry for entry.
//
// The algorithms work with body-frame spatial velocities (model/spatial.hpp, (angular, linear)).
// The base's is V_0 = (omega, R^T v) = Phi nu_b with nu_b = (v, omega) and
//   Phi = [[0, 1], [R^T, 0]]        (the free joint's motion subspace, in the base frame).
// Phi depends on R, so differentiating V_0 = Phi nu_b gives an extra acceleration:
//   a_0 = Phi nudot_b + (0, d/dt(R^T) v) = Phi nudot_b + (0, -omega x R^T v)
// (d/dt R^T = -[omega]x R^T). RNEA starts from that a_0; this term is the only place where the
// free joint's mixed world/body coordinates show up in h. Generalized forces on the base are
// Phi^T F = (R f, n) for a body-frame spatial force F = (n, f): the world force, then the
// body-frame moment about the base origin (power F . Phi nu_b = (Phi^T F) . nu_b).
//
// Armature (the rotor inertia seen through the gearbox) is added to the joints' diagonal of M
// only, as MuJoCo does; joint damping is a passive force, in neither M nor h.
//
// Fixed-size Eigen throughout: no call allocates.
#pragma once

#include <Eigen/Core>
#include <array>

#include "model/quadruped.hpp"
#include "model/quadruped_inertia.hpp"
#include "model/spatial.hpp"

namespace legkit::model {

constexpr int kNumJointDof = 3 * kNumLegs;  // 12 joint rates
constexpr int kNumDof = 6 + kNumJointDof;   // 18 generalized velocities
using GeneralizedVector = Eigen::Matrix<double, kNumDof, 1>;
using GeneralizedMatrix = Eigen::Matrix<double, kNumDof, kNumDof>;
using ContactJacobian = Eigen::Matrix<double, 3, kNumDof>;
using JointVector12 = Eigen::Matrix<double, kNumJointDof, 1>;  // index 3 * leg + joint

// The robot's configuration and velocity in the coordinates above. R must be a rotation matrix
// (not checked: orthonormalize an integrated attitude before use).
struct FloatingBaseState {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();      // base origin, world [m]
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // base attitude, body to world
  Eigen::Vector3d v = Eigen::Vector3d::Zero();      // base origin velocity, world [m/s]
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();  // base angular velocity, body [rad/s]
  JointVector12 q = JointVector12::Zero();          // joint angles [rad]
  JointVector12 dq = JointVector12::Zero();         // joint rates [rad/s]

  // nu = (v, omega, dq).
  GeneralizedVector nu() const;
};

class QuadrupedDynamics {
 public:
  // gravity: magnitude of g [m/s^2], pointing along -z of the world. Throws std::invalid_argument
  // for a geometry QuadrupedKinematics rejects, a link with a negative or non-finite mass, a
  // non-finite inertia, a negative armature or a non-finite gravity.
  QuadrupedDynamics(const QuadrupedGeometry& geometry, const QuadrupedInertia& inertia,
                    double gravity = 9.81);

  // M(q) by CRBA, armature included (it depends on R and q only; p and the velocities are unused).
  GeneralizedMatrix massMatrix(const FloatingBaseState& x) const;

  // h(q, nu) by RNEA with nudot = 0: gravity, Coriolis and centrifugal forces.
  GeneralizedVector biasForces(const FloatingBaseState& x) const;

  // J_c of one foot point (centre of the foot sphere): its world-frame velocity is J_c nu,
  //   J_c = [1, -R [B_p_f]x, R B_J (in the leg's 3 columns)],
  // from pdot_f = v + R (omega x B_p_f + B_J dq_leg) with B_p_f, B_J of model/quadruped.hpp.
  // Throws std::invalid_argument for a leg outside 0..3.
  ContactJacobian footJacobian(int leg, const FloatingBaseState& x) const;

  const QuadrupedKinematics& kinematics() const { return kin_; }

 private:
  // The base is body 0; leg l's hip, thigh and calf are bodies 1 + 3 l + (0, 1, 2), whose joint
  // is generalized velocity 5 + body.
  static constexpr int kNumBodies = 1 + kNumJointDof;

  // Placement of body i in its parent at joint angle qi: origin joint_origin_[i], turned by qi
  // about the joint axis.
  spatial::Transform placement(int i, double qi) const;

  QuadrupedKinematics kin_;
  std::array<int, kNumBodies> parent_{};                  // parent body (-1 for the base)
  std::array<int, kNumBodies> axis_{};                    // joint axis of body i: 0 = x, 1 = y
  std::array<Eigen::Vector3d, kNumBodies> joint_origin_;  // body i's origin in its parent
  std::array<spatial::RigidBodyInertia, kNumBodies> I_;   // spatial inertia of body i, own frame
  JointVector12 armature_ = JointVector12::Zero();        // [kg m^2]
  Eigen::Vector3d g_;                                     // gravity, world [m/s^2]
};

}  // namespace legkit::model
