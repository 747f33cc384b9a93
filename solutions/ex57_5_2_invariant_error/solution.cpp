// Reference solution to exercise 57.5.2.
#include <lie/imu_dynamics.hpp>

#include "ex57_5_2.hpp"

namespace ex57_5_2 {

namespace {

lie::SE23d step(const lie::SE23d& X, const ImuInput& u, const Eigen::Vector3d& g) {
  return lie::imu::propagate(X, u.w, u.a, g, u.dt);
}

// The ESKF's error of the estimate X_hat against the truth X: (Log(R_hat^T R), v - v_hat,
// p - p_hat), and its inverse (the truth at error e).
Vector9d eskfError(const lie::SE23d& X_hat, const lie::SE23d& X) {
  Vector9d e;
  e << lie::SO3d::fromMatrix(X_hat.R().transpose() * X.R(), 1e-6).Log(), X.col(0) - X_hat.col(0),
      X.col(1) - X_hat.col(1);
  return e;
}
lie::SE23d eskfTruth(const lie::SE23d& X_hat, const Vector9d& e) {
  lie::SE23d::Columns C;
  C << X_hat.col(0) + e.segment<3>(3), X_hat.col(1) + e.segment<3>(6);
  return lie::SE23d(lie::SO3d(X_hat.rotation() * lie::SO3d::Exp(e.head<3>())), C);
}

}  // namespace

// eta = X_hat X^-1 = (R_hat R^T, v_hat - R_hat R^T v, p_hat - R_hat R^T p): the rigid motion of
// the world frame that carries the true state onto the estimate.
Vector9d rightInvariantError(const lie::SE23d& X_hat, const lie::SE23d& X) {
  return (X_hat * X.inverse()).Log();
}

Vector9d errorAfterStep(const lie::SE23d& X_hat, const lie::SE23d& X, const ImuInput& u,
                        const Eigen::Vector3d& g) {
  return rightInvariantError(step(X_hat, u, g), step(X, u, g));
}

Matrix9d errorTransition(const lie::SE23d& X, const ImuInput& u, const Eigen::Vector3d& g,
                         double h) {
  Matrix9d Phi;
  for (int j = 0; j < 9; ++j) {
    const Vector9d dxi = h * Vector9d::Unit(j);
    Phi.col(j) = (errorAfterStep(lie::SE23d::Exp(dxi) * X, X, u, g) -
                  errorAfterStep(lie::SE23d::Exp(-dxi) * X, X, u, g)) /
                 (2 * h);
  }
  return Phi;
}

Matrix9d eskfErrorTransition(const lie::SE23d& X_hat, const ImuInput& u, const Eigen::Vector3d& g,
                             double h) {
  const lie::SE23d next = step(X_hat, u, g);
  Matrix9d F;
  for (int j = 0; j < 9; ++j) {
    const Vector9d de = h * Vector9d::Unit(j);
    F.col(j) = (eskfError(next, step(eskfTruth(X_hat, de), u, g)) -
                eskfError(next, step(eskfTruth(X_hat, -de), u, g))) /
               (2 * h);
  }
  return F;
}

Matrix9d closedFormPhi(const Eigen::Vector3d& g, double dt) {
  Matrix9d Phi = Matrix9d::Identity();
  const Eigen::Matrix3d G = lie::hat3(g);
  Phi.block<3, 3>(3, 0) = G * dt;                            // v <- phi
  Phi.block<3, 3>(6, 0) = 0.5 * G * dt * dt;                 // p <- phi
  Phi.block<3, 3>(6, 3) = Eigen::Matrix3d::Identity() * dt;  // p <- v
  return Phi;
}

}  // namespace ex57_5_2
