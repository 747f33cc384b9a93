// Capstone 57.11.1, piece 3: leg odometry (section 57.3), the base velocity from the stance feet.
#pragma once

#include <Eigen/Core>
#include <array>

#include "io/log.hpp"
#include "model/quadruped.hpp"

namespace ex57_11 {

// One stance foot: v_i = -R (w x r_i + J_i dq_i), with r_i = FK(q_i) the body-frame foot position
// and J_i its Jacobian (model::QuadrupedKinematics), w the body rate [rad/s], R body to world.
Eigen::Vector3d footBaseVelocity(const legkit::model::QuadrupedKinematics& kin, int leg,
                                 const Eigen::Matrix3d& R, const Eigen::Vector3d& w,
                                 const legkit::io::JointVector& q,
                                 const legkit::io::JointVector& dq);

struct LegVelocity {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  // the mean of v_i over the stance feet [m/s]
  int feet = 0;                                 // how many; v is zero when none
};

// The fused velocity: the plain mean over the feet with stance[i] set.
LegVelocity legOdometry(const legkit::model::QuadrupedKinematics& kin, const Eigen::Matrix3d& R,
                        const Eigen::Vector3d& w, const legkit::io::JointVector& q,
                        const legkit::io::JointVector& dq, const std::array<bool, 4>& stance);

}  // namespace ex57_11
