// The legs of any robot, seen from its base: each foot's position in the base frame and its
// Jacobian with respect to the robot's joints. Two implementations: the analytic Go2-class
// quadruped of model/quadruped.hpp (the teaching model) and a robot described by its own URDF or
// MJCF, through MuJoCo's kinematics (model/mujoco_kinematics.hpp).
#pragma once

#include <Eigen/Core>
#include <string>

namespace legkit::model {

constexpr int kMaxLegJoints = 24;  // joints a LegKinematics may have (io::kMaxJoints)
using LegJointVector = Eigen::Matrix<double, kMaxLegJoints, 1>;  // entries >= numJoints() unused
using FootJacobian = Eigen::Matrix<double, 3, kMaxLegJoints>;    // columns >= numJoints() zero

class LegKinematics {
 public:
  virtual ~LegKinematics() = default;
  virtual int numFeet() const = 0;
  virtual int numJoints() const = 0;
  virtual std::string footName(int foot) const = 0;
  // The model's name of leg joint `joint` (the log's column joint<k>_q, or q_<leg>_<j>).
  virtual std::string jointName(int joint) const = 0;
  // The robot's total mass as its model gives it (the sum of its bodies' masses) [kg].
  virtual double mass() const = 0;
  // Foot `foot`'s point in the base frame at joint angles q [m], and its Jacobian d p / d q
  // (so that the foot's velocity relative to the base is J dq). No allocation. Not thread-safe
  // for the MuJoCo implementation (it owns one mjData).
  virtual void foot(int foot, const LegJointVector& q, Eigen::Vector3d& p_B,
                    FootJacobian& J) const = 0;
  // A flat foot's orientation (section 57.5, flat feet): the rotation R_BF of the foot's frame
  // into the base frame at joint angles q, and its rotational Jacobian J_w, the foot's angular
  // velocity relative to the base in the base frame being J_w dq. False (nothing written) for a
  // model whose feet are points (the analytic quadruped).
  virtual bool footRotation(int /*foot*/, const LegJointVector& /*q*/, Eigen::Matrix3d& /*R_BF*/,
                            FootJacobian& /*J_w*/) const {
    return false;
  }
};

}  // namespace legkit::model
