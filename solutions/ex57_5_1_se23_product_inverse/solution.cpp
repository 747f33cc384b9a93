// Reference solution to exercise 57.5.1.
#include "ex57_5_1.hpp"

#include <Eigen/Dense>

namespace ex57_5_1 {

Matrix5d toMatrix(const ExtendedPose& X) {
  Matrix5d M = Matrix5d::Identity();
  M.topLeftCorner<3, 3>() = X.R;
  M.block<3, 1>(0, 3) = X.v;
  M.block<3, 1>(0, 4) = X.p;
  return M;
}

// [[R1, v1, p1], [0, I]] [[R2, v2, p2], [0, I]] = [[R1 R2, R1 v2 + v1, R1 p2 + p1], [0, I]]:
// R1 R2 is a rotation and the bottom rows stay [0 | I], so the product is in SE_2(3).
ExtendedPose compose(const ExtendedPose& X1, const ExtendedPose& X2) {
  return {X1.R * X2.R, X1.R * X2.v + X1.v, X1.R * X2.p + X1.p};
}

// Solving X Y = I block by block: R Ry = I gives Ry = R^T, and R vy + v = 0 gives vy = -R^T v
// (likewise for p). R^T is a rotation, so the inverse is in SE_2(3) too.
ExtendedPose inverse(const ExtendedPose& X) {
  const Eigen::Matrix3d Rt = X.R.transpose();
  return {Rt, -Rt * X.v, -Rt * X.p};
}

bool isInSE23(const Matrix5d& M, double tol) {
  if (!M.allFinite()) return false;
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  const bool orthonormal = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= tol;
  const bool proper = std::abs(R.determinant() - 1.0) <= tol;
  Eigen::Matrix<double, 2, 5> bottom = Eigen::Matrix<double, 2, 5>::Zero();
  bottom(0, 3) = 1.0;
  bottom(1, 4) = 1.0;
  const bool bottomRows = (M.bottomRows<2>() - bottom).cwiseAbs().maxCoeff() <= tol;
  return orthonormal && proper && bottomRows;
}

}  // namespace ex57_5_1
