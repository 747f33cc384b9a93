// Ceres manifolds for SO(3) (SE(3) and SE_K(3) are next): the optional component lie::ceres
// (find_package(lie REQUIRED COMPONENTS ceres), target lie::ceres; it links Ceres::ceres).
//
// Ambient layouts (what a Ceres parameter block holds):
//   SO3Manifold       9 doubles: the rotation matrix R, column-major.
//   SEK3Manifold<K>   9 + 3K doubles: R column-major, then the columns c_1, ..., c_K of SE_K(3).
//   SE3Manifold       = SEK3Manifold<1>: R, then the translation t (12 doubles).
// Tangent vectors are lie/'s: phi (SO3), (phi, rho_1, ..., rho_K) (SE_K(3), rotation first).
//
//   Plus(X, xi)   = X Exp(xi)        (right plus; for SE_K(3) the SE_K(3) exponential)
//   Minus(Y, X)   = Log(X^-1 Y)      (right minus)
// Ceres asks only for the Jacobians at xi = 0 and at Y = X, where lie/'s Jr and Jr^-1 are I:
//   PlusJacobian  = d vec(X Exp(xi)) / d xi = X dExp(0) Jr(0):
//                   rotation columns vec(R [e_j]x) (j = 1..3), column blocks d c_i / d rho_i = R;
//   MinusJacobian = Jr^-1(0) d Log(X^-1 Y) / d vec(Y):
//                   rotation rows vec(R [e_j]x)^T / 2, column blocks d rho_i / d c_i = R^T.
// The rotation columns are orthogonal with squared norm tr([e_j]x^T [e_j]x) = 2, so
// MinusJacobian * PlusJacobian = I exactly for an orthonormal R, and the tangent Jacobian of a
// cost is recovered from its ambient one as J_t = J_a PlusJacobian
// (RightMultiplyByPlusJacobian, written without forming PlusJacobian: row-wise
// vee(R^T G - G^T R) for the 3x3 rotation part G of an ambient row, R^T g for a column part g).
//
// Minus accepts any finite ambient Y, not only exact rotations (Ceres's numeric checks step off
// the manifold): R_X^T R_Y is projected onto SO(3) through its quaternion, which leaves a rotation
// matrix unchanged to rounding and whose derivative at the identity is vee((E - E^T)/2), the
// MinusJacobian above. Plus is the plain matrix product, defined for any ambient X.
// Plus and Minus return false (Ceres rejects the step) when the result is not finite.
//
// Tested in tests/lie/ceres_manifold_test.cpp with Ceres's own manifold_test_utils.h
// (EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD): Plus(x, 0) = x, Minus(x, x) = 0,
// Minus(Plus(x, d), x) = d (also d = 0), Plus(x, Minus(y, x)) = y (also y = x), PlusJacobian and
// MinusJacobian against Ridders numeric differences, MinusJacobian * PlusJacobian = I, and
// RightMultiplyByPlusJacobian = ambient * PlusJacobian; at angles near 0 (down to 1e-12), moderate,
// and near pi; plus Plus against lie/'s Exp, and one Ceres problem solved on each manifold.
#pragma once

#include <ceres/manifold.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "lie/sek3.hpp"
#include "lie/so3.hpp"

namespace lie::ceres {

namespace detail {

template <int Rows, int Cols>
using RowMajor = Eigen::Matrix<double, Rows, Cols, Eigen::RowMajor>;

// X^T Y projected onto SO(3) through its quaternion (see the header comment).
inline lie::SO3d relativeRotation(const Eigen::Matrix3d& R_X, const Eigen::Matrix3d& R_Y) {
  return lie::SO3d::fromQuaternion(Eigen::Quaterniond(Eigen::Matrix3d(R_X.transpose() * R_Y)));
}

// vec(R [e_j]x) for j = 0..2: the rotation part of PlusJacobian (9 x 3).
inline Eigen::Matrix<double, 9, 3> rotationPlusJacobian(const Eigen::Matrix3d& R) {
  Eigen::Matrix<double, 9, 3> J;
  for (int j = 0; j < 3; ++j) {
    const Eigen::Matrix3d RE = R * lie::SO3d::hat(Eigen::Vector3d::Unit(j));
    J.col(j) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(RE.data());
  }
  return J;
}

// G . vec(R [e_j]x) for j = 0..2, G a 3x3 (column-major ambient) block: vee(R^T G - G^T R).
inline Eigen::Vector3d rotationRowTimesPlusJacobian(const Eigen::Matrix3d& R,
                                                    const Eigen::Matrix3d& G) {
  const Eigen::Matrix3d A = R.transpose() * G;
  return Eigen::Vector3d(A(2, 1) - A(1, 2), A(0, 2) - A(2, 0), A(1, 0) - A(0, 1));
}

}  // namespace detail

// SO(3) as a Ceres manifold: 9 ambient numbers (R column-major), 3 tangent (phi).
class SO3Manifold final : public ::ceres::Manifold {
 public:
  static constexpr int kAmbientSize = 9;
  static constexpr int kTangentSize = 3;
  using PlusJacobianMatrix = Eigen::Matrix<double, kAmbientSize, kTangentSize>;

  // PlusJacobian(R) as an Eigen matrix (for cost functions that map tangent Jacobians back to
  // the ambient space: J_a = J_t PlusJacobian^T / 2).
  static PlusJacobianMatrix plusJacobian(const Eigen::Matrix3d& R) {
    return detail::rotationPlusJacobian(R);
  }

  int AmbientSize() const override { return kAmbientSize; }
  int TangentSize() const override { return kTangentSize; }

  // x_plus_delta = R Exp(phi).
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    const Eigen::Map<const Eigen::Matrix3d> R(x);
    Eigen::Map<Eigen::Matrix3d> out(x_plus_delta);
    out = R * lie::SO3d::Exp(Eigen::Map<const Eigen::Vector3d>(delta)).matrix();
    return out.allFinite();
  }

  bool PlusJacobian(const double* x, double* jacobian) const override {
    Eigen::Map<detail::RowMajor<kAmbientSize, kTangentSize>> J(jacobian);
    J = plusJacobian(Eigen::Map<const Eigen::Matrix3d>(x));
    return true;
  }

  bool RightMultiplyByPlusJacobian(const double* x, const int num_rows,
                                   const double* ambient_matrix,
                                   double* tangent_matrix) const override {
    const Eigen::Map<const Eigen::Matrix3d> R(x);
    for (int r = 0; r < num_rows; ++r) {
      Eigen::Map<Eigen::Vector3d> row(tangent_matrix + r * kTangentSize);
      row = detail::rotationRowTimesPlusJacobian(
          R, Eigen::Map<const Eigen::Matrix3d>(ambient_matrix + r * kAmbientSize));
    }
    return true;
  }

  // y_minus_x = Log(R_x^T R_y).
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    Eigen::Map<Eigen::Vector3d> phi(y_minus_x);
    phi = detail::relativeRotation(Eigen::Map<const Eigen::Matrix3d>(x),
                                   Eigen::Map<const Eigen::Matrix3d>(y))
              .Log();
    return phi.allFinite();
  }

  bool MinusJacobian(const double* x, double* jacobian) const override {
    Eigen::Map<detail::RowMajor<kTangentSize, kAmbientSize>> J(jacobian);
    J = 0.5 * plusJacobian(Eigen::Map<const Eigen::Matrix3d>(x)).transpose();
    return true;
  }
};

}  // namespace lie::ceres
