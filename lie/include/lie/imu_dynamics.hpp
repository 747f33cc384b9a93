// IMU-driven dynamics on SE_{2+n}(3) and the exact transition matrix Phi of the right-invariant
// error, with and without the IMU biases.
//
// State X = (R, v, p, d_1..d_n): columns 0 and 1 are velocity and position, the rest contact
// points. Continuous dynamics with body rate w and specific force a (bias-corrected):
//   dR/dt = R [w]_x,   dv/dt = R a + g,   dp/dt = v,   dd_i/dt = 0.
// For w, a constant over dt the solution is exact and factors as (Barrau & Bonnabel 2017)
//   X_{k+1} = Gamma_g * f(X_k) * Upsilon,
//   Gamma_g  = (I, g dt, g dt^2/2, 0...)            gravity, a left translation
//   f(X)     = (R, v, p + v dt, d)                  a group automorphism
//   Upsilon  = (Exp(w dt), Gamma_1(w dt) a dt, Gamma_2(w dt) a dt^2, 0...)   the body increment.
//
// Right-invariant error eta = X_hat X^-1, xi = Log(eta). With the same input for estimate and
// truth, eta_{k+1} = Gamma_g f(eta_k) Gamma_g^-1 exactly, hence log-linearity:
//   xi_{k+1} = Phi xi_k,   Phi = Ad_{Gamma_g} Df = I + A dt + A^2 dt^2 / 2,
//   A = [[0, 0, 0], [[g]_x, 0, 0], [0, I, 0]] on (phi, v, p), zero rows for the contacts.
//
// With biases ("imperfect" IMU) the bias error zeta = b_hat - b (gyro first, then accel) enters
// through the increment: the truth uses Upsilon(u_hat + zeta), so to first order
//   xi_{k+1} = Phi xi_k - Ad_{X_hat_{k+1}} J_u zeta,
// where J_u is the right Jacobian of Upsilon with respect to its input u = (w, a):
// Upsilon(u + du) = Upsilon(u) Exp(J_u du). J_u is written in closed form with the Gamma
// functions and their derivatives, so Phi is exact for piecewise-constant input, not the
// first-order I + A dt that the widely used reference implementation takes.
#pragma once

#include <Eigen/Core>
#include <stdexcept>
#include <string>

#include "lie/sek3.hpp"
#include "lie/so3.hpp"

namespace lie::imu {

namespace detail {
// The IMU dynamics need the velocity and position columns: at least SE_2(3).
inline void requireVelocityAndPosition(Eigen::Index numCols, const char* where) {
  if (numCols < 2) {
    throw std::invalid_argument(std::string(where) +
                                ": needs columns v and p (SE_2(3) or larger), got " +
                                std::to_string(numCols) + " column(s)");
  }
}
}  // namespace detail

// d(Gamma_m(phi) a)/d(phi), m = 1 or 2:
//   Gamma_m(phi) a = a/m! + G_{m+1} phi x a + G_{m+2} phi x (phi x a), differentiated term by
//   term with d(G)/d(phi) = H phi^T.
template <int m, typename Scalar>
Matrix3<Scalar> dGammaTimesVector(const Vector3<Scalar>& phi, const Vector3<Scalar>& a,
                                  const AngleSeries<Scalar>& c) {
  static_assert(m == 1 || m == 2, "provided for Gamma_1 and Gamma_2");
  const Vector3<Scalar> pa = phi.cross(a);
  const Vector3<Scalar> ppa = phi.cross(pa);
  const Matrix3<Scalar> dTriple = phi.dot(a) * Matrix3<Scalar>::Identity() + phi * a.transpose() -
                                  Scalar(2) * a * phi.transpose();
  return -c.template G<m + 1>() * hat3(a) + c.template G<m + 2>() * dTriple +
         c.template H<m + 1>() * pa * phi.transpose() +
         c.template H<m + 2>() * ppa * phi.transpose();
}

// Exact propagation of X over dt with constant bias-corrected body rate w and specific force a.
template <typename Group>
Group propagate(const Group& X, const Vector3<typename Group::Scalar>& w,
                const Vector3<typename Group::Scalar>& a, const Vector3<typename Group::Scalar>& g,
                typename Group::Scalar dt) {
  using Scalar = typename Group::Scalar;
  detail::requireVelocityAndPosition(X.numCols(), "lie::imu::propagate");
  const Vector3<Scalar> phi = w * dt;
  const AngleSeries<Scalar> c(phi.squaredNorm());
  const Matrix3<Scalar> P = hat3(phi);
  const Matrix3<Scalar> P2 = P * P;
  const Matrix3<Scalar> I = Matrix3<Scalar>::Identity();
  const Matrix3<Scalar> dR = I + c.template G<1>() * P + c.template G<2>() * P2;
  const Vector3<Scalar> dv = (I + c.template G<2>() * P + c.template G<3>() * P2) * a * dt;
  const Vector3<Scalar> dp =
      (Scalar(0.5) * I + c.template G<3>() * P + c.template G<4>() * P2) * a * (dt * dt);
  const Vector3<Scalar> v = X.col(0);
  const Vector3<Scalar> p = X.col(1);
  typename Group::Columns C = X.columns();
  C.col(0) = v + X.R() * dv + g * dt;                                // v + R Gamma_1 a dt + g dt
  C.col(1) = p + v * dt + X.R() * dp + Scalar(0.5) * g * (dt * dt);  // p + v dt + R Gamma_2 ...
  return Group(SO3<Scalar>::fromQuaternion(Eigen::Quaternion<Scalar>(X.R() * dR)), C);
}

// Phi for a perfect IMU (no bias states); depends only on g and dt.
template <typename Group>
typename Group::Jacobian phi(Eigen::Index numCols, const Vector3<typename Group::Scalar>& g,
                             typename Group::Scalar dt) {
  using Scalar = typename Group::Scalar;
  detail::requireVelocityAndPosition(numCols, "lie::imu::phi");
  const Eigen::Index n = 3 + 3 * numCols;
  typename Group::Jacobian F = Group::Jacobian::Identity(n, n);
  const Matrix3<Scalar> G = hat3(g);
  F.template block<3, 3>(3, 0) = G * dt;                            // v <- phi
  F.template block<3, 3>(6, 0) = Scalar(0.5) * G * (dt * dt);       // p <- phi
  F.template block<3, 3>(6, 3) = Matrix3<Scalar>::Identity() * dt;  // p <- v
  return F;
}

// Right Jacobian J_u of the increment Upsilon(w, a, dt) with respect to (w, a): (3+3K) x 6.
template <typename Group>
Eigen::Matrix<typename Group::Scalar, Group::DoF, 6, 0, Group::MaxDoF, 6> incrementJacobian(
    Eigen::Index numCols, const Vector3<typename Group::Scalar>& w,
    const Vector3<typename Group::Scalar>& a, typename Group::Scalar dt) {
  using Scalar = typename Group::Scalar;
  detail::requireVelocityAndPosition(numCols, "lie::imu::incrementJacobian");
  const Vector3<Scalar> phi = w * dt;
  const AngleSeries<Scalar> c(phi.squaredNorm());
  const Matrix3<Scalar> P = hat3(phi);
  const Matrix3<Scalar> P2 = P * P;
  const Matrix3<Scalar> I = Matrix3<Scalar>::Identity();
  const Matrix3<Scalar> dRt =
      (I + c.template G<1>() * P + c.template G<2>() * P2).transpose();  // Exp(phi)^T
  const Matrix3<Scalar> Gamma1 = I + c.template G<2>() * P + c.template G<3>() * P2;
  const Matrix3<Scalar> Gamma2 = Scalar(0.5) * I + c.template G<3>() * P + c.template G<4>() * P2;
  const Scalar dt2 = dt * dt;

  Eigen::Matrix<Scalar, Group::DoF, 6, 0, Group::MaxDoF, 6> J;
  J.setZero(3 + 3 * numCols, 6);
  J.template block<3, 3>(0, 0) = Gamma1.transpose() * dt;  // Jr(phi) dt  (Jr = Gamma_1^T)
  J.template block<3, 3>(3, 0) = dRt * dGammaTimesVector<1>(phi, a, c) * dt2;
  J.template block<3, 3>(3, 3) = dRt * Gamma1 * dt;
  J.template block<3, 3>(6, 0) = dRt * dGammaTimesVector<2>(phi, a, c) * (dt2 * dt);
  J.template block<3, 3>(6, 3) = dRt * Gamma2 * dt2;
  return J;
}

// Phi of the right-invariant error augmented with the bias error (gyro, accel):
//   [[Phi, -Ad_{X_next} J_u], [0, I_6]],  X_next = propagate(X, w, a, g, dt).
template <typename Group>
Eigen::Matrix<typename Group::Scalar, Group::kDynamic ? Eigen::Dynamic : Group::DoF + 6,
              Group::kDynamic ? Eigen::Dynamic : Group::DoF + 6, 0, Group::MaxDoF + 6,
              Group::MaxDoF + 6>
phiWithBias(const Group& X_next, const Vector3<typename Group::Scalar>& w,
            const Vector3<typename Group::Scalar>& a, const Vector3<typename Group::Scalar>& g,
            typename Group::Scalar dt) {
  using Scalar = typename Group::Scalar;
  const Eigen::Index n = X_next.dof();
  Eigen::Matrix<Scalar, Group::kDynamic ? Eigen::Dynamic : Group::DoF + 6,
                Group::kDynamic ? Eigen::Dynamic : Group::DoF + 6, 0, Group::MaxDoF + 6,
                Group::MaxDoF + 6>
      F;
  F.setIdentity(n + 6, n + 6);
  F.topLeftCorner(n, n) = phi<Group>(X_next.numCols(), g, dt);
  // -Ad_X J_u block by block: Ad_X = [[R, 0], [[c_i]_x R, R]] and J_u has only the rotation,
  // velocity and position rows, so each row block is R J_phi crossed with c_i, plus R J_i.
  const auto J = incrementJacobian<Group>(X_next.numCols(), w, a, dt);
  const Matrix3<Scalar>& R = X_next.R();
  const Eigen::Matrix<Scalar, 3, 6> RJphi = R * J.template topRows<3>();
  F.template block<3, 6>(0, n) = -RJphi;
  for (Eigen::Index i = 0; i < X_next.numCols(); ++i) {
    const Vector3<Scalar> c = X_next.col(i);
    Eigen::Matrix<Scalar, 3, 6> rows;
    for (int j = 0; j < 6; ++j) rows.col(j) = -c.cross(RJphi.col(j));
    if (i < 2) rows.noalias() -= R * J.template block<3, 6>(3 + 3 * i, 0);  // v and p rows
    F.template block<3, 6>(3 + 3 * i, n) = rows;
  }
  return F;
}

}  // namespace lie::imu
