// Reference solution to exercise 57.5.3.
#include <algorithm>

#include "ex57_5_3.hpp"

namespace ex57_5_3 {

namespace {

Eigen::Matrix3d hat(const Eigen::Vector3d& a) {
  Eigen::Matrix3d m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

// Block offsets in the 15-vector.
constexpr int kTheta = 0, kV = 3, kP = 6, kBg = 9, kBa = 12;

}  // namespace

// R = R_hat Exp(dtheta) with dR/dt = R [w_m - b_g - n_g]_x gives
//   d(dtheta)/dt = -[w_m - b_g_hat]_x dtheta - db_g - n_g;
// dv/dt = R (a_m - b_a - n_a) + g with R (f - db_a) = R_hat (I + [dtheta]_x)(f - db_a) gives
//   d(dv)/dt = -R_hat [f]_x dtheta - R_hat db_a - R_hat n_a,   f = a_m - b_a_hat;
// d(dp)/dt = dv; the biases are random walks.
Matrix15 eskfF(const NavState& x_hat, const Eigen::Vector3d& w_m, const Eigen::Vector3d& a_m) {
  const Eigen::Vector3d w = w_m - x_hat.b_g;
  const Eigen::Vector3d f = a_m - x_hat.b_a;
  Matrix15 F = Matrix15::Zero();
  F.block<3, 3>(kTheta, kTheta) = -hat(w);
  F.block<3, 3>(kTheta, kBg) = -Eigen::Matrix3d::Identity();
  F.block<3, 3>(kV, kTheta) = -x_hat.R * hat(f);
  F.block<3, 3>(kV, kBa) = -x_hat.R;
  F.block<3, 3>(kP, kV) = Eigen::Matrix3d::Identity();
  return F;
}

// Without biases the right-invariant error obeys d(xi)/dt = A_t xi with the constant
// A_t = [[0, 0, 0], [[g]_x, 0, 0], [0, I, 0]]. A bias error zeta = b_hat - b makes the filter's
// input differ from the true one by zeta; a body-frame input error enters the right-invariant
// (world-frame) error through the adjoint of X_hat, so
//   A_b = -Ad_{X_hat} [[I, 0], [0, I], [0, 0]] = [[-R, 0], [-[v]_x R, -R], [-[p]_x R, 0]].
Matrix15 inekfA(const NavState& x_hat, const Eigen::Vector3d& g) {
  const Eigen::Matrix3d& R = x_hat.R;
  Matrix15 A = Matrix15::Zero();
  A.block<3, 3>(kV, kTheta) = hat(g);
  A.block<3, 3>(kP, kV) = Eigen::Matrix3d::Identity();
  A.block<3, 3>(kTheta, kBg) = -R;
  A.block<3, 3>(kV, kBg) = -hat(x_hat.v) * R;
  A.block<3, 3>(kP, kBg) = -hat(x_hat.p) * R;
  A.block<3, 3>(kV, kBa) = -R;
  return A;
}

BlockCount countBlocks(const Matrix15& J_at_x1, const Matrix15& J_at_x2) {
  constexpr double kTol = 1e-12;
  BlockCount count;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) {
      const Eigen::Matrix3d a = J_at_x1.block<3, 3>(3 * i, 3 * j);
      const Eigen::Matrix3d b = J_at_x2.block<3, 3>(3 * i, 3 * j);
      if (std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()) > kTol) ++count.nonzero;
      if ((a - b).cwiseAbs().maxCoeff() > kTol) ++count.estimate_dependent;
    }
  }
  return count;
}

}  // namespace ex57_5_3
