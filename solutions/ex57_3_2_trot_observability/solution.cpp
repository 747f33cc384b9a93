// Reference solution to exercise 57.3.2.
#include <Eigen/SVD>

#include "ex57_3_2.hpp"

namespace ex57_3_2 {
namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d S;
  S << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return S;
}

}  // namespace

// With R^T a ~ R_hat^T a + R_hat^T [a]_x dtheta:
//   y_i = R^T (d_i - p): d/dp = -R^T, d/dtheta = R^T [d_i - p]_x, d/dd_i = R^T
//   u_i = R^T v:         d/dtheta = R^T [v]_x, d/dv = R^T
//   g_b = R^T e_z:       d/dtheta = R^T [e_z]_x
Eigen::MatrixXd stackedJacobian(const Eigen::Vector3d& p, const Eigen::Matrix3d& R,
                                const Eigen::Vector3d& v, const Eigen::Matrix3Xd& d,
                                bool with_gravity) {
  const int k = static_cast<int>(d.cols());
  const Eigen::Matrix3d Rt = R.transpose();
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(6 * k + (with_gravity ? 3 : 0), 9 + 3 * k);
  for (int i = 0; i < k; ++i) {
    H.block<3, 3>(3 * i, 0) = -Rt;
    H.block<3, 3>(3 * i, 3) = Rt * skew(d.col(i) - p);
    H.block<3, 3>(3 * i, 9 + 3 * i) = Rt;
    H.block<3, 3>(3 * k + 3 * i, 3) = Rt * skew(v);
    H.block<3, 3>(3 * k + 3 * i, 6) = Rt;
  }
  if (with_gravity) H.block<3, 3>(6 * k, 3) = Rt * skew(Eigen::Vector3d::UnitZ());
  return H;
}

NullSpace nullSpace(const Eigen::MatrixXd& H) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(H, Eigen::ComputeFullV);
  const Eigen::VectorXd& s = svd.singularValues();
  const double threshold = 1e-9 * s.maxCoeff();
  const int rank = static_cast<int>((s.array() > threshold).count());
  NullSpace out;
  out.dimension = static_cast<int>(H.cols()) - rank;
  out.basis = svd.matrixV().rightCols(out.dimension);
  return out;
}

}  // namespace ex57_3_2
