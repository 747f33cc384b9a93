// Gyro integration on SO(3) (section 57.2) and the discretisation error of the Rodrigues step
// when the rate changes inside a step (exercise 57.2.3).
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "estimation/imu/gyro_integration.hpp"

using legkit::imu::gyroStep;
using legkit::imu::gyroStepError;
using legkit::imu::integrateRate;
using legkit::imu::RateSample;

TEST_CASE("57.2 the Rodrigues step is exact for a constant rate", "[gyro]") {
  const Eigen::Vector3d w(0.7, -1.2, 2.0), b_g(0.01, 0.02, -0.03);
  lie::SO3d R;
  for (int k = 0; k < 1000; ++k) R = gyroStep(R, w + b_g, b_g, 1e-3);
  CHECK(R.isApprox(lie::SO3d::Exp(w * 1.0), 1e-12));
  CHECK((R.matrix().transpose() * R.matrix() - Eigen::Matrix3d::Identity()).norm() < 1e-14);
}

TEST_CASE("57.2 a pure gyro bias rotates the estimate by b_g t", "[gyro]") {
  const Eigen::Vector3d b_g(0.01, 0.005, -0.008);
  lie::SO3d R;  // true rate zero: the reading is the bias, the integrator assumes none
  for (int k = 0; k < 100; ++k) R = gyroStep(R, b_g, Eigen::Vector3d::Zero(), 1e-3);
  CHECK((R.Log() - b_g * 0.1).norm() < 1e-15);  // constant axis: exactly Exp(b_g * 0.1 s)
}

TEST_CASE("57.2 holding the start rate of a ramp costs |dw/dt| dt^2 / 2 per step", "[gyro]") {
  // Fixed axis, rate ramping from w0 by alpha: the angle is the integral of the rate, so the
  // start sample misses alpha dt^2 / 2 and the midpoint sample is exact.
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, 2.0, -0.5).normalized();
  const double w0 = 2.0, alpha = 5000.0;  // 5 rad/s gained in 1 ms: a landing impact
  const auto ramp = [&](double t) -> Eigen::Vector3d { return (w0 + alpha * t) * axis; };
  for (double dt : {1e-3, 2.5e-3, 5e-3}) {
    CHECK(gyroStepError(ramp, 0.0, dt, RateSample::kStart) ==
          Approx(0.5 * alpha * dt * dt).epsilon(1e-6));
    CHECK(gyroStepError(ramp, 0.0, dt, RateSample::kMidpoint) < 1e-12);
  }
}

TEST_CASE("57.2 a turning rate axis leaves a coning error dt^3 |w0 x w1| / 12", "[gyro]") {
  // w(t) = w0 + w1 t with w0 not parallel to w1: the step's rotation is not Exp of the mean
  // rate; the leading term of the difference (Magnus expansion) is dt^3 / 12 |w0 x w1|.
  const Eigen::Vector3d w0(3.0, 0.0, 0.0), w1(0.0, 4000.0, 0.0);
  const auto w = [&](double t) -> Eigen::Vector3d { return w0 + w1 * t; };
  const double dt = 1e-3;
  const double coning = dt * dt * dt / 12.0 * w0.cross(w1).norm();
  CHECK(gyroStepError(w, 0.0, dt, RateSample::kMidpoint) == Approx(coning).epsilon(0.05));
}

TEST_CASE("57.2 the start-sample error shrinks quadratically with the step", "[gyro]") {
  // A fast sinusoid (20 Hz, 4 rad/s) around a tilted axis plus a slow turn.
  const auto w = [](double t) -> Eigen::Vector3d {
    return Eigen::Vector3d(0.5, 4.0 * std::sin(2.0 * M_PI * 20.0 * t), 0.3);
  };
  double previous = gyroStepError(w, 0.004, 4e-3, RateSample::kStart);
  for (double dt : {2e-3, 1e-3, 5e-4}) {
    const double e = gyroStepError(w, 0.004, dt, RateSample::kStart);
    CHECK(previous / e == Approx(4.0).epsilon(0.15));
    previous = e;
  }
}

TEST_CASE("57.2 gyro integration rejects bad input", "[gyro]") {
  const lie::SO3d R;
  const Eigen::Vector3d z = Eigen::Vector3d::Zero();
  const Eigen::Vector3d nan(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0);
  CHECK_THROWS_AS(gyroStep(R, z, z, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(gyroStep(R, z, z, -1e-3), std::invalid_argument);
  CHECK_THROWS_AS(gyroStep(R, nan, z, 1e-3), std::invalid_argument);
  CHECK_THROWS_AS(gyroStep(R, z, nan, 1e-3), std::invalid_argument);
  const auto bad = [](double) -> Eigen::Vector3d {
    return Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  };
  CHECK_THROWS_AS(integrateRate(bad, 0.0, 1e-3, 10, RateSample::kStart), std::invalid_argument);
  CHECK_THROWS_AS(integrateRate(bad, 0.0, 1e-3, 0, RateSample::kStart), std::invalid_argument);
}
