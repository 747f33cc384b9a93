// MJCF (MuJoCo's XML model format) of the kit's quadruped, generated from the same data that the
// analytic model uses (QuadrupedGeometry, QuadrupedInertia), so that analytic kinematics and
// dynamics and the physics simulation describe one robot. A pure string generator: no MuJoCo
// include here (model/mujoco.hpp loads the string).
//
// Names in the generated model:
//   body "base" with a free joint "base": qpos[0..2] = base position (world), qpos[3..6] = base
//     attitude quaternion (w, x, y, z); qvel[0..2] = linear velocity (world frame),
//     qvel[3..5] = angular velocity (BODY frame);
//   hinge joints "<LEG>_abduction", "<LEG>_hip", "<LEG>_knee" in leg order FL FR RL RR, so that
//     qpos[7 + 3 leg + j] and qvel[6 + 3 leg + j] are joint j of leg (bodies "<LEG>_hip",
//     "<LEG>_thigh", "<LEG>_calf" carry them);
//   sites "imu" (body origin, identity) and "<LEG>_foot" (the foot point of quadruped.hpp);
//   geoms "trunk" (box), "<LEG>_thigh" and "<LEG>_calf" (capsules), "<LEG>_foot" (sphere of
//     foot_radius) and "ground" (plane): only these robot geoms collide, only with world geoms
//     (ground and extra_worldbody), never with each other;
//   motor actuators "<LEG>_abduction", ... in the joint order (ctrl[3 leg + j]), gear 1,
//     ctrlrange +-torque_limit;
//   Euler integrator, Newton solver, elliptic friction cone, impratio 10.
#pragma once

#include <Eigen/Core>
#include <string>

#include "model/quadruped.hpp"
#include "model/quadruped_inertia.hpp"

namespace legkit::model {

struct MjcfOptions {
  double timestep = 0.0005;      // physics step [s]
  double gravity = 9.81;         // magnitude of gravity, along world -z [m/s^2]
  double ground_friction = 0.6;  // sliding friction of the ground plane
  // Sliding friction of every robot geom: low, so that the ground or a patch decides (MuJoCo uses
  // the larger of the two geoms' coefficients).
  double foot_friction = 0.05;
  std::string extra_worldbody;  // MJCF elements put inside <worldbody> (terrain: patches, steps)
  Eigen::Vector3d base_position{0.0, 0.0, 0.35};  // initial base position (qpos0) [m]
};

// The MJCF document of the robot on a ground plane. Numbers are written with 17 significant
// digits, so the model holds the very doubles of geometry and inertia. Throws
// std::invalid_argument naming the first bad field: a non-positive timestep, a negative or
// non-finite gravity or friction, a non-finite base position, non-finite or non-positive link
// lengths or foot radius, non-finite hip offsets or joint limits with q_min > q_max, a
// non-positive or non-finite mass, a non-finite centre of mass, an inertia that is not finite,
// symmetric and positive definite, negative or non-finite torque limits, armature or damping.
// Each link's <inertial> is its QuadrupedInertia (never geom-derived) in principal form: moments
// and axes from Eigen's eigensolver, so that MuJoCo's body_inertia / body_iquat give the given
// matrix back to rounding (MJCF's fullinertia goes through MuJoCo's iterative diagonalisation,
// which is off by ~1e-6 relative).
std::string quadrupedMjcf(const QuadrupedGeometry& geometry, const QuadrupedInertia& inertia,
                          const MjcfOptions& options = {});

}  // namespace legkit::model
