// Exercise 57.5.2: what the right-invariant error measures, why it evolves without the state, and
// what that buys the covariance propagation. States are SE_2(3) elements X = (R, v, p)
// (lie::SE23d); tangent vectors are ordered (rotation, velocity, position).
#pragma once

#include <Eigen/Core>
#include <lie/sek3.hpp>

namespace ex57_5_2 {

using Vector9d = Eigen::Matrix<double, 9, 1>;
using Matrix9d = Eigen::Matrix<double, 9, 9>;

// One IMU sample, bias-free, held over dt: body rate w [rad/s] and specific force a [m/s^2].
struct ImuInput {
  Eigen::Vector3d w;
  Eigen::Vector3d a;
  double dt;
};

// (a) The right-invariant error xi = Log(X_hat X^-1) of an estimate X_hat of the truth X.
Vector9d rightInvariantError(const lie::SE23d& X_hat, const lie::SE23d& X);

// (b) Apply the same IMU step to the estimate and to the truth (exactly, with gravity g) and
// return the right-invariant error after the step.
Vector9d errorAfterStep(const lie::SE23d& X_hat, const lie::SE23d& X, const ImuInput& u,
                        const Eigen::Vector3d& g);

// (b) The error-transition matrix of that step at the truth X: the derivative of the error after
// the step with respect to the error before it, d xi_{k+1} / d xi_k at xi_k = 0, by central
// differences of step h, with X_hat = Exp(xi_k) X.
Matrix9d errorTransition(const lie::SE23d& X, const ImuInput& u, const Eigen::Vector3d& g,
                         double h);

// (c) The same for the ESKF's error e = (dtheta, dv, dp) at the estimate X_hat, with the truth
// R = R_hat Exp(dtheta), v = v_hat + dv, p = p_hat + dp: d e_{k+1} / d e_k at e_k = 0.
Matrix9d eskfErrorTransition(const lie::SE23d& X_hat, const ImuInput& u, const Eigen::Vector3d& g,
                             double h);

// (c) The closed-form transition of the right-invariant error over dt:
// Phi = I + A dt + A^2 dt^2 / 2 with A = [[0, 0, 0], [[g]_x, 0, 0], [0, I, 0]].
Matrix9d closedFormPhi(const Eigen::Vector3d& g, double dt);

}  // namespace ex57_5_2
