// Exercise 57.3.1: the base velocity seen by the front-right (FR) foot of a Go2, written out
// explicitly in the joint angles q1..q3, the joint rates dq1..dq3 and the body angular rate w.
#pragma once

#include <Eigen/Core>

namespace ex57_3_1 {

// FR leg of the Go2 (body frame: x forward, y left, z up; the foot point is the centre of the
// foot sphere). Joints: q1 hip abduction about body x, q2 hip flexion and q3 knee about the
// thigh's / calf's y axis; at q = 0 the leg hangs straight down.
constexpr double kHipX = 0.1934;       // hip position in the body frame [m]
constexpr double kHipY = -0.0465;      //   (FR is a right leg: negative y)
constexpr double kAbduction = 0.0955;  // hip-to-thigh lateral offset, outward (here -y) [m]
constexpr double kThigh = 0.213;       // l1 [m]
constexpr double kCalf = 0.213;        // l2 [m]

// Body-frame position r(q) of the FR foot, as explicit expressions in sin/cos of q1, q2, q2+q3.
Eigen::Vector3d frFootPosition(const Eigen::Vector3d& q);

// Its Jacobian J(q) = dr/dq (3x3), every entry written out.
Eigen::Matrix3d frFootJacobian(const Eigen::Vector3d& q);

// The answer to 57.3.1: the base velocity in the BODY frame while FR is in stance,
//   v_b = -(w x r(q) + J(q) dq),
// written out component by component (the world-frame velocity is R v_b).
Eigen::Vector3d frBaseVelocityBody(const Eigen::Vector3d& w, const Eigen::Vector3d& q,
                                   const Eigen::Vector3d& dq);

}  // namespace ex57_3_1
