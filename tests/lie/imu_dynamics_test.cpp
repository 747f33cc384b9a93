// lie::imu: the closed-form Phi against a matrix exponential, the log-linearity of the
// right-invariant error (the chapter's central claim, over 2000 steps from a far-away
// estimate), the exact bias block of phiWithBias against central differences of the true
// propagation, and propagate against a fine RK4 integration of the ODE.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <random>
#include <unsupported/Eigen/MatrixFunctions>

#include "lie_test_support.hpp"

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using lietest::maxAbsDiff;

using SEK3_6 = lie::SEK3<double, 6>;
using SEKd6 = lie::SEKd<double, 6>;

namespace {

const Vector3d kGravity(0, 0, -9.81);

// The continuous error dynamics A of the header comment, on (phi, v, p, d_1..d_n).
MatrixXd errorDynamicsA(Eigen::Index numCols, const Vector3d& g) {
  const Eigen::Index n = 3 + 3 * numCols;
  MatrixXd A = MatrixXd::Zero(n, n);
  A.block<3, 3>(3, 0) = lie::hat3(g);
  A.block<3, 3>(6, 3).setIdentity();
  return A;
}

// Time-varying, non-trivial inputs (rates up to ~2 rad/s, specific force around 1 g).
Vector3d gyro(double t) {
  return Vector3d(1.5 * std::sin(0.7 * t), 0.8 * std::cos(1.3 * t), 0.4 + std::sin(2.1 * t));
}
Vector3d accel(double t) {
  return Vector3d(2 * std::sin(t), -1.5 * std::cos(0.5 * t), 9.81 + 3 * std::sin(1.7 * t));
}

// LEGKIT_IMU_REPORT=1 prints the measured errors behind the tolerances.
void report(const char* what, double value) {
  if (std::getenv("LEGKIT_IMU_REPORT")) std::cout << what << ": " << value << "\n";
}

template <typename Group>
Group randomState(std::mt19937& gen, Eigen::Index k, double scale) {
  return Group::Random(gen, scale, k);
}

}  // namespace

TEMPLATE_TEST_CASE("imu::phi is the matrix exponential of A dt", "[lie][imu]", lie::SE23d, SEK3_6,
                   SEKd6) {
  using G = TestType;
  for (int k = G::kDynamic ? 2 : G::K; k <= G::MaxK; ++k) {
    for (const double dt : {1e-4, 1e-3, 0.01, 0.1, 1.0, 5.0}) {
      CAPTURE(k, dt);
      const MatrixXd expected = (errorDynamicsA(k, kGravity) * dt).exp();
      const MatrixXd F = lie::imu::phi<G>(k, kGravity, dt);
      CHECK(maxAbsDiff(F, expected) <= 1e-14 * expected.cwiseAbs().maxCoeff());
      report("phi vs exp(A dt), relative",
             maxAbsDiff(F, expected) / expected.cwiseAbs().maxCoeff());
    }
  }
}

// Log-linearity: with the same noise-free input for truth and estimate, the right-invariant
// error eta = X_hat X^-1 obeys Log(eta_t) = Phi_total Log(eta_0) EXACTLY, however large the
// initial error (here 1.9 rad, metres, m/s, and moved feet). Nothing is linearised.
TEMPLATE_TEST_CASE("the right-invariant error is log-linear", "[lie][imu]", SEK3_6, SEKd6) {
  using G = TestType;
  std::mt19937 gen(2026);
  const int k = 6;  // v, p and 4 feet
  const G X0 = randomState<G>(gen, k, 3.0);
  typename G::Tangent xi0(3 + 3 * k);
  xi0 << 1.1, -0.9, 1.2,                                               // rotation error of 1.9 rad
      1.5, -2.0, 0.7,                                                  // velocity, m/s
      4.0, 3.0, -2.5,                                                  // position, m
      0.3, -0.2, 0.1, -0.5, 0.4, 0.2, 1.0, 0.0, -0.3, 0.2, 0.6, -0.7;  // feet, m
  G X = X0;
  G Xhat = G::Exp(xi0) * X0;
  const typename G::Tangent start = (Xhat * X.inverse()).Log();
  REQUIRE(maxAbsDiff(start, xi0) <= 1e-13);

  const double dt = 0.005;
  const int steps = 2000;  // 10 s
  const MatrixXd Phi = lie::imu::phi<G>(k, kGravity, dt);
  MatrixXd PhiTotal = MatrixXd::Identity(start.size(), start.size());
  for (int i = 0; i < steps; ++i) {
    const double t = i * dt;
    const Vector3d w = gyro(t), a = accel(t);
    X = lie::imu::propagate(X, w, a, kGravity, dt);
    Xhat = lie::imu::propagate(Xhat, w, a, kGravity, dt);
    PhiTotal = Phi * PhiTotal;
  }
  const VectorXd predicted = PhiTotal * VectorXd(start);
  const VectorXd actual = (Xhat * X.inverse()).Log();
  CAPTURE(predicted.transpose(), actual.transpose());
  // The error really changed (position error grows by ~g t^2 |phi|): the test is not trivial.
  CHECK((predicted - VectorXd(start)).norm() > 100);
  CHECK(maxAbsDiff(actual, predicted) <= 1e-9 * predicted.cwiseAbs().maxCoeff());
  report("log-linearity: max |Log(eta_N) - Phi_total xi_0| / max |Phi_total xi_0|",
         maxAbsDiff(actual, predicted) / predicted.cwiseAbs().maxCoeff());
  // The truth went somewhere (the states are not static).
  CHECK((X.col(1) - X0.col(1)).norm() > 1);
}

// phiWithBias: the bias columns -Ad_{X_hat_next} J_u are the exact derivative of the one-step
// error with respect to the bias error zeta, for piecewise-constant input. Checked by central
// differences of the true propagation (truth uses u_hat + zeta, estimate u_hat, both from the
// same X), at dt = 0.05 and rates of ~4 rad/s where a first-order (I + A dt) bias block is
// visibly wrong.
TEMPLATE_TEST_CASE("imu::phiWithBias has the exact bias block", "[lie][imu]", lie::SE23d, SEK3_6,
                   SEKd6) {
  using G = TestType;
  std::mt19937 gen(77);
  for (int k = G::kDynamic ? 2 : G::K; k <= G::MaxK; k += 2) {
    CAPTURE(k);
    const G X = randomState<G>(gen, k, 3.0);
    const Vector3d w(3.0, -2.0, 1.5), a(2.0, -1.0, 9.0);
    const double dt = 0.05;
    const G Xhat = lie::imu::propagate(X, w, a, kGravity, dt);
    const auto F = lie::imu::phiWithBias(Xhat, w, a, kGravity, dt);
    const Eigen::Index n = Xhat.dof();
    REQUIRE(F.rows() == n + 6);
    CHECK(maxAbsDiff(F.topLeftCorner(n, n), MatrixXd(lie::imu::phi<G>(k, kGravity, dt))) == 0.0);
    CHECK(F.bottomLeftCorner(6, n).isZero(0.0));
    CHECK(F.bottomRightCorner(6, 6).isIdentity(0.0));
    const MatrixXd B = F.topRightCorner(n, 6);

    const double h = 1e-6;
    MatrixXd numeric(n, 6);
    for (int j = 0; j < 6; ++j) {
      const auto errorAfterStep = [&](double s) {
        Eigen::Matrix<double, 6, 1> zeta = Eigen::Matrix<double, 6, 1>::Zero();
        zeta(j) = s;
        const G Xtrue = lie::imu::propagate(X, Vector3d(w + zeta.head<3>()),
                                            Vector3d(a + zeta.tail<3>()), kGravity, dt);
        return VectorXd((Xhat * Xtrue.inverse()).Log());
      };
      numeric.col(j) = (errorAfterStep(h) - errorAfterStep(-h)) / (2 * h);
    }
    const double scale = B.cwiseAbs().maxCoeff();
    const double tol = 1e-7 * scale;
    CHECK(maxAbsDiff(B, numeric) <= tol);
    report("bias block vs central differences, relative to the block",
           maxAbsDiff(B, numeric) / scale);

    // The first-order bias block of the widely used implementation (Hartley's A times dt):
    // -Ad_X [[I dt, 0], [0, I dt], [0, 0], ...]. It differs from the exact one by O(dt^2), far
    // more than the tolerance above: the check above can tell them apart.
    MatrixXd firstOrder = MatrixXd::Zero(n, 6);
    firstOrder.block<3, 3>(0, 0) = Matrix3d::Identity() * dt;
    firstOrder.block<3, 3>(3, 3) = Matrix3d::Identity() * dt;
    firstOrder = -MatrixXd(Xhat.Adj()) * firstOrder;
    CHECK(maxAbsDiff(firstOrder, B) > 100 * tol);
    CHECK(maxAbsDiff(firstOrder, numeric) > 100 * tol);
    report("first-order bias block vs exact, relative to the block",
           maxAbsDiff(firstOrder, B) / scale);
  }
}

// The increment Jacobian is right at tiny rotation increments too (the Taylor branches).
TEST_CASE("imu::phiWithBias at tiny rates", "[lie][imu]") {
  std::mt19937 gen(3);
  const lie::SE23d X = lie::SE23d::Random(gen, 2.0);
  for (const double rate : {0.0, 1e-9, 1e-5, 1e-2}) {
    const Vector3d w = rate * Vector3d(0.6, 0.0, -0.8), a(0.5, 1.0, 9.5);
    const double dt = 0.01;
    const lie::SE23d Xhat = lie::imu::propagate(X, w, a, kGravity, dt);
    const MatrixXd B = lie::imu::phiWithBias(Xhat, w, a, kGravity, dt).topRightCorner(9, 6);
    MatrixXd numeric(9, 6);
    const double h = 1e-6;
    for (int j = 0; j < 6; ++j) {
      const auto errorAfterStep = [&](double s) {
        Vector3d dw = Vector3d::Zero(), da = Vector3d::Zero();
        (j < 3 ? dw : da)(j % 3) = s;
        return VectorXd(
            (Xhat *
             lie::imu::propagate(X, Vector3d(w + dw), Vector3d(a + da), kGravity, dt).inverse())
                .Log());
      };
      numeric.col(j) = (errorAfterStep(h) - errorAfterStep(-h)) / (2 * h);
    }
    CAPTURE(rate);
    CHECK(maxAbsDiff(B, numeric) <= 1e-7 * B.cwiseAbs().maxCoeff());
  }
}

// propagate is the exact solution for constant input: compare with RK4 on
// dR/dt = R [w]_x, dv/dt = R a + g, dp/dt = v (1e5 steps: its error is ~1e-20, rounding ~1e-12).
TEMPLATE_TEST_CASE("imu::propagate solves the ODE", "[lie][imu]", lie::SE23d, SEK3_6, SEKd6) {
  using G = TestType;
  std::mt19937 gen(9);
  struct Case {
    Vector3d w, a;
    double dt;
  };
  const Case cases[] = {{Vector3d(0.8, -0.5, 1.2), Vector3d(1.0, -2.0, 9.5), 1.0},
                        {Vector3d(-3.0, 4.0, 4.0), Vector3d(0.5, 0.5, 12.0), 0.5},  // 3.2 rad
                        {Vector3d(1e-4, 2e-4, -1e-4), Vector3d(0.1, 0.0, 9.8), 0.02},
                        {Vector3d::Zero(), Vector3d(0.0, 1.0, 9.81), 0.3}};
  for (const Case& c : cases) {
    const G X = randomState<G>(gen, G::kDynamic ? 4 : G::K, 2.0);
    const G Y = lie::imu::propagate(X, c.w, c.a, kGravity, c.dt);

    Matrix3d R = X.R();
    Vector3d v = X.col(0), p = X.col(1);
    const int substeps = 100000;
    const double h = c.dt / substeps;
    const Matrix3d W = lie::hat3(c.w);
    struct Deriv {
      Matrix3d dR;
      Vector3d dv, dp;
    };
    const auto f = [&](const Matrix3d& Rs, const Vector3d& vs) {
      return Deriv{Rs * W, Rs * c.a + kGravity, vs};
    };
    for (int i = 0; i < substeps; ++i) {
      const Deriv k1 = f(R, v);
      const Deriv k2 = f(R + 0.5 * h * k1.dR, v + 0.5 * h * k1.dv);
      const Deriv k3 = f(R + 0.5 * h * k2.dR, v + 0.5 * h * k2.dv);
      const Deriv k4 = f(R + h * k3.dR, v + h * k3.dv);
      R += h / 6 * (k1.dR + 2 * k2.dR + 2 * k3.dR + k4.dR);
      v += h / 6 * (k1.dv + 2 * k2.dv + 2 * k3.dv + k4.dv);
      p += h / 6 * (k1.dp + 2 * k2.dp + 2 * k3.dp + k4.dp);
    }
    CAPTURE(c.w.transpose(), c.dt);
    CHECK(maxAbsDiff(Y.R(), R) <= 1e-10);
    report("propagate vs RK4: rotation", maxAbsDiff(Y.R(), R));
    report("propagate vs RK4: position, relative", maxAbsDiff(Y.col(1), p) / (1 + p.norm()));
    CHECK(maxAbsDiff(Y.col(0), v) <= 1e-10 * (1 + v.norm()));
    CHECK(maxAbsDiff(Y.col(1), p) <= 1e-10 * (1 + p.norm()));
    for (Eigen::Index i = 2; i < X.numCols(); ++i) CHECK(Y.col(i) == X.col(i));  // contacts stay
  }
}

TEST_CASE("the IMU dynamics refuse a group without velocity and position columns", "[lie]") {
  using SEKd6 = lie::SEKd<double, 6>;
  const SEKd6 one(1);  // a single column: SE(3), no velocity
  const Eigen::Vector3d w(0.1, 0.2, 0.3), a(0.0, 0.0, 9.81);
  CHECK_THROWS_WITH(lie::imu::propagate(one, w, a, kGravity, 1e-3),
                    Catch::Contains("needs columns v and p"));
  CHECK_THROWS_WITH(lie::imu::phi<SEKd6>(1, kGravity, 1e-3), Catch::Contains("got 1 column"));
  CHECK_THROWS_AS(lie::imu::phiWithBias(one, w, a, kGravity, 1e-3), std::invalid_argument);
  CHECK_NOTHROW(lie::imu::phiWithBias(SEKd6(2), w, a, kGravity, 1e-3));
}

TEST_CASE("act refuses a column that does not exist", "[lie]") {
  using SEKd6 = lie::SEKd<double, 6>;
  const SEKd6 X(2), none(0);
  CHECK_THROWS_AS(X.act(Eigen::Vector3d::Ones(), 2), std::out_of_range);
  CHECK_THROWS_AS(none.act(Eigen::Vector3d::Ones()), std::out_of_range);
  CHECK_NOTHROW(X.act(Eigen::Vector3d::Ones(), 1));
}
