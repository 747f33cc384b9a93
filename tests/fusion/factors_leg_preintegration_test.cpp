// Leg-odometry preintegration (section 57.8, VILENS): the velocity-bias Jacobian against
// re-integration, the gyro-bias Jacobian against central differences of re-integration, the
// covariance of dp against Monte Carlo (fixed seed), bad input, and no allocation per sample.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "allocation_counter.hpp"
#include "estimation/fusion/leg_preintegration.hpp"
#include "estimation/imu/preintegration.hpp"

using Eigen::Matrix3d;
using Eigen::Vector3d;
using legkit::fusion::LegPreintegrator;
using legkit::model::ImuNoise;

namespace {

constexpr double kDt = 1e-3;
constexpr int kSamples = 200;  // 0.2 s between keyframes at 1 kHz

struct Sample {
  Vector3d w_m, v;
};

// Trot-like gyro readings and leg velocities (forward 1 m/s with a 2 Hz bounce and sway).
std::vector<Sample> motion() {
  std::vector<Sample> s(kSamples);
  for (int k = 0; k < kSamples; ++k) {
    const double t = k * kDt;
    s[k].w_m = Vector3d(0.4 * std::sin(12.6 * t), 0.3 * std::cos(12.6 * t), 0.5 + 0.2 * t);
    s[k].v = Vector3d(1.0 + 0.1 * std::sin(12.6 * t), 0.1 * std::cos(6.3 * t),
                      0.15 * std::sin(12.6 * t + 0.5));
  }
  return s;
}

const Matrix3d kSigmaV = Vector3d(0.05, 0.04, 0.08).cwiseAbs2().asDiagonal();  // [m^2/s^2]

LegPreintegrator integrate(const std::vector<Sample>& s, const Vector3d& b_g0, const Vector3d& b_v0,
                           const ImuNoise& noise = ImuNoise::go2()) {
  LegPreintegrator lpi(b_g0, b_v0, noise);
  for (const Sample& x : s) lpi.integrate(x.w_m, x.v, kSigmaV, kDt);
  return lpi;
}

}  // namespace

TEST_CASE("57.8 leg preintegration: with no rotation dp is the sum of (v_k - b_v) dt",
          "[leg_preintegration]") {
  // A noiseless gyro reading zero: dR_ik = I, Gamma_1 = I, J_R_bg = -t_k I before sample k, so
  //   dp = sum (v_k - b_v) dt,  J_p_bv = -dt_ij I,  J_p_bg = sum [v_k - b_v]_x (t_k + dt/2) dt
  // (the dt/2 is Gamma_1's rotation within the sample), covariance sum Sigma_v dt^2.
  const Vector3d b_v(0.02, -0.01, 0.03);
  LegPreintegrator lpi(Vector3d::Zero(), b_v, ImuNoise::noiseless());
  Vector3d sum = Vector3d::Zero();
  Matrix3d J_p_bg = Matrix3d::Zero();
  int k = 0;
  for (const Sample& x : motion()) {
    lpi.integrate(Vector3d::Zero(), x.v, kSigmaV, kDt);
    sum += (x.v - b_v) * kDt;
    J_p_bg += lie::hat3(Vector3d(x.v - b_v)) * (k++ * kDt + kDt / 2) * kDt;
  }
  CHECK((lpi.dp() - sum).norm() <= 1e-15);
  CHECK((lpi.J_p_bv() + kSamples * kDt * Matrix3d::Identity()).norm() <= 1e-14);
  CHECK((lpi.J_p_bg() - J_p_bg).norm() <= 1e-14);
  CHECK((lpi.covariance() - kSamples * kDt * kDt * kSigmaV).norm() <=
        1e-12 * lpi.covariance().norm());
  CHECK(lpi.dt_ij() == Approx(kSamples * kDt));
}

TEST_CASE("57.8 leg preintegration: its rotation is the IMU preintegration's",
          "[leg_preintegration]") {
  const Vector3d b_g(0.01, -0.02, 0.005);
  legkit::imu::Preintegrator pim(legkit::model::ImuBias{b_g, Vector3d::Zero()});
  LegPreintegrator lpi(b_g, Vector3d::Zero());
  for (const Sample& x : motion()) {
    pim.integrate(legkit::model::ImuReading{x.w_m, Vector3d(0, 0, 9.81)}, kDt);
    lpi.integrate(x.w_m, x.v, kSigmaV, kDt);
  }
  CHECK(lpi.dR().isApprox(pim.dR(), 1e-15));
}

TEST_CASE("57.8 leg preintegration: the velocity-bias Jacobian equals re-integration",
          "[leg_preintegration]") {
  const std::vector<Sample> s = motion();
  const Vector3d b_g0(0.01, -0.02, 0.005), b_v0(0.02, -0.01, 0.03);
  const LegPreintegrator lpi = integrate(s, b_g0, b_v0);
  // dp is linear in b_v: the correction is exact, however large the change.
  for (const Vector3d& db_v : {Vector3d(0.1, 0.0, 0.0), Vector3d(-0.05, 0.2, 0.1)}) {
    const LegPreintegrator again = integrate(s, b_g0, Vector3d(b_v0 + db_v));
    const Vector3d change = again.dp() - lpi.dp();
    REQUIRE(change.norm() > 0.01);
    CHECK((lpi.corrected(b_v0 + db_v, b_g0) - again.dp()).norm() <= 1e-14);
  }
}

TEST_CASE("57.8 leg preintegration: the gyro-bias Jacobian equals central differences",
          "[leg_preintegration]") {
  const std::vector<Sample> s = motion();
  const Vector3d b_g0(0.01, -0.02, 0.005), b_v0(0.02, -0.01, 0.03);
  const LegPreintegrator lpi = integrate(s, b_g0, b_v0);
  const double e = 1e-6;
  Matrix3d J_num;
  for (int i = 0; i < 3; ++i) {
    const Vector3d d = e * Vector3d::Unit(i);
    J_num.col(i) =
        (integrate(s, b_g0 + d, b_v0).dp() - integrate(s, b_g0 - d, b_v0).dp()) / (2 * e);
  }
  INFO("analytic\n" << lpi.J_p_bg() << "\nnumeric\n" << J_num);
  CHECK((lpi.J_p_bg() - J_num).cwiseAbs().maxCoeff() <= 1e-6 * J_num.cwiseAbs().maxCoeff());
  // The first-order correction is second-order accurate: a 0.01 rad/s change moves dp by
  // about 1e-3 m, the corrected increment misses re-integration by orders of magnitude less.
  const Vector3d db_g(0.01, -0.01, 0.005);
  const Vector3d again = integrate(s, b_g0 + db_g, b_v0).dp();
  const double change = (again - lpi.dp()).norm();
  const double miss = (lpi.corrected(b_v0, b_g0 + db_g) - again).norm();
  WARN("gyro bias 0.015 rad/s: dp changes by " << change << " m, the correction misses by " << miss
                                               << " m");
  CHECK(change > 1e-4);
  CHECK(miss <= 1e-2 * change);
}

TEST_CASE("57.8 leg preintegration: the covariance of dp matches Monte Carlo",
          "[leg_preintegration]") {
  // A noisy gyro (10x the Go2's density) so that the rotation's share is not negligible.
  ImuNoise noise = ImuNoise::go2();
  noise.gyro_noise_density = 0.04;
  const std::vector<Sample> s = motion();
  const Vector3d b_g0 = Vector3d::Zero(), b_v0 = Vector3d::Zero();
  const LegPreintegrator lpi = integrate(s, b_g0, b_v0, noise);
  const Matrix3d Sigma = lpi.covariance();
  ImuNoise no_gyro = noise;
  no_gyro.gyro_noise_density = 0.0;
  const Matrix3d Sigma_legs_only = integrate(s, b_g0, b_v0, no_gyro).covariance();

  const int runs = 2000;
  std::mt19937_64 gen(20261124);
  std::normal_distribution<double> n01(0.0, 1.0);
  const auto draw = [&]() { return Vector3d(n01(gen), n01(gen), n01(gen)); };
  const Matrix3d L_v = kSigmaV.llt().matrixL();
  const double sigma_g = noise.gyroSampleSigma(kDt);
  const Matrix3d Sigma_inv = Sigma.inverse(), Sigma_legs_only_inv = Sigma_legs_only.inverse();
  Matrix3d scatter = Matrix3d::Zero();
  double nees = 0.0, nees_legs_only = 0.0;
  for (int r = 0; r < runs; ++r) {
    LegPreintegrator noisy(b_g0, b_v0, noise);
    for (const Sample& x : s) {
      noisy.integrate(x.w_m + sigma_g * draw(), x.v + L_v * draw(), kSigmaV, kDt);
    }
    const Vector3d err = noisy.dp() - lpi.dp();
    scatter += err * err.transpose();
    nees += err.dot(Sigma_inv * err);
    nees_legs_only += err.dot(Sigma_legs_only_inv * err);
  }
  scatter /= runs;
  nees /= runs;
  nees_legs_only /= runs;
  const double rel = (scatter - Sigma).norm() / Sigma.norm();
  WARN("Monte Carlo (" << runs << " runs): |S_mc - Sigma|_F / |Sigma|_F = " << rel << ", mean NEES "
                       << nees << " (3 expected), without the rotation's share " << nees_legs_only);
  CHECK(rel <= 0.1);
  // Mean NEES of 2000 runs: 3 with a standard deviation of sqrt(6 / 2000) = 0.055.
  CHECK(std::abs(nees - 3.0) <= 0.25);
  // Leaving the rotation's noise out would be visibly overconfident.
  CHECK(nees_legs_only > 3.5);
}

TEST_CASE("57.8 leg preintegration refuses bad input and stays unchanged", "[leg_preintegration]") {
  LegPreintegrator lpi;
  const std::vector<Sample> s = motion();
  for (int k = 0; k < 10; ++k) lpi.integrate(s[k].w_m, s[k].v, kSigmaV, kDt);
  const LegPreintegrator before = lpi;
  const Vector3d w = s[10].w_m, v = s[10].v;
  CHECK_THROWS_AS(lpi.integrate(w, v, kSigmaV, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(lpi.integrate(w, v, kSigmaV, NAN), std::invalid_argument);
  CHECK_THROWS_AS(lpi.integrate(Vector3d(NAN, 0, 0), v, kSigmaV, kDt), std::invalid_argument);
  CHECK_THROWS_AS(lpi.integrate(w, Vector3d(0, INFINITY, 0), kSigmaV, kDt), std::invalid_argument);
  Matrix3d bad = kSigmaV;
  bad(0, 1) = 1e-3;  // not symmetric
  CHECK_THROWS_AS(lpi.integrate(w, v, bad, kDt), std::invalid_argument);
  bad = kSigmaV;
  bad(2, 2) = -1e-3;
  CHECK_THROWS_AS(lpi.integrate(w, v, bad, kDt), std::invalid_argument);
  bad(2, 2) = NAN;
  CHECK_THROWS_AS(lpi.integrate(w, v, bad, kDt), std::invalid_argument);
  CHECK(lpi.dt_ij() == before.dt_ij());
  CHECK(lpi.dp() == before.dp());
  CHECK(lpi.covariance() == before.covariance());
  CHECK(lpi.J_p_bg() == before.J_p_bg());
  CHECK_THROWS_AS(LegPreintegrator(Vector3d(NAN, 0, 0)), std::invalid_argument);
  CHECK_THROWS_AS(LegPreintegrator(Vector3d::Zero(), Vector3d(0, 0, INFINITY)),
                  std::invalid_argument);
}

TEST_CASE("57.8 leg preintegration does not allocate per sample", "[leg_preintegration]") {
  const std::vector<Sample> s = motion();
  LegPreintegrator lpi;
  const long before = legkit::test::allocationCount();
  for (const Sample& x : s) lpi.integrate(x.w_m, x.v, kSigmaV, kDt);
  CHECK(legkit::test::allocationCount() == before);
  CHECK(lpi.dp().norm() > 0.1);
}
