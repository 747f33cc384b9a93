// model/imu_model.hpp: the synthesised readings follow a_m = R^T (a - g) + b_a + n_a,
// w_m = w + b_g + n_g, with the discretised noise and bias random walk of ImuNoise.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>

#include "model/imu_model.hpp"

using legkit::model::ImuBias;
using legkit::model::ImuNoise;
using legkit::model::ImuReading;
using legkit::model::synthesiseReading;

TEST_CASE("57.2 a stationary IMU averages to -R^T g + b_a and b_g", "[imu_model]") {
  std::mt19937_64 gen(7);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  ImuNoise noise = ImuNoise::go2();
  noise.gyro_bias_random_walk = 0.0;  // keep the biases fixed: the mean is then known exactly
  noise.accel_bias_random_walk = 0.0;
  const ImuBias b0{Eigen::Vector3d(0.01, -0.02, 0.005), Eigen::Vector3d(0.05, 0.1, -0.08)};
  ImuBias b = b0;
  const double dt = 1e-3;
  const int n = 20000;
  Eigen::Vector3d sum_w = Eigen::Vector3d::Zero(), sum_a = Eigen::Vector3d::Zero();
  for (int k = 0; k < n; ++k) {
    const ImuReading m =
        synthesiseReading(noise, dt, R, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), b, gen);
    sum_w += m.w_m;
    sum_a += m.a_m;
  }
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  const Eigen::Vector3d expected_a = -R.transpose() * g + b0.b_a;
  // 5 standard errors of the mean of n samples of sigma / sqrt(dt).
  const double tol_a = 5.0 * noise.accelSampleSigma(dt) / std::sqrt(n);
  const double tol_w = 5.0 * noise.gyroSampleSigma(dt) / std::sqrt(n);
  CHECK((sum_a / n - expected_a).cwiseAbs().maxCoeff() < tol_a);
  CHECK((sum_w / n - b0.b_g).cwiseAbs().maxCoeff() < tol_w);
  CHECK(b.b_a == b0.b_a);
}

TEST_CASE("57.2 without noise the reading is exactly the measurement model", "[imu_model]") {
  std::mt19937_64 gen(1);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d a(1.0, -2.0, 3.0), w(0.4, 0.5, -0.6);
  ImuBias b{Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(-0.1, 0.0, 0.2)};
  const ImuReading m = synthesiseReading(ImuNoise::noiseless(), 1e-3, R, a, w, b, gen);
  CHECK((m.w_m - (w + b.b_g)).norm() < 1e-15);
  CHECK((m.a_m - (R.transpose() * (a - Eigen::Vector3d(0, 0, -9.81)) + b.b_a)).norm() < 1e-14);
}

TEST_CASE("57.2 the bias random walk spreads as sigma_b sqrt(t)", "[imu_model]") {
  const ImuNoise noise = ImuNoise::go2();
  const double dt = 1e-3;
  const int runs = 200, steps = 1000;  // 1 s each
  double sum_sq_g = 0.0, sum_sq_a = 0.0;
  std::mt19937_64 gen(3);
  for (int r = 0; r < runs; ++r) {
    ImuBias b;
    for (int k = 0; k < steps; ++k)
      synthesiseReading(noise, dt, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(),
                        Eigen::Vector3d::Zero(), b, gen);
    sum_sq_g += b.b_g.squaredNorm();
    sum_sq_a += b.b_a.squaredNorm();
  }
  const double T = steps * dt;
  // 3 * runs samples of a chi-square(1) scaled by sigma^2 T: relative std sqrt(2 / 600) ~ 6 %.
  CHECK(sum_sq_g / (3 * runs) / (noise.gyro_bias_random_walk * noise.gyro_bias_random_walk * T) ==
        Approx(1.0).margin(0.25));
  CHECK(sum_sq_a / (3 * runs) / (noise.accel_bias_random_walk * noise.accel_bias_random_walk * T) ==
        Approx(1.0).margin(0.25));
}

TEST_CASE("57.2 the sensor model rejects bad input", "[imu_model]") {
  std::mt19937_64 gen(1);
  ImuBias b;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d z = Eigen::Vector3d::Zero();
  const ImuNoise noise = ImuNoise::go2();
  CHECK_THROWS_AS(synthesiseReading(noise, 0.0, I, z, z, b, gen), std::invalid_argument);
  CHECK_THROWS_AS(synthesiseReading(noise, -1e-3, I, z, z, b, gen), std::invalid_argument);
  const Eigen::Vector3d nan(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0);
  CHECK_THROWS_AS(synthesiseReading(noise, 1e-3, I, nan, z, b, gen), std::invalid_argument);
  CHECK_THROWS_AS(synthesiseReading(noise, 1e-3, I, z, nan, b, gen), std::invalid_argument);
}
