// Reference solution to exercise 57.4.1.
#include "ex57_4_1.hpp"

namespace ex57_4_1 {
namespace {

const Eigen::Matrix3d I3 = Eigen::Matrix3d::Identity();

Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d S;
  S << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return S;
}

int stanceCount(const Stance& stance) {
  int k = 0;
  for (bool s : stance) k += s;
  return k;
}

}  // namespace

// p <- p + v dt: the identity with dt I in the (p, v) block.
Matrix18 F(double dt) {
  Matrix18 F = Matrix18::Identity();
  F.block<3, 3>(0, 3) = dt * I3;
  return F;
}

// p gets u dt^2 / 2, v gets u dt.
Eigen::Matrix<double, kDim, 3> B(double dt) {
  Eigen::Matrix<double, kDim, 3> B = Eigen::Matrix<double, kDim, 3>::Zero();
  B.topRows<3>() = 0.5 * dt * dt * I3;
  B.middleRows<3>(3) = dt * I3;
  return B;
}

// B (sigma_a^2 / dt I) B^T on (p, v): per axis sigma_a^2 [[dt^3/4, dt^2/2], [dt^2/2, dt]].
Matrix18 Q(double dt, const Stance& stance, const Densities& densities) {
  const Eigen::Matrix<double, kDim, 3> Bm = B(dt);
  Matrix18 Q = Bm * (densities.accel * densities.accel / dt * I3) * Bm.transpose();
  for (int i = 0; i < 4; ++i) {
    const double s = stance[i] ? densities.foot_stance : densities.foot_swing;
    Q.block<3, 3>(6 + 3 * i, 6 + 3 * i) = s * s * dt * I3;
  }
  return Q;
}

// Foot i: -I on p, +I on d_i.
Eigen::MatrixXd H(const Stance& stance) {
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3 * stanceCount(stance), kDim);
  int row = 0;
  for (int i = 0; i < 4; ++i) {
    if (!stance[i]) continue;
    H.block<3, 3>(row, 0) = -I3;
    H.block<3, 3>(row, 6 + 3 * i) = I3;
    row += 3;
  }
  return H;
}

// Block (i, j): the feet's own noise on the diagonal, the shared attitude error everywhere.
Eigen::MatrixXd R(const Stance& stance, const Eigen::Matrix3d& R_hat,
                  const std::array<Eigen::Vector3d, 4>& r, const std::array<Eigen::Matrix3d, 4>& C,
                  const Eigen::Matrix3d& Sigma_theta) {
  const int k = stanceCount(stance);
  Eigen::MatrixXd Rn = Eigen::MatrixXd::Zero(3 * k, 3 * k);
  int row = 0;
  for (int i = 0; i < 4; ++i) {
    if (!stance[i]) continue;
    const Eigen::Matrix3d zi_x = skew(R_hat * r[i]);
    Rn.block<3, 3>(row, row) = R_hat * C[i] * R_hat.transpose();
    int col = 0;
    for (int j = 0; j < 4; ++j) {
      if (!stance[j]) continue;
      Rn.block<3, 3>(row, col) += zi_x * Sigma_theta * skew(R_hat * r[j]).transpose();
      col += 3;
    }
    row += 3;
  }
  return Rn;
}

}  // namespace ex57_4_1
