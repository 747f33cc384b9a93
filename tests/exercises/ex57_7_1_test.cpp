// Exercise 57.7.1: the Mahalanobis slip detector, by hand values, against the kit's chi-square
// quantile (eval/consistency.hpp), by its invariance to a change of coordinates, and by its false
// alarm rate on residuals drawn from the filter's own covariance.
#include <rapidcheck/catch.h>
#include <Eigen/Cholesky>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "estimation/slip/slip_detector.hpp"
#include "eval/consistency.hpp"
#include "ex57_7_1.hpp"
#include "exercises/exercise_check.hpp"

using ex57_7_1::FootResidual;
using ex57_7_1::Matrix3x9;
using ex57_7_1::Matrix9;

namespace {

// A random symmetric positive definite n x n matrix with eigenvalues in [scale/100, scale].
template <int N>
Eigen::Matrix<double, N, N> randomSpd(std::mt19937& gen, double scale) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.01, 1.0);
  Eigen::Matrix<double, N, N> A;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) A(i, j) = n(gen);
  const Eigen::HouseholderQR<Eigen::Matrix<double, N, N>> qr(A);
  const Eigen::Matrix<double, N, N> Q = qr.householderQ();
  Eigen::Matrix<double, N, 1> d;
  for (int i = 0; i < N; ++i) d(i) = scale * u(gen);
  return Q * d.asDiagonal() * Q.transpose();
}

// A stance foot as the linear KF or the InEKF sees it: the residual depends on the attitude
// error through [v]_x and on the velocity error directly (H = [[v]_x, -I, 0]), here with a random
// velocity, residual and noise.
FootResidual randomFoot(std::mt19937& gen, int id) {
  std::normal_distribution<double> n(0.0, 1.0);
  FootResidual f;
  f.foot = id;
  const Eigen::Vector3d v(n(gen), n(gen), n(gen));
  Eigen::Matrix3d v_hat;
  v_hat << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  f.H.leftCols<3>() = v_hat;
  f.H.middleCols<3>(3) = -Eigen::Matrix3d::Identity();
  f.r = 0.1 * Eigen::Vector3d(n(gen), n(gen), n(gen));
  f.R = randomSpd<3>(gen, 1e-3);
  return f;
}

}  // namespace

TEST_CASE("57.7.1 d2 by hand", "[ex57.7.1][hint 1]") {
  // Only the velocity error enters (H = [0, I, 0]): S = P_vv + R = (0.01 + 0.0004) I.
  FootResidual f;
  f.H.middleCols<3>(3).setIdentity();
  f.R = 0.0004 * Eigen::Matrix3d::Identity();
  f.r = Eigen::Vector3d(0.1, 0.0, 0.0);
  Matrix9 P = Matrix9::Identity();
  P.block<3, 3>(3, 3) = 0.01 * Eigen::Matrix3d::Identity();
  REQUIRE_NEAR(ex57_7_1::mahalanobisSquared(f, P), 0.01 / 0.0104, 1e-12);
  // The filter's own covariance, not a fixed matrix: a filter four times less sure of its
  // velocity finds the same residual less surprising.
  P.block<3, 3>(3, 3) *= 4.0;
  REQUIRE_NEAR(ex57_7_1::mahalanobisSquared(f, P), 0.01 / 0.0404, 1e-12);
  // A correlated S (H = 0, so S = R): S = [[2, 1, 0], [1, 2, 0], [0, 0, 1]], r = (1, 1, 0):
  // S^-1 r = (1/3, 1/3, 0), d2 = 2/3.
  FootResidual g;
  g.H.setZero();
  g.R << 2.0, 1.0, 0.0, 1.0, 2.0, 0.0, 0.0, 0.0, 1.0;
  g.r = Eigen::Vector3d(1.0, 1.0, 0.0);
  REQUIRE_NEAR(ex57_7_1::mahalanobisSquared(g, P), 2.0 / 3.0, 1e-12);
}

TEST_CASE("57.7.1 the chi-square quantile is the kit's", "[ex57.7.1][hint 2]") {
  REQUIRE_NEAR(ex57_7_1::chiSquare3Quantile(0.99), 11.345, 5e-4);  // the chapter's table value
  for (const double alpha : {0.5, 0.9, 0.95, 0.99, 0.999, 0.9999}) {
    INFO("alpha " << alpha);
    REQUIRE_REL(ex57_7_1::chiSquare3Quantile(alpha), legkit::eval::chiSquareQuantile(alpha, 3.0),
                1e-9);
  }
}

TEST_CASE("57.7.1 d2 does not depend on the coordinates", "[ex57.7.1][hint 1]") {
  rc::prop("invariant to a change of state and of residual coordinates", [](unsigned seed) {
    std::mt19937 gen(seed);
    const FootResidual f = randomFoot(gen, 0);
    const Matrix9 P = randomSpd<9>(gen, 0.01);
    const double d2 = ex57_7_1::mahalanobisSquared(f, P);
    RC_ASSERT(d2 >= 0.0);
    // Another state basis e' = A e: P' = A P A^T, H' = H A^-1.
    const Matrix9 A = randomSpd<9>(gen, 1.0) + Matrix9::Identity();
    FootResidual f_state = f;
    f_state.H = f.H * A.inverse();
    const double d2_state = ex57_7_1::mahalanobisSquared(f_state, A * P * A.transpose());
    RC_ASSERT(std::abs(d2_state - d2) <= 1e-8 * (1.0 + d2));
    // Another residual frame r' = T r (a rotation and a change of units): H' = T H, R' = T R T^T.
    const Eigen::Matrix3d T = randomSpd<3>(gen, 10.0) + Eigen::Matrix3d::Identity();
    FootResidual f_frame = f;
    f_frame.r = T * f.r;
    f_frame.H = T * f.H;
    f_frame.R = T * f.R * T.transpose();
    const double d2_frame = ex57_7_1::mahalanobisSquared(f_frame, P);
    RC_ASSERT(std::abs(d2_frame - d2) <= 1e-8 * (1.0 + d2));
  });
}

TEST_CASE("57.7.1 one false alarm in a hundred, and the slipping foot found",
          "[ex57.7.1][hint 3]") {
  // Residuals drawn from the filter's own S = H P H^T + R are chi2_3 in d2: at alpha = 0.99 the
  // detector must flag 1 % of them. 4 feet x 5000 samples: 20000 draws, binomial sigma 0.07 %.
  std::mt19937 gen(5771);
  std::normal_distribution<double> n(0.0, 1.0);
  std::array<FootResidual, 4> feet;
  for (int i = 0; i < 4; ++i) feet[i] = randomFoot(gen, i);
  const Matrix9 P = randomSpd<9>(gen, 0.01);
  std::array<Eigen::Matrix3d, 4> L;
  for (int i = 0; i < 4; ++i)
    L[i] = (feet[i].H * P * feet[i].H.transpose() + feet[i].R).llt().matrixL();
  int alarms = 0, draws = 0;
  for (int k = 0; k < 5000; ++k) {
    for (int i = 0; i < 4; ++i) feet[i].r = L[i] * Eigen::Vector3d(n(gen), n(gen), n(gen));
    const ex57_7_1::SlipVerdict v = ex57_7_1::detectSlip(feet.data(), 4, P);
    for (int i = 0; i < v.num_feet; ++i) alarms += v.feet[i].slipping ? 1 : 0;
    draws += 4;
  }
  const double rate = static_cast<double>(alarms) / draws;
  REQUIRE_NEAR(rate, 0.01, 0.0025);
  // Foot 2 slips by 5 sigma of its S along x: flagged, with the ids and d2 in order, the others
  // not.
  for (int i = 0; i < 4; ++i) feet[i].r.setZero();
  feet[2].r = L[2] * Eigen::Vector3d(5.0, 0.0, 0.0);
  const ex57_7_1::SlipVerdict v = ex57_7_1::detectSlip(feet.data(), 4, P, 0.99);
  REQUIRE(v.num_feet == 4);
  for (int i = 0; i < 4; ++i) {
    INFO("foot " << i);
    REQUIRE(v.feet[i].foot == i);
    REQUIRE(v.feet[i].slipping == (i == 2));
  }
  REQUIRE_NEAR(v.feet[2].d2, 25.0, 1e-9);
}

TEST_CASE("57.7.1 d2 and the verdict are the kit's slip detector's", "[ex57.7.1][hint 1]") {
  // legkit::slip::SlipDetector (estimation/slip/slip_detector.hpp), deciding on one check, on two
  // stance feet of a filter with a random covariance; foot 1 slides 0.3 m/s backwards. Your d2
  // from the residual, the Jacobian H_i = [[v_leg,i]_x, I, 0] and the leg noise R_i the kit used
  // must be the kit's.
  std::mt19937 gen(5772);
  legkit::StepInput in;
  in.t = 2.0;
  in.dt = 0.001;
  in.imu.w_m = Eigen::Vector3d(0.1, -0.2, 0.05);
  in.imu.a_m = Eigen::Vector3d(0.0, 0.0, 9.81);
  in.num_contacts = 2;
  const Eigen::Vector3d v_base(0.5, 0.0, 0.0);
  for (int i = 0; i < 2; ++i) {
    legkit::ContactMeasurement& c = in.contacts[i];
    c.foot = i;
    c.p_body = Eigen::Vector3d(i == 0 ? 0.19 : -0.19, i == 0 ? 0.14 : -0.14, -0.3);
    c.cov = 1e-6 * Eigen::Matrix3d::Identity();
    // A foot that holds: v_body = -(w x p) - v_base (level base, R = I).
    c.v_body = Eigen::Vector3d(-in.imu.w_m.cross(c.p_body) - v_base);
  }
  *in.contacts[1].v_body += Eigen::Vector3d(0.3, 0.0, 0.0);  // v_leg,1 = v_base - 0.3 x
  legkit::EstimateSample x;
  x.t = in.t;
  x.v = v_base + Eigen::Vector3d(0.01, -0.02, 0.0);
  legkit::BaseCovariance cov;
  cov.P = randomSpd<9>(gen, 1e-3);
  // One check decides (the kit confirms a slip over 3 consecutive checks by default: at 1 kHz a
  // 1 % test alone would flag 10 samples a second).
  legkit::slip::SlipParams params;
  params.confirm_samples = 1;
  legkit::slip::SlipDetector kit(params);
  const legkit::slip::SlipReport report = kit.check(in, x, cov);
  REQUIRE(report.num_feet == 2);
  std::array<FootResidual, 2> feet;
  for (int i = 0; i < 2; ++i) {
    const legkit::slip::FootSlip& k = report.feet[i];
    feet[i].foot = k.foot;
    feet[i].r = k.residual;
    const Eigen::Vector3d& u = k.v_leg;
    feet[i].H.leftCols<3>() << 0.0, -u.z(), u.y(), u.z(), 0.0, -u.x(), -u.y(), u.x(), 0.0;
    feet[i].H.middleCols<3>(3).setIdentity();
    feet[i].R = k.R;
  }
  const ex57_7_1::SlipVerdict v = ex57_7_1::detectSlip(feet.data(), 2, cov.P, 0.99);
  for (int i = 0; i < 2; ++i) {
    INFO("foot " << i << ": the kit's d2 " << report.feet[i].d2);
    REQUIRE_REL(v.feet[i].d2, report.feet[i].d2, 1e-9);
    REQUIRE(v.feet[i].slipping == report.feet[i].slipping);
  }
  REQUIRE_FALSE(v.feet[0].slipping);
  REQUIRE(v.feet[1].slipping);
}
