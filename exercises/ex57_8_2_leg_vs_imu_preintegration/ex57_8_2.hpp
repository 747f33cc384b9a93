// Exercise 57.8.2: leg-odometry preintegration against IMU preintegration (VILENS, section 57.8).
// The discussion goes in answer.md; the code is the leg side: the base velocity the legs measure,
// preintegrated between two keyframes with a velocity bias b_v, and what that bias does to a leg-
// length error.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "lie/so3.hpp"

namespace ex57_8_2 {

// One sample between keyframes i and j, held over dt: the bias-corrected gyro rate and the base
// velocity measured by the legs in stance (kinematics), both in the body frame.
struct LegSample {
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();  // [rad/s]
  Eigen::Vector3d v = Eigen::Vector3d::Zero();      // [m/s]
  double dt = 0.0;                                  // [s]
};

// The leg odometry between keyframes i and j, preintegrated at the velocity bias b_v_lin, in the
// body frame of keyframe i (the keyframes' states do not enter it):
//   dR_i,k+1 = dR_ik Exp(omega_k dt_k)                      (dR_ii = I)
//   dp_ij    = sum_k dR_ik (v_k - b_v_lin) dt_k             (the rotation BEFORE sample k)
//   dp_db_v  = d(dp_ij)/d(b_v) = -sum_k dR_ik dt_k
// so that the keyframe constraint is R_i^T (p_j - p_i) = dp_ij(b_v).
struct LegDelta {
  lie::SO3d dR;                                       // dR_ij
  Eigen::Vector3d dp = Eigen::Vector3d::Zero();       // [m]
  Eigen::Matrix3d dp_db_v = Eigen::Matrix3d::Zero();  // [s]
  Eigen::Vector3d b_v_lin = Eigen::Vector3d::Zero();  // [m/s]
};

LegDelta preintegrate(const std::vector<LegSample>& samples, const Eigen::Vector3d& b_v);

// dp_ij at another bias without integrating again, through the Jacobian:
//   dp_ij(b_v) = dp + dp_db_v (b_v - b_v_lin).
Eigen::Vector3d correctedDelta(const LegDelta& d, const Eigen::Vector3d& b_v);

// The velocity bias that makes the leg odometry agree with the positions of keyframes i and j
// (e.g. two exteroceptive poses): solves R_i^T (p_j - p_i) = dp_ij(b_v) for b_v. Throws
// std::invalid_argument when dp_db_v is singular (no time between the keyframes).
Eigen::Vector3d velocityBiasFromPoses(const LegDelta& d, const lie::SO3d& R_i,
                                      const Eigen::Vector3d& p_i, const Eigen::Vector3d& p_j);

}  // namespace ex57_8_2
