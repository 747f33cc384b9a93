// Exercise 57.5.2: the right-invariant error measures the world-frame rigid motion between truth
// and estimate; with the same IMU input it evolves identically whatever the state (log-linear,
// with a transition matrix that depends on g and dt only); the ESKF's error transition depends on
// the estimate and the input.
#include <catch2/catch.hpp>
#include <lie/imu_dynamics.hpp>
#include <lie/sek3.hpp>
#include <random>
#include <unsupported/Eigen/MatrixFunctions>

#include "ex57_5_2.hpp"
#include "exercises/exercise_check.hpp"

using ex57_5_2::ImuInput;
using ex57_5_2::Matrix9d;
using ex57_5_2::Vector9d;

namespace {

const Eigen::Vector3d kGravity(0.0, 0.0, -9.81);

ImuInput randomInput(std::mt19937& gen, double dt) {
  std::normal_distribution<double> n(0.0, 1.0);
  return {Eigen::Vector3d(n(gen), n(gen), n(gen)),
          Eigen::Vector3d(3 * n(gen), 3 * n(gen), 9.81 + 3 * n(gen)), dt};
}

double maxAbs(const Eigen::MatrixXd& M) {
  return M.cwiseAbs().maxCoeff();
}

}  // namespace

TEST_CASE("57.5.2 (a) eta is the world-frame rigid motion from the truth to the estimate",
          "[ex57.5.2][hint 1]") {
  std::mt19937 gen(1);
  // A world-frame motion T: turn 0.4 rad about world z, shift by s, add a velocity offset.
  Vector9d t;
  t << 0.0, 0.0, 0.4, 0.3, -0.2, 0.0, 1.0, 2.0, -0.5;
  const lie::SE23d T = lie::SE23d::Exp(t);
  for (int i = 0; i < 20; ++i) {
    const lie::SE23d X = lie::SE23d::Random(gen, 3.0);
    REQUIRE_NEAR(ex57_5_2::rightInvariantError(X, X), Vector9d::Zero(), 1e-12);
    // Moving the truth by T in the world gives the same error Log(T) at every state.
    REQUIRE_NEAR(ex57_5_2::rightInvariantError(T * X, X), t, 1e-12);
    const lie::SE23d Y = lie::SE23d::Random(gen, 3.0);
    REQUIRE_NEAR(ex57_5_2::rightInvariantError(Y, X), (Y * X.inverse()).Log(), 1e-12);
  }
}

TEST_CASE("57.5.2 (b) the error evolves the same way whatever the state", "[ex57.5.2][hint 2]") {
  std::mt19937 gen(2);
  // Two very different truths with the same (large) initial error eta_0.
  Vector9d xi0;
  xi0 << 0.5, -0.4, 0.8, 1.0, -0.5, 0.3, 2.0, 1.0, -1.5;
  lie::SE23d X1 = lie::SE23d::Random(gen, 5.0), X2 = lie::SE23d::Random(gen, 5.0);
  lie::SE23d X1_hat = lie::SE23d::Exp(xi0) * X1, X2_hat = lie::SE23d::Exp(xi0) * X2;
  Vector9d predicted = xi0;
  double worst = 0.0;
  for (int k = 0; k < 200; ++k) {
    const ImuInput u = randomInput(gen, 0.005);
    const Vector9d e1 = ex57_5_2::errorAfterStep(X1_hat, X1, u, kGravity);
    const Vector9d e2 = ex57_5_2::errorAfterStep(X2_hat, X2, u, kGravity);
    predicted = (ex57_5_2::closedFormPhi(kGravity, u.dt) * predicted).eval();
    worst = std::max({worst, (e1 - e2).norm(), (e1 - predicted).norm()});
    X1 = lie::imu::propagate(X1, u.w, u.a, kGravity, u.dt);
    X2 = lie::imu::propagate(X2, u.w, u.a, kGravity, u.dt);
    X1_hat = lie::imu::propagate(X1_hat, u.w, u.a, kGravity, u.dt);
    X2_hat = lie::imu::propagate(X2_hat, u.w, u.a, kGravity, u.dt);
  }
  WARN("57.5.2 (b): largest difference between the two errors, and from Phi xi, over 1 s: "
       << worst << " (the error itself grew to " << predicted.norm() << ")");
  REQUIRE_BELOW(worst, 1e-9 * predicted.norm());
  REQUIRE_ABOVE((predicted - xi0).norm(), 1.0);  // the error did change: not a trivial check
}

TEST_CASE("57.5.2 (b) the error transition is the same at every state and input",
          "[ex57.5.2][hint 3]") {
  std::mt19937 gen(3);
  const double dt = 0.01;
  const Matrix9d Phi = ex57_5_2::closedFormPhi(kGravity, dt);
  Matrix9d A = Matrix9d::Zero();
  A.block<3, 3>(3, 0) = lie::hat3(kGravity);
  A.block<3, 3>(6, 3).setIdentity();
  const Matrix9d exact = (A * dt).exp();
  REQUIRE_NEAR(Phi, exact, 1e-14);
  // a constant-coefficient flow: Phi(s) Phi(t) = Phi(s + t)
  REQUIRE_NEAR(ex57_5_2::closedFormPhi(kGravity, 0.004) * ex57_5_2::closedFormPhi(kGravity, 0.006),
               Phi, 1e-14);
  for (int i = 0; i < 10; ++i) {
    const lie::SE23d X = lie::SE23d::Random(gen, 5.0);
    const ImuInput u = randomInput(gen, dt);
    const Matrix9d numeric = ex57_5_2::errorTransition(X, u, kGravity, 1e-5);
    REQUIRE_NEAR(numeric, Phi, 1e-7);
  }
}

TEST_CASE("57.5.2 (c) the ESKF's error transition depends on the estimate and the input",
          "[ex57.5.2]") {
  std::mt19937 gen(4);
  const double dt = 0.01;
  const lie::SE23d X1 = lie::SE23d::Random(gen, 5.0), X2 = lie::SE23d::Random(gen, 5.0);
  const ImuInput u1 = randomInput(gen, dt), u2 = randomInput(gen, dt);
  const Matrix9d F11 = ex57_5_2::eskfErrorTransition(X1, u1, kGravity, 1e-5);
  const Matrix9d F21 = ex57_5_2::eskfErrorTransition(X2, u1, kGravity, 1e-5);
  const Matrix9d F12 = ex57_5_2::eskfErrorTransition(X1, u2, kGravity, 1e-5);
  const Matrix9d I11 = ex57_5_2::errorTransition(X1, u1, kGravity, 1e-5);
  const Matrix9d I21 = ex57_5_2::errorTransition(X2, u2, kGravity, 1e-5);
  WARN("57.5.2 (c): |F(X1, u1) - F(X2, u1)| = "
       << maxAbs(F11 - F21) << ", |F(X1, u1) - F(X1, u2)| = " << maxAbs(F11 - F12)
       << "; InEKF |Phi(X1, u1) - Phi(X2, u2)| = " << maxAbs(I11 - I21));
  REQUIRE_ABOVE(maxAbs(F11 - F21), 0.01);  // another attitude: another Jacobian
  REQUIRE_ABOVE(maxAbs(F11 - F12), 0.01);  // another input: another Jacobian
  REQUIRE_BELOW(maxAbs(I11 - I21), 1e-7);  // the invariant error's does not move
  // Both describe the same motion: the ESKF's is still the identity plus O(dt).
  REQUIRE_BELOW(maxAbs(F11 - Matrix9d::Identity()), 1.0);
}
