// Reference solution to exercise 57.3.1: everything in explicit scalar form.
#include <cmath>

#include "ex57_3_1.hpp"

namespace ex57_3_1 {

// With c1 = cos q1, s1 = sin q1, c2, s2, c23 = cos(q2 + q3), s23 = sin(q2 + q3) and the
// lateral offset y0 = -d (right leg), the leg-plane point (x, y0, z0) turned by q1 about x is
//   r_x = hx + x                       x  = -l1 s2 - l2 s23
//   r_y = hy + c1 y0 - s1 z0           z0 = -l1 c2 - l2 c23
//   r_z =      s1 y0 + c1 z0
Eigen::Vector3d frFootPosition(const Eigen::Vector3d& q) {
  const double c1 = std::cos(q[0]), s1 = std::sin(q[0]);
  const double s2 = std::sin(q[1]), c2 = std::cos(q[1]);
  const double s23 = std::sin(q[1] + q[2]), c23 = std::cos(q[1] + q[2]);
  const double y0 = -kAbduction;
  const double x = -kThigh * s2 - kCalf * s23;
  const double z0 = -kThigh * c2 - kCalf * c23;
  return {kHipX + x, kHipY + c1 * y0 - s1 * z0, s1 * y0 + c1 * z0};
}

// Row by row (d/dq1, d/dq2, d/dq3):
//   r_x:  0,                    -l1 c2 - l2 c23,         -l2 c23
//   r_y: -(s1 y0 + c1 z0),       s1 (-l1 s2 - l2 s23),   -s1 l2 s23
//   r_z:  c1 y0 - s1 z0,        -c1 (-l1 s2 - l2 s23),    c1 l2 s23
Eigen::Matrix3d frFootJacobian(const Eigen::Vector3d& q) {
  const double c1 = std::cos(q[0]), s1 = std::sin(q[0]);
  const double s2 = std::sin(q[1]), c2 = std::cos(q[1]);
  const double s23 = std::sin(q[1] + q[2]), c23 = std::cos(q[1] + q[2]);
  const double y0 = -kAbduction;
  const double x = -kThigh * s2 - kCalf * s23;
  const double z0 = -kThigh * c2 - kCalf * c23;
  Eigen::Matrix3d J;
  J << 0.0, z0, -kCalf * c23,                           //
      -(s1 * y0 + c1 * z0), s1 * x, -s1 * kCalf * s23,  //
      c1 * y0 - s1 * z0, -c1 * x, c1 * kCalf * s23;
  return J;
}

// v_b = -(w x r + J dq), one component at a time:
//   v_x = -(w_y r_z - w_z r_y) - (J_x2 dq2 + J_x3 dq3)
//   v_y = -(w_z r_x - w_x r_z) - (J_y1 dq1 + J_y2 dq2 + J_y3 dq3)
//   v_z = -(w_x r_y - w_y r_x) - (J_z1 dq1 + J_z2 dq2 + J_z3 dq3)
// (J_x1 = 0: abduction moves the foot only across the body's x axis.)
Eigen::Vector3d frBaseVelocityBody(const Eigen::Vector3d& w, const Eigen::Vector3d& q,
                                   const Eigen::Vector3d& dq) {
  const Eigen::Vector3d r = frFootPosition(q);
  const Eigen::Matrix3d J = frFootJacobian(q);
  const double vx = -(w[1] * r[2] - w[2] * r[1]) - (J(0, 1) * dq[1] + J(0, 2) * dq[2]);
  const double vy =
      -(w[2] * r[0] - w[0] * r[2]) - (J(1, 0) * dq[0] + J(1, 1) * dq[1] + J(1, 2) * dq[2]);
  const double vz =
      -(w[0] * r[1] - w[1] * r[0]) - (J(2, 0) * dq[0] + J(2, 1) * dq[1] + J(2, 2) * dq[2]);
  return {vx, vy, vz};
}

}  // namespace ex57_3_1
