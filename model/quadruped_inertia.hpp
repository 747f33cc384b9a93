// Mass properties and joint drive figures of the Go2-class quadruped (issue 12: the one source of
// truth that the MJCF generator (mjcf.hpp) and the floating-base dynamics both read).
//
// Link frames, matching QuadrupedKinematics (quadruped.hpp) exactly (x forward, y left, z up):
//   trunk:            the body (IMU) frame,
//   hip link of leg i: origin hip_offset[i] in the body frame, rotated Rx(q_abduction),
//   thigh link:       origin (0, s * abduction_offset, 0) in the hip frame, then Ry(q_hip),
//   calf link:        origin (0, 0, -thigh_length) in the thigh frame, then Ry(q_knee),
//   foot point:       (0, 0, -calf_length) in the calf frame (centre of the foot sphere),
// with s = lateralSign(leg). The calf's mass properties include the foot.
#pragma once

#include <Eigen/Core>
#include <array>

#include "model/quadruped.hpp"

namespace legkit::model {

struct LinkInertia {
  double mass = 0.0;                              // [kg]
  Eigen::Vector3d com = Eigen::Vector3d::Zero();  // centre of mass in the link frame [m]
  // Inertia about the centre of mass, in link-frame axes [kg m^2].
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
};

struct QuadrupedInertia {
  LinkInertia trunk;  // in the body (IMU) frame
  std::array<LinkInertia, kNumLegs> hip, thigh,
      calf;  // each in its link frame; calf holds the foot
  // Per joint (abduction, hip flexion, knee), the same for every leg:
  Eigen::Vector3d torque_limit = Eigen::Vector3d::Zero();  // motor torque limit [N m]
  Eigen::Vector3d armature = Eigen::Vector3d::Zero();      // reflected rotor inertia [kg m^2]
  Eigen::Vector3d damping = Eigen::Vector3d::Zero();       // viscous joint damping [N m s/rad]

  // Sum of the trunk's and the twelve leg links' masses [kg].
  double totalMass() const;

  // The Unitree Go2's public figures (the trunk and the front-left leg of its published MJCF,
  // diagonal inertia + principal-axes quaternion turned into full matrices), mirrored for the
  // other legs as the published model does: y -> -y for the right legs, and x -> -x for the rear
  // hip links (rear thighs and calves equal the front ones). 15.206 kg in all.
  static QuadrupedInertia go2();
};

}  // namespace legkit::model
