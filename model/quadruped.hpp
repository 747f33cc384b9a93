// Kinematics of a Go2-class quadruped leg (section 57.3): forward kinematics of each foot in the
// body frame, its analytic Jacobian with respect to the three joint angles, and inverse
// kinematics on the knee-backward branch.
//
// Frames: the body frame is the IMU frame (x forward, y left, z up). Every leg is a chain of
// three revolute joints: hip abduction about the body x axis (through the hip point), hip flexion
// about the thigh's y axis, knee flexion about the calf's y axis. In the zero configuration the
// thigh and the calf hang straight down. The "foot point" is the centre of the foot sphere; the
// ground contact point lies foot_radius below it on flat ground.
//
// Geometry is data (QuadrupedGeometry), so that a user can load their own robot's numbers.
#pragma once

#include <Eigen/Core>
#include <array>

namespace legkit::model {

// Legs in the project's order; the value is the leg id used everywhere (logs, contacts).
enum Leg : int { FL, FR, RL, RR };
constexpr int kNumLegs = 4;

// Name of a leg id ("FL", ...); throws std::invalid_argument for an id outside 0..3.
const char* legName(int leg);

// +1 for the left legs (FL, RL), -1 for the right legs (FR, RR): the sign of the lateral offsets.
double lateralSign(int leg);

struct QuadrupedGeometry {
  // Position of each hip (the abduction axis) in the body frame [m], indexed by Leg.
  std::array<Eigen::Vector3d, kNumLegs> hip_offset;
  // Lateral distance from the abduction axis to the thigh plane, outward positive [m]
  // (applied as +y for left legs, -y for right legs, before the abduction rotation).
  double abduction_offset = 0.0;
  double thigh_length = 0.0;  // hip-flexion axis to knee axis [m]
  double calf_length = 0.0;   // knee axis to the centre of the foot sphere [m]
  double foot_radius = 0.0;   // radius of the foot sphere [m]
  // Joint limits per leg, (abduction, hip flexion, knee) [rad].
  std::array<Eigen::Vector3d, kNumLegs> q_min;
  std::array<Eigen::Vector3d, kNumLegs> q_max;

  // Unitree Go2-class numbers (hips at (+-0.1934, +-0.0465, 0), links of 0.213 m).
  static QuadrupedGeometry go2();

  // True when every joint angle of q lies within the leg's limits (inclusive, with tolerance).
  bool withinLimits(int leg, const Eigen::Vector3d& q, double tol = 0.0) const;
};

class QuadrupedKinematics {
 public:
  explicit QuadrupedKinematics(const QuadrupedGeometry& g = QuadrupedGeometry::go2());

  // Body-frame position of the foot point, B_p_f = FK(q) (chapter eq. for B_p_{f_i}).
  Eigen::Vector3d footPosition(int leg, const Eigen::Vector3d& q) const;

  // Body-frame foot Jacobian B_J = d FK / dq (3x3, analytic): the foot velocity relative to the
  // body, expressed in the body frame, is B_J * qdot.
  Eigen::Matrix3d footJacobian(int leg, const Eigen::Vector3d& q) const;

  // Joint angles that put the foot point at p_body (body frame). Solves on the Go2 branch: knee
  // angle negative (knee pointing backward) and the foot below the hip-flexion axis in the leg's
  // own frame. Throws std::domain_error naming the leg and the point when no solution on that
  // branch exists within the joint limits.
  Eigen::Vector3d inverseKinematics(int leg, const Eigen::Vector3d& p_body) const;

  const QuadrupedGeometry& geometry() const { return g_; }

 private:
  QuadrupedGeometry g_;
};

}  // namespace legkit::model
