// Exercise 57.3.2: what leg odometry can and cannot observe while trotting (two diagonal feet).
#pragma once

#include <Eigen/Core>

namespace ex57_3_2 {

// Error state, in this order (dimension 9 + 3k for k stance feet):
//   (dp, dtheta, dv, dd_1, ..., dd_k)
// base position p, attitude R = Exp(dtheta) R_hat (world-frame perturbation), base velocity v,
// world positions d_i of the stance feet (the columns of d).
//
// Rows, first the k foot-position blocks, then the k velocity blocks, then (with_gravity) one
// gravity block:
//   y_i = R^T (d_i - p)   the body-frame foot position the encoders give,
//   u_i = R^T v           the body-frame base velocity leg odometry gives from foot i,
//   g_b = R^T e_z         the "up" direction the accelerometer senses when not accelerating.
// Return their stacked Jacobian with respect to the error state.
Eigen::MatrixXd stackedJacobian(const Eigen::Vector3d& p, const Eigen::Matrix3d& R,
                                const Eigen::Vector3d& v, const Eigen::Matrix3Xd& d,
                                bool with_gravity);

// Null space of H: its dimension (columns minus numerical rank; treat singular values below
// 1e-9 times the largest as zero) and an orthonormal basis (one column per direction).
struct NullSpace {
  int dimension = 0;
  Eigen::MatrixXd basis;
};
NullSpace nullSpace(const Eigen::MatrixXd& H);

}  // namespace ex57_3_2
