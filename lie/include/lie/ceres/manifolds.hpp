// Ceres manifolds for SO(3), SE(3) and SE_K(3): the optional component lie::ceres
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
// Ceres asks for the Jacobians only at xi = 0 and at Y = X, where lie/'s Jr(0) = Jr^-1(0) = I:
//   PlusJacobian  = d vec(X Exp(xi)) / d xi at 0:
//                   rotation columns vec(R [e_j]x) (j = 1..3), column blocks d c_i / d rho_i = R;
//   MinusJacobian = d Log(X^-1 Y) / d vec(Y) at Y = X:
//                   rotation rows vec(R [e_j]x)^T / 2, column blocks d rho_i / d c_i = R^T.
// The rotation columns are orthogonal with squared norm tr([e_j]x^T [e_j]x) = 2, so
// MinusJacobian * PlusJacobian = I exactly for an orthonormal R. A cost function with a tangent
// Jacobian J_t hands Ceres J_a = J_t MinusJacobian(X) (for SO3: J_t PlusJacobian^T / 2; the
// static plusJacobian / minusJacobian give them as Eigen matrices), and Ceres gets back
// J_a PlusJacobian = J_t (RightMultiplyByPlusJacobian, written without forming PlusJacobian:
// row-wise vee(R^T G - G^T R) for the 3x3 rotation part G of an ambient row, R^T g for a column
// part g).
//
// Minus accepts any finite ambient Y, not only exact rotations (Ceres's numeric checks step off
// the manifold): R_X^T R_Y is projected onto SO(3) through its quaternion, which leaves a rotation
// matrix unchanged to rounding and whose derivative at the identity is vee((E - E^T)/2), the
// MinusJacobian above. Plus is the plain matrix product, defined for any ambient X.
// Plus and Minus return false (Ceres rejects the step) when the result is not finite.
//
// Tested in tests/lie/ceres_manifold_test.cpp (test_lie_ceres) on SO(3), SE(3), SE_2(3) and
// SE_3(3) with Ceres's own manifold_test_utils.h (EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD, relative
// tolerance 1e-9): Plus(x, 0) = x, Minus(x, x) = 0, Minus(Plus(x, d), x) = d (also d = 0),
// Plus(x, Minus(y, x)) = y (also y = x), PlusJacobian and MinusJacobian against Ridders numeric
// differences, MinusJacobian * PlusJacobian = I, RightMultiplyByPlusJacobian = ambient *
// PlusJacobian; at rotation angles 0, 1e-12 .. 1e-4, moderate and pi - 1e-6, columns 0 .. 10 m.
// The same identities' worst absolute errors are measured and bounded there (printed by the
// test); Plus is compared with lie/'s X * Exp(xi), non-finite input must return false, and one
// Ceres problem per manifold (a Karcher mean with a known answer) is solved.
#pragma once

#include <cstddef>

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

  // MinusJacobian(R) = PlusJacobian(R)^T / 2.
  static Eigen::Matrix<double, kTangentSize, kAmbientSize> minusJacobian(const Eigen::Matrix3d& R) {
    return 0.5 * plusJacobian(R).transpose();
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
      Eigen::Map<Eigen::Vector3d> row(tangent_matrix + std::ptrdiff_t{r} * kTangentSize);
      row = detail::rotationRowTimesPlusJacobian(
          R, Eigen::Map<const Eigen::Matrix3d>(ambient_matrix + std::ptrdiff_t{r} * kAmbientSize));
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
    J = minusJacobian(Eigen::Map<const Eigen::Matrix3d>(x));
    return true;
  }
};

// SE_K(3) as a Ceres manifold: 9 + 3K ambient numbers (R column-major, then c_1, ..., c_K),
// 3 + 3K tangent (phi, rho_1, ..., rho_K).
template <int K>
class SEK3Manifold final : public ::ceres::Manifold {
 public:
  static_assert(K >= 1, "SEK3Manifold needs K >= 1 columns");
  using Group = lie::SEK3<double, K>;
  static constexpr int kAmbientSize = 9 + 3 * K;
  static constexpr int kTangentSize = 3 + 3 * K;
  using PlusJacobianMatrix = Eigen::Matrix<double, kAmbientSize, kTangentSize>;
  using MinusJacobianMatrix = Eigen::Matrix<double, kTangentSize, kAmbientSize>;

  // PlusJacobian(X) = blockdiag(vec(R [e_j]x), R, ..., R).
  static PlusJacobianMatrix plusJacobian(const Eigen::Matrix3d& R) {
    PlusJacobianMatrix J = PlusJacobianMatrix::Zero();
    J.template topLeftCorner<9, 3>() = detail::rotationPlusJacobian(R);
    for (int i = 0; i < K; ++i) J.template block<3, 3>(9 + 3 * i, 3 + 3 * i) = R;
    return J;
  }
  // MinusJacobian(X) = blockdiag(vec(R [e_j]x)^T / 2, R^T, ..., R^T).
  static MinusJacobianMatrix minusJacobian(const Eigen::Matrix3d& R) {
    MinusJacobianMatrix J = MinusJacobianMatrix::Zero();
    J.template topLeftCorner<3, 9>() = 0.5 * detail::rotationPlusJacobian(R).transpose();
    for (int i = 0; i < K; ++i) J.template block<3, 3>(3 + 3 * i, 9 + 3 * i) = R.transpose();
    return J;
  }

  int AmbientSize() const override { return kAmbientSize; }
  int TangentSize() const override { return kTangentSize; }

  // x_plus_delta = X Exp(xi) = (R Exp(phi), R Jl(phi) rho_i + c_i).
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    const Eigen::Map<const Eigen::Matrix3d> R(x);
    const Eigen::Map<const Columns> C(x + 9);
    const Group E = Group::Exp(Eigen::Map<const typename Group::Tangent>(delta));
    const Eigen::Matrix3d R_plus = R * E.R();
    const Columns C_plus = R * E.columns() + C;
    Eigen::Map<Eigen::Matrix3d> R_out(x_plus_delta);
    Eigen::Map<Columns> C_out(x_plus_delta + 9);
    R_out = R_plus;
    C_out = C_plus;
    return R_plus.allFinite() && C_plus.allFinite();
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
      const double* a = ambient_matrix + std::ptrdiff_t{r} * kAmbientSize;
      Eigen::Map<Eigen::Matrix<double, kTangentSize, 1>> row(tangent_matrix +
                                                             std::ptrdiff_t{r} * kTangentSize);
      row.template head<3>() =
          detail::rotationRowTimesPlusJacobian(R, Eigen::Map<const Eigen::Matrix3d>(a));
      for (int i = 0; i < K; ++i) {
        row.template segment<3>(3 + 3 * i) =
            R.transpose() * Eigen::Map<const Eigen::Vector3d>(a + 9 + std::ptrdiff_t{3} * i);
      }
    }
    return true;
  }

  // y_minus_x = Log(X^-1 Y) = Log(R_x^T R_y, R_x^T (c_y,i - c_x,i)).
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    const Eigen::Map<const Eigen::Matrix3d> R_x(x);
    const Eigen::Map<const Eigen::Matrix3d> R_y(y);
    const Columns C =
        R_x.transpose() * (Eigen::Map<const Columns>(y + 9) - Eigen::Map<const Columns>(x + 9));
    Eigen::Map<typename Group::Tangent> xi(y_minus_x);
    xi = Group(detail::relativeRotation(R_x, R_y), C).Log();
    return xi.allFinite();
  }

  bool MinusJacobian(const double* x, double* jacobian) const override {
    Eigen::Map<detail::RowMajor<kTangentSize, kAmbientSize>> J(jacobian);
    J = minusJacobian(Eigen::Map<const Eigen::Matrix3d>(x));
    return true;
  }

 private:
  using Columns = Eigen::Matrix<double, 3, K>;
};

// SE(3): R column-major, then the translation (12 ambient numbers), tangent (phi, rho).
using SE3Manifold = SEK3Manifold<1>;

}  // namespace lie::ceres
