// SO(3): rotations of R^3, stored as a 3x3 rotation matrix.
//
// Tangent space: a rotation vector phi in R^3, hat(phi) = [phi]_x (skew-symmetric).
//   Exp(phi) = I + G_1 [phi] + G_2 [phi]^2                      (Rodrigues)
//   Jr(phi)  = I - G_2 [phi] + G_3 [phi]^2,  Jl(phi) = Jr(-phi)  (right/left Jacobians)
//   Jl^-1    = I - [phi]/2 + D [phi]^2
// with the G's and D from so3_series.hpp. Jacobian convention (manif, Sola et al. 2018):
//   Exp(phi + d) = Exp(phi) Exp(Jr(phi) d) = Exp(Jl(phi) d) Exp(phi).
// Log reads the angle and the axis off the matrix (logOfMatrix): accurate at every angle, with
// one asin and no atan2, no quaternion.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <random>
#include <sstream>
#include <type_traits>

#include "lie/errors.hpp"
#include "lie/so3_series.hpp"

namespace lie {

template <typename Scalar, int K, int MaxK>
class SEK3;

template <typename Scalar>
using Vector3 = Eigen::Matrix<Scalar, 3, 1>;
template <typename Scalar>
using Matrix3 = Eigen::Matrix<Scalar, 3, 3>;

// [v]_x, so that hat(v) * w = v x w.
template <typename Derived>
Matrix3<typename Derived::Scalar> hat3(const Eigen::MatrixBase<Derived>& v) {
  using S = typename Derived::Scalar;
  Matrix3<S> m;
  m << S(0), -v(2), v(1), v(2), S(0), -v(0), -v(1), v(0), S(0);
  return m;
}

// d I + alpha [phi] + beta [phi]^2, built entrywise from [phi]^2 = phi phi^T - theta^2 I: every
// closed form in lie/ is of this shape, and no 3x3 product is needed to evaluate one.
// Scalar is deduced from phi alone: the coefficients may be expressions of it (an
// Eigen::AutoDiffScalar product is its own type) and convert on the way in.
template <typename Scalar>
Matrix3<Scalar> skewSeries(const Vector3<Scalar>& phi, detail::NonDeduced<Scalar> theta2,
                           detail::NonDeduced<Scalar> d, detail::NonDeduced<Scalar> alpha,
                           detail::NonDeduced<Scalar> beta) {
  const Scalar diag = d - beta * theta2;
  const Scalar xy = beta * phi(0) * phi(1), xz = beta * phi(0) * phi(2),
               yz = beta * phi(1) * phi(2);
  const Vector3<Scalar> a = alpha * phi;
  Matrix3<Scalar> m;
  m << diag + beta * phi(0) * phi(0), xy - a(2), xz + a(1),  //
      xy + a(2), diag + beta * phi(1) * phi(1), yz - a(0),   //
      xz - a(1), yz + a(0), diag + beta * phi(2) * phi(2);
  return m;
}

// The SO(3) Gamma functions of the InEKF literature, Gamma_m(phi) = sum_n [phi]^n / (n+m)!:
// Gamma_0 = Exp, Gamma_1 = Jl (the integral of Exp), Gamma_2 (the integral of Gamma_1).
template <int m, typename Derived>
Matrix3<typename Derived::Scalar> Gamma(const Eigen::MatrixBase<Derived>& phi_in) {
  static_assert(m >= 0 && m <= 2, "Gamma_m is provided for m = 0, 1, 2");
  using Scalar = typename Derived::Scalar;
  const Vector3<Scalar> phi = phi_in;
  const AngleSeries<Scalar> c(phi.squaredNorm());
  return skewSeries(phi, c.theta2(), Scalar(1) / Scalar(detail::factorial(m)),
                    c.template G<m + 1>(), c.template G<m + 2>());
}

template <typename Scalar_>
class SO3 {
 public:
  using Scalar = Scalar_;
  static constexpr int DoF = 3;
  using Tangent = Vector3<Scalar>;
  using Point = Vector3<Scalar>;
  using Jacobian = Matrix3<Scalar>;
  using AdjointMatrix = Matrix3<Scalar>;
  using Matrix = Matrix3<Scalar>;

  SO3() : R_(Matrix::Identity()) {}
  static SO3 Identity() { return SO3(); }

  // Checked construction: throws lie::NotInGroup unless R is finite, orthonormal to tol and
  // has determinant +1.
  static SO3 fromMatrix(const Matrix& R, Scalar tol = Scalar(1e-9)) {
    if (!R.allFinite()) throw NotInGroup("SO3::fromMatrix: matrix has a NaN or inf entry");
    const Scalar orth = (R.transpose() * R - Matrix::Identity()).cwiseAbs().maxCoeff();
    if (!(orth <= tol)) {
      std::ostringstream os;
      os << "SO3::fromMatrix: matrix is not orthonormal (max |R^T R - I| = " << orth << " > tol "
         << tol << ")";
      throw NotInGroup(os.str());
    }
    if (R.determinant() < Scalar(0)) {
      throw NotInGroup("SO3::fromMatrix: determinant is -1 (a reflection, not a rotation)");
    }
    return SO3(R, Unchecked{});
  }
  static SO3 fromQuaternion(const Eigen::Quaternion<Scalar>& q) {
    return SO3(q.normalized().toRotationMatrix(), Unchecked{});
  }

  const Matrix& matrix() const { return R_; }
  Eigen::Quaternion<Scalar> quaternion() const { return Eigen::Quaternion<Scalar>(R_); }

  // Group operations ---------------------------------------------------------------------
  SO3 operator*(const SO3& other) const { return SO3(R_ * other.R_, Unchecked{}); }
  SO3 compose(const SO3& other, Jacobian* J_out_this = nullptr,
              Jacobian* J_out_other = nullptr) const {
    if (J_out_this) *J_out_this = other.R_.transpose();  // Ad of other^-1
    if (J_out_other) J_out_other->setIdentity();
    return *this * other;
  }
  SO3 inverse(Jacobian* J_out_this = nullptr) const {
    if (J_out_this) *J_out_this = -R_;  // -Ad
    return SO3(R_.transpose(), Unchecked{});
  }
  Point act(const Point& x, Jacobian* J_out_this = nullptr, Jacobian* J_out_x = nullptr) const {
    if (J_out_this) *J_out_this = -R_ * hat3(x);
    if (J_out_x) *J_out_x = R_;
    return R_ * x;
  }
  Point operator*(const Point& x) const { return R_ * x; }

  // Exp / Log ---------------------------------------------------------------------------
  static SO3 Exp(const Tangent& phi, Jacobian* J_out_phi = nullptr) {
    const AngleSeries<Scalar> c(phi.squaredNorm());
    if (J_out_phi) *J_out_phi = Jr(phi, c);
    return SO3(expMatrix(phi, c), Unchecked{});
  }

  Tangent Log(Jacobian* J_out_this = nullptr) const {
    const Tangent phi = logOfMatrix(R_);
    if (J_out_this) *J_out_this = JrInv(phi);
    return phi;
  }

  static Matrix hat(const Tangent& phi) { return hat3(phi); }
  static Tangent vee(const Matrix& P) { return Tangent(P(2, 1), P(0, 2), P(1, 0)); }

  AdjointMatrix Adj() const { return R_; }
  static AdjointMatrix ad(const Tangent& phi) { return hat3(phi); }

  // Jacobians -----------------------------------------------------------------------------
  static Jacobian Jr(const Tangent& phi) { return Jr(phi, AngleSeries<Scalar>(phi.squaredNorm())); }
  static Jacobian Jl(const Tangent& phi) { return Jr(Tangent(-phi)); }
  static Jacobian JrInv(const Tangent& phi) { return JlInv(Tangent(-phi)); }
  static Jacobian JlInv(const Tangent& phi) {
    return JlInv(phi, AngleSeries<Scalar>(phi.squaredNorm()));
  }

  // Plus / minus: right (body-frame) and left (world-frame) versions.
  SO3 rplus(const Tangent& tau) const { return *this * Exp(tau); }
  SO3 lplus(const Tangent& tau) const { return Exp(tau) * *this; }
  Tangent rminus(const SO3& X) const { return (X.inverse() * *this).Log(); }  // Log(X^-1 Y)
  Tangent lminus(const SO3& X) const { return (*this * X.inverse()).Log(); }  // Log(Y X^-1)

  // Geodesic interpolation: t = 0 gives *this, t = 1 gives other.
  SO3 interpolate(const SO3& other, Scalar t) const { return rplus(t * other.rminus(*this)); }

  // Uniformly distributed rotation (Haar measure): a normalised 4-D Gaussian quaternion.
  template <typename Generator>
  static SO3 Random(Generator& gen) {
    std::normal_distribution<Scalar> n01(Scalar(0), Scalar(1));
    Eigen::Quaternion<Scalar> q(n01(gen), n01(gen), n01(gen), n01(gen));
    return fromQuaternion(q);
  }

  bool isApprox(const SO3& other, Scalar tol = Scalar(1e-10)) const {
    return (R_ - other.R_).cwiseAbs().maxCoeff() <= tol;
  }

  // The nearest rotation matrix in the Frobenius norm (removes accumulated rounding drift): the
  // orthogonal factor U V^T of the SVD. Eigen's SVD takes no autodiff scalar, so for those the
  // same polar factor comes from Newton's iteration Q <- (Q + Q^-T)/2 (Higham), quadratic from a
  // near-rotation: kPolarIterations steps take a drift of 0.1 below rounding. Q^-T is the
  // cofactor matrix over the determinant, columns (q1 x q2, q2 x q0, q0 x q1) / det Q.
  SO3 normalized() const {
    if constexpr (std::is_floating_point_v<Scalar>) {
      Eigen::JacobiSVD<Matrix> svd(R_, Eigen::ComputeFullU | Eigen::ComputeFullV);
      Matrix U = svd.matrixU();
      if ((U * svd.matrixV().transpose()).determinant() < Scalar(0)) U.col(2) *= Scalar(-1);
      return SO3(U * svd.matrixV().transpose(), Unchecked{});
    } else {
      constexpr int kPolarIterations = 6;
      Matrix Q = R_;
      for (int i = 0; i < kPolarIterations; ++i) {
        Matrix cofactor;
        cofactor.col(0) = Q.col(1).cross(Q.col(2));
        cofactor.col(1) = Q.col(2).cross(Q.col(0));
        cofactor.col(2) = Q.col(0).cross(Q.col(1));
        const Scalar det = Q.col(0).dot(cofactor.col(0));
        Q = (Q + cofactor / det) / Scalar(2);
      }
      return SO3(Q, Unchecked{});
    }
  }

  // Building blocks shared with SE_K(3), which reuses one AngleSeries per operation ------
  static Matrix expMatrix(const Tangent& phi, const AngleSeries<Scalar>& c) {
    return skewSeries(phi, c.theta2(), Scalar(1), c.template G<1>(), c.template G<2>());
  }
  static Jacobian Jr(const Tangent& phi, const AngleSeries<Scalar>& c) {
    return skewSeries(phi, c.theta2(), Scalar(1), -c.template G<2>(), c.template G<3>());
  }
  static Jacobian JlInv(const Tangent& phi, const AngleSeries<Scalar>& c) {
    return skewSeries(phi, c.theta2(), Scalar(1), Scalar(-0.5), c.jlInvD());
  }

  // Rotation vector of a rotation matrix. With c = cos theta = (trace R - 1)/2 and
  // s = vee(R - R^T)/2 = sin(theta) u, the angle is the one asin that is well conditioned,
  // asin of whichever of |s| = sin theta and |c| is smaller (at most 1/sqrt 2):
  //   theta = asin|s| (theta < pi/4),  pi/2 - asin(c) (otherwise),  pi - asin|s| (theta > 3pi/4).
  // The axis is s/|s| unless theta is near pi, where s vanishes and its rounding would tilt the
  // axis; there (c < kNearPiCos) the axis is the column of the symmetric part
  // (R + R^T)/2 - c I = (1 - c) u u^T with the largest diagonal entry, signed to agree with s.
  // Optionally hands back the AngleSeries of theta, built from sin theta and cos theta.
  static Tangent logOfMatrix(const Matrix& R, AngleSeries<Scalar>* series = nullptr) {
    using std::abs;
    using std::asin;
    using std::sqrt;
    const Scalar pi(3.141592653589793238462643383279502884L), halfPi = pi / Scalar(2);
    const Scalar c = (R(0, 0) + R(1, 1) + R(2, 2) - Scalar(1)) / Scalar(2);
    const Tangent s = Tangent(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1)) / Scalar(2);
    // sin theta. At R = I it is 0 and so is its derivative: sqrt(0) would give an autodiff
    // scalar an infinite one, hence the guard (with phi = s below, d phi = d s there).
    const Scalar n2 = s.squaredNorm();
    const Scalar n = n2 > Scalar(0) ? Scalar(sqrt(n2)) : Scalar(0);
    const bool nearAxis = n < abs(c);  // theta within pi/4 of 0 or of pi
    const Scalar a = asin(nearAxis ? n : c);
    const Scalar theta = nearAxis ? (c > Scalar(0) ? a : Scalar(pi - a)) : Scalar(halfPi - a);
    if (series) *series = AngleSeries<Scalar>(theta, n, c);
    if (c >= kNearPiCos)
      return (n > Scalar(0) ? Scalar(theta / n) : Scalar(1)) * s;  // theta/sin theta
    // Column i of the symmetric part, i the largest diagonal entry: (1 - c) u_i u.
    int i = R(1, 1) > R(0, 0) ? 1 : 0;
    if (R(2, 2) > R(i, i)) i = 2;
    Tangent axis = (R.col(i) + R.row(i).transpose()) / Scalar(2);
    axis(i) -= c;
    const Scalar axisNorm = axis.norm();
    const Scalar norm = axis.dot(s) < Scalar(0) ? Scalar(-axisNorm) : axisNorm;
    return (theta / norm) * axis;
  }

  // cos theta below which Log takes the axis from the symmetric part (theta > 2.69): there the
  // rounding of s, divided by sin theta < 0.44, would cost more than a few ulp of phi.
  static constexpr double kNearPiCos = -0.9;

 private:
  template <typename, int, int>
  friend class SEK3;
  struct Unchecked {};
  SO3(const Matrix& R, Unchecked) : R_(R) {}

  Matrix R_;
};

using SO3d = SO3<double>;

}  // namespace lie
