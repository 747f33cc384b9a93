// Forster preintegration (section 57.2): the keyframe constraint, the first-order bias
// correction, and the propagated covariance against Monte Carlo.
#include <rapidcheck/catch.h>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "estimation/imu/dead_reckoning.hpp"
#include "estimation/imu/preintegration.hpp"

using legkit::imu::deadReckoningStep;
using legkit::imu::Matrix9d;
using legkit::imu::NavState;
using legkit::imu::PreintegratedDelta;
using legkit::imu::Preintegrator;
using legkit::model::ImuBias;
using legkit::model::ImuNoise;
using legkit::model::ImuReading;

namespace {

constexpr double kDt = 1e-3;

// Readings of a lively motion (trot-like rates and specific forces), deterministic in seed.
std::vector<ImuReading> lively(unsigned seed, int n) {
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Vector3d w0(u(gen), u(gen), u(gen)), a0(u(gen), u(gen), 9.81 + u(gen));
  const Eigen::Vector3d fw(5 + 3 * u(gen), 4 + 2 * u(gen), 2 + u(gen));
  std::vector<ImuReading> m(n);
  for (int k = 0; k < n; ++k) {
    const double t = k * kDt;
    m[k].w_m = w0 + 1.5 * Eigen::Vector3d(std::sin(fw(0) * t), std::cos(fw(1) * t),
                                          std::sin(fw(2) * t + 1.0));
    m[k].a_m =
        a0 + 3.0 * Eigen::Vector3d(std::cos(fw(1) * t), std::sin(fw(2) * t), std::sin(fw(0) * t));
  }
  return m;
}

Preintegrator preintegrate(const std::vector<ImuReading>& m, const ImuBias& b,
                           const ImuNoise& noise = ImuNoise::go2()) {
  Preintegrator pre(b, noise);
  for (const ImuReading& r : m) pre.integrate(r, kDt);
  return pre;
}

// Difference of two sets of increments as (dphi, dv, dp), rotation on the right.
Eigen::Matrix<double, 9, 1> minus(const PreintegratedDelta& a, const PreintegratedDelta& b) {
  Eigen::Matrix<double, 9, 1> e;
  e << a.dR.rminus(b.dR), a.dv - b.dv, a.dp - b.dp;
  return e;
}

}  // namespace

TEST_CASE("57.2 the keyframe constraint reproduces step-by-step dead reckoning",
          "[preintegration]") {
  const std::vector<ImuReading> m = lively(11, 500);
  const ImuBias b{Eigen::Vector3d(0.02, -0.01, 0.03), Eigen::Vector3d(0.1, -0.05, 0.2)};
  NavState x{lie::SO3d::Exp(Eigen::Vector3d(0.3, -0.6, 2.0)), Eigen::Vector3d(0.5, -0.2, 0.1),
             Eigen::Vector3d(1.0, 2.0, 0.3)};
  const NavState x_i = x;
  for (const ImuReading& r : m) x = deadReckoningStep(x, r, b, kDt);
  const NavState x_j = preintegrate(m, b).predict(x_i, b);
  CHECK(x_j.R.isApprox(x.R, 1e-12));
  CHECK((x_j.v - x.v).norm() < 1e-11);
  CHECK((x_j.p - x.p).norm() < 1e-11);
}

TEST_CASE("57.2 property: the constraint holds for any motion and keyframe state",
          "[preintegration]") {
  rc::prop("predict(x_i) equals dead reckoning from x_i", [](unsigned seed) {
    const std::vector<ImuReading> m = lively(seed, 200);
    std::mt19937_64 gen(seed);
    const lie::SO3d R_i = lie::SO3d::Random(gen);
    std::normal_distribution<double> n(0.0, 1.0);
    NavState x{R_i, Eigen::Vector3d(n(gen), n(gen), n(gen)), Eigen::Vector3d(n(gen), n(gen), 0)};
    const NavState x_i = x;
    for (const ImuReading& r : m) x = deadReckoningStep(x, r, ImuBias{}, kDt);
    const NavState x_j = preintegrate(m, ImuBias{}).predict(x_i, ImuBias{});
    RC_ASSERT(x_j.R.isApprox(x.R, 1e-12));
    RC_ASSERT((x_j.v - x.v).norm() < 1e-11);
    RC_ASSERT((x_j.p - x.p).norm() < 1e-11);
  });
}

TEST_CASE("57.2 first-order bias correction is second-order accurate", "[preintegration]") {
  // Correcting the increments for b0 + db with the Jacobians leaves an O(|db|^2) error against
  // re-integration at b0 + db: halving db divides the error by about 4.
  const std::vector<ImuReading> m = lively(5, 300);
  const ImuBias b0{Eigen::Vector3d(0.01, 0.02, -0.01), Eigen::Vector3d(0.05, 0.0, -0.1)};
  const Preintegrator pre = preintegrate(m, b0);
  const Eigen::Vector3d dbg_dir(0.3, -0.2, 0.25), dba_dir(0.5, 0.4, -0.6);
  double previous = 0.0;
  for (int h = 0; h < 5; ++h) {
    const double s = std::pow(0.5, h);
    const ImuBias b{b0.b_g + s * dbg_dir, b0.b_a + s * dba_dir};
    const double e = minus(pre.corrected(b), preintegrate(m, b).delta()).norm();
    const double uncorrected = minus(pre.delta(), preintegrate(m, b).delta()).norm();
    INFO("scale " << s << ": corrected " << e << ", uncorrected " << uncorrected);
    CHECK(e < 0.1 * s * uncorrected);  // the correction removes the first-order part
    if (h > 0) CHECK(previous / e == Approx(4.0).epsilon(0.1));
    previous = e;
  }
}

TEST_CASE("57.2 the bias Jacobians match finite differences", "[preintegration]") {
  const std::vector<ImuReading> m = lively(8, 200);
  const ImuBias b0;
  const Preintegrator pre = preintegrate(m, b0);
  const double h = 1e-6;
  for (int i = 0; i < 3; ++i) {
    ImuBias bg = b0, ba = b0;
    bg.b_g(i) += h;
    ba.b_a(i) += h;
    const Eigen::Matrix<double, 9, 1> dg = minus(preintegrate(m, bg).delta(), pre.delta()) / h;
    const Eigen::Matrix<double, 9, 1> da = minus(preintegrate(m, ba).delta(), pre.delta()) / h;
    CHECK((dg.segment<3>(0) - pre.J_R_bg().col(i)).norm() < 1e-5);
    CHECK((dg.segment<3>(3) - pre.J_v_bg().col(i)).norm() < 1e-5);
    CHECK((dg.segment<3>(6) - pre.J_p_bg().col(i)).norm() < 1e-5);
    CHECK(da.segment<3>(0).norm() < 1e-9);  // the accelerometer bias cannot rotate
    CHECK((da.segment<3>(3) - pre.J_v_ba().col(i)).norm() < 1e-5);
    CHECK((da.segment<3>(6) - pre.J_p_ba().col(i)).norm() < 1e-5);
  }
}

TEST_CASE("57.2 the preintegrated covariance is symmetric PSD and matches Monte Carlo",
          "[preintegration]") {
  const int n = 200, runs = 400;
  const std::vector<ImuReading> truth = lively(21, n);
  ImuNoise noise = ImuNoise::go2();
  noise.gyro_bias_random_walk = 0.0;  // the 9x9 covariance is that of the white noise
  noise.accel_bias_random_walk = 0.0;
  const Preintegrator ref = preintegrate(truth, ImuBias{}, noise);
  const Matrix9d& Sigma = ref.covariance();
  CHECK((Sigma - Sigma.transpose()).norm() == 0.0);
  const Eigen::SelfAdjointEigenSolver<Matrix9d> eig(Sigma);
  CHECK(eig.eigenvalues().minCoeff() > 0.0);

  std::mt19937_64 gen(2026);
  std::normal_distribution<double> unit(0.0, 1.0);
  const Matrix9d Sigma_inv = Sigma.inverse();
  Matrix9d S = Matrix9d::Zero();
  double nees = 0.0;
  for (int r = 0; r < runs; ++r) {
    Preintegrator noisy(ImuBias{}, noise);
    for (const ImuReading& t : truth) {
      ImuReading m = t;
      for (int i = 0; i < 3; ++i) {
        m.w_m(i) += noise.gyroSampleSigma(kDt) * unit(gen);
        m.a_m(i) += noise.accelSampleSigma(kDt) * unit(gen);
      }
      noisy.integrate(m, kDt);
    }
    const Eigen::Matrix<double, 9, 1> e = minus(noisy.delta(), ref.delta());
    S += e * e.transpose() / runs;
    nees += e.dot(Sigma_inv * e) / runs;
  }
  // runs * mean NEES ~ chi-square(9 runs): mean 9, std sqrt(18 / runs) = 0.21.
  CHECK(nees == Approx(9.0).margin(0.7));
  for (int i = 0; i < 9; ++i) CHECK(S(i, i) / Sigma(i, i) == Approx(1.0).margin(0.25));
}

TEST_CASE("57.2 preintegration rejects bad input and stays unchanged", "[preintegration]") {
  Preintegrator pre;
  pre.integrate(ImuReading{Eigen::Vector3d(0.1, 0, 0), Eigen::Vector3d(0, 0, 9.81)}, kDt);
  const PreintegratedDelta before = pre.delta();
  ImuReading bad{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  bad.w_m(1) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(pre.integrate(bad, kDt), std::invalid_argument);
  CHECK_THROWS_AS(pre.integrate(ImuReading{}, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(pre.integrate(ImuReading{}, -kDt), std::invalid_argument);
  CHECK(pre.dt_ij() == kDt);
  CHECK(minus(pre.delta(), before).norm() == 0.0);
  ImuBias nan_bias;
  nan_bias.b_a(0) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(Preintegrator(nan_bias), std::invalid_argument);
}
