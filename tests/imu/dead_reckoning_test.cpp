// Dead reckoning (section 57.1): exact strapdown steps, and the drift table of the chapter
// measured on readings synthesised for a robot standing still.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "estimation/imu/dead_reckoning.hpp"
#include "estimation/imu/drift_study.hpp"

using legkit::imu::deadReckoningStep;
using legkit::imu::driftAt;
using legkit::imu::NavState;
using legkit::imu::runStationaryDrift;
using legkit::imu::StationaryDriftStudy;
using legkit::model::ImuBias;
using legkit::model::ImuReading;

TEST_CASE("57.1 dead reckoning of a perfect stationary IMU stays put", "[dead_reckoning]") {
  const lie::SO3d R = lie::SO3d::Exp(Eigen::Vector3d(0.2, -0.4, 1.0));
  const ImuReading m = legkit::model::idealReading(R.matrix(), Eigen::Vector3d::Zero(),
                                                   Eigen::Vector3d::Zero(), ImuBias{});
  NavState x{R, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (int k = 0; k < 10000; ++k) x = deadReckoningStep(x, m, ImuBias{}, 1e-3);
  CHECK(x.p.norm() < 1e-9);
  CHECK(x.v.norm() < 1e-10);
  CHECK(x.R.isApprox(R, 1e-12));
}

TEST_CASE("57.1 one dead-reckoning step is exact for a constant rate and specific force",
          "[dead_reckoning]") {
  // Constant body rate w and body specific force f: a big step must equal many small ones.
  const Eigen::Vector3d w(0.3, -0.2, 0.8), f(0.5, 0.1, 9.9);
  const ImuReading m{w, f};
  const NavState x0{lie::SO3d::Exp(Eigen::Vector3d(0.1, 0.2, 0.3)), Eigen::Vector3d(1, 0, 0),
                    Eigen::Vector3d(0, 0, 0.3)};
  const NavState big = deadReckoningStep(x0, m, ImuBias{}, 0.5);
  NavState small = x0;
  for (int k = 0; k < 500; ++k) small = deadReckoningStep(small, m, ImuBias{}, 1e-3);
  CHECK(big.R.isApprox(small.R, 1e-12));
  CHECK((big.v - small.v).norm() < 1e-12);
  CHECK((big.p - small.p).norm() < 1e-12);
}

TEST_CASE("57.1 drift table: accelerometer bias 0.01 m/s^2 (measured, not the formula)",
          "[dead_reckoning][drift]") {
  StationaryDriftStudy study;
  study.bias.b_a = Eigen::Vector3d(0.01, 0.0, 0.0);
  study.report_every = 1.0;
  const auto drift = runStationaryDrift(study);
  // chapter 57.1: 0.01 m/s, 0.005 m at 1 s; 0.1 m/s, 0.5 m at 10 s; 0.6 m/s, 18 m at 60 s
  CHECK(driftAt(drift, 1.0).position_error == Approx(0.005).epsilon(1e-6));
  CHECK(driftAt(drift, 10.0).position_error == Approx(0.5).epsilon(1e-6));
  CHECK(driftAt(drift, 60.0).position_error == Approx(18.0).epsilon(1e-6));
  CHECK(driftAt(drift, 1.0).velocity_error == Approx(0.01).epsilon(1e-6));
  CHECK(driftAt(drift, 10.0).velocity_error == Approx(0.1).epsilon(1e-6));
  CHECK(driftAt(drift, 60.0).velocity_error == Approx(0.6).epsilon(1e-6));
  CHECK(driftAt(drift, 60.0).attitude_error_deg < 1e-9);
}

TEST_CASE("57.1 drift table: gyro bias 0.01 rad/s tilts the attitude by 34 deg in 60 s",
          "[dead_reckoning][drift]") {
  StationaryDriftStudy study;
  study.bias.b_g = Eigen::Vector3d(0.01, 0.0, 0.0);  // about the x axis: a roll drift
  study.report_every = 1.0;
  const auto drift = runStationaryDrift(study);
  CHECK(driftAt(drift, 60.0).attitude_error_deg == Approx(34.38).margin(0.01));
  // The tilted gravity is then integrated twice: for small angles |p| ~ g b_g t^3 / 6.
  CHECK(driftAt(drift, 1.0).position_error == Approx(9.81 * 0.01 / 6.0).epsilon(0.01));
  CHECK(driftAt(drift, 60.0).position_error > 1000.0);
}

TEST_CASE("57.1 a yaw gyro bias leaves a standing robot's position alone",
          "[dead_reckoning][drift]") {
  // A rotation about gravity does not change the gravity direction in the body frame.
  StationaryDriftStudy study;
  study.bias.b_g = Eigen::Vector3d(0.0, 0.0, 0.01);
  study.duration = 10.0;
  const auto drift = runStationaryDrift(study);
  CHECK(driftAt(drift, 10.0).attitude_error_deg == Approx(5.7296).margin(1e-3));
  CHECK(driftAt(drift, 10.0).position_error < 1e-8);
}

TEST_CASE("57.1 with Go2 accelerometer noise the drift spread matches the velocity random walk",
          "[dead_reckoning][drift]") {
  // White accelerometer noise integrates twice: each position axis gets a zero-mean error of
  // variance sigma_a^2 t^3 / 3 (0.065 m std at 2 s), on top of the bias drift b_a t^2 / 2
  // (0.02 m). So E|p|^2 = 3 sigma_a^2 t^3 / 3 + (b_a t^2 / 2)^2 (the bias walk adds < 0.01 %).
  StationaryDriftStudy study;
  study.bias.b_a = Eigen::Vector3d(0.01, 0.0, 0.0);
  study.noise = legkit::model::ImuNoise::go2();
  study.noise.gyro_noise_density =
      0.0;  // keep attitude exact: this test is about the accelerometer
  study.noise.gyro_bias_random_walk = 0.0;
  const double t = 2.0;
  study.duration = t;
  study.report_every = t;
  const int runs = 200;
  double sum_sq = 0.0;
  for (int r = 0; r < runs; ++r) {
    study.seed = 100 + r;
    const double e = driftAt(runStationaryDrift(study), t).position_error;
    sum_sq += e * e;
  }
  const double sigma_a = study.noise.accel_noise_density;
  const double expected = sigma_a * sigma_a * t * t * t + std::pow(0.01 * t * t / 2.0, 2);
  // 200 samples of a scaled chi-square(3): relative std of the mean about 6 %.
  CHECK(sum_sq / runs == Approx(expected).epsilon(0.2));
}

TEST_CASE("57.1 dead reckoning rejects bad input", "[dead_reckoning]") {
  const NavState x;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(deadReckoningStep(x, ImuReading{}, ImuBias{}, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(deadReckoningStep(x, ImuReading{}, ImuBias{}, -1.0), std::invalid_argument);
  ImuReading bad;
  bad.a_m(2) = nan;
  CHECK_THROWS_AS(deadReckoningStep(x, bad, ImuBias{}, 1e-3), std::invalid_argument);
  bad = ImuReading{};
  bad.w_m(0) = nan;
  CHECK_THROWS_AS(deadReckoningStep(x, bad, ImuBias{}, 1e-3), std::invalid_argument);
  StationaryDriftStudy study;
  study.dt = 0.0;
  CHECK_THROWS_AS(runStationaryDrift(study), std::invalid_argument);
}
