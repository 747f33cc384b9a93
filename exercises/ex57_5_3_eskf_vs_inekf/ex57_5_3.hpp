// Exercise 57.5.3: the ESKF's error Jacobian against the invariant EKF's.
#pragma once

#include <Eigen/Core>

namespace ex57_5_3 {

using Matrix15 = Eigen::Matrix<double, 15, 15>;

// The navigation part of both filters' state: attitude R (body to world), world velocity v and
// position p, gyro and accelerometer biases. (The feet are left out: in both filters their rows
// of the error Jacobian are zero.)
struct NavState {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();
};

// The ESKF's continuous error dynamics d(dx)/dt = F dx at the estimate x_hat and the measured
// input (w_m, a_m), for the error dx = (dtheta, dv, dp, db_g, db_a) with the local attitude error
// R = R_hat Exp(dtheta) and v = v_hat + dv, p = p_hat + dp, b = b_hat + db.
Matrix15 eskfF(const NavState& x_hat, const Eigen::Vector3d& w_m, const Eigen::Vector3d& a_m);

// The "imperfect" right-invariant EKF's continuous error dynamics d(xi)/dt = A xi at the estimate
// x_hat, for xi = (xi_R, xi_v, xi_p, zeta_g, zeta_a): (xi_R, xi_v, xi_p) = Log(X_hat X^-1) on
// SE_2(3), and the bias errors zeta = b_hat - b (the convention of lie/imu_dynamics.hpp).
// g is the world gravity vector.
Matrix15 inekfA(const NavState& x_hat, const Eigen::Vector3d& g);

// What a 15 x 15 error Jacobian costs to rebuild, read off two evaluations of it at different
// estimates (and the same input): over its 25 blocks of 3 x 3,
//   nonzero             blocks with an entry of magnitude above 1e-12 in either evaluation;
//   estimate_dependent  blocks whose two evaluations differ by more than 1e-12 in some entry.
struct BlockCount {
  int nonzero = 0;
  int estimate_dependent = 0;
};
BlockCount countBlocks(const Matrix15& J_at_x1, const Matrix15& J_at_x2);

}  // namespace ex57_5_3
