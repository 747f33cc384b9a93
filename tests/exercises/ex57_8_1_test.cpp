// Exercise 57.8.1: a SLAM pose as an observation of T_MO: the measurement from the odometry pose at
// the SLAM stamp, its covariance (hand-worked cases and a Monte Carlo of the exact transform), the
// odometry history's interpolation, and the error of taking the odometry at the arrival instead.
#include <Eigen/Cholesky>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <stdexcept>

#include "ex57_8_1.hpp"
#include "exercises/exercise_check.hpp"

using ex57_8_1::Matrix6d;
using ex57_8_1::OdomHistory;
using ex57_8_1::Pose;
using ex57_8_1::PoseMeasurement;

namespace {

lie::SO3d yaw(double angle) {
  return lie::SO3d::Exp(Eigen::Vector3d(0.0, 0.0, angle));
}

// The SLAM's view of the base at the same instant as T_OB, when the map is T_MO from the odom
// frame.
PoseMeasurement slamPose(const lie::SO3d& R_MO, const Eigen::Vector3d& p_MO, const Pose& T_OB) {
  PoseMeasurement z;
  z.R_MB = R_MO * T_OB.R;
  z.p_MB = R_MO.matrix() * T_OB.p + p_MO;
  return z;
}

// A random SPD 6x6 covariance with standard deviations about sigma_theta [rad] and sigma_p [m].
Matrix6d randomCovariance(std::mt19937& gen, double sigma_theta, double sigma_p) {
  std::normal_distribution<double> n(0.0, 1.0);
  Matrix6d A;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) A(i, j) = n(gen);
  Eigen::Matrix<double, 6, 1> scale;
  scale << sigma_theta, sigma_theta, sigma_theta, sigma_p, sigma_p, sigma_p;
  const Matrix6d C = A * A.transpose() / 6.0 + 0.1 * Matrix6d::Identity();
  return scale.asDiagonal() * C * scale.asDiagonal();
}

// A draw of (dtheta, dp) ~ N(0, cov).
Eigen::Matrix<double, 6, 1> draw(std::mt19937& gen, const Matrix6d& cov) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix<double, 6, 1> w;
  for (int i = 0; i < 6; ++i) w(i) = n(gen);
  return Eigen::LLT<Matrix6d>(cov).matrixL() * w;
}

}  // namespace

TEST_CASE("57.8.1 (a) T_MO from the SLAM pose and the odometry pose at its stamp", "[ex57.8.1]") {
  std::mt19937 gen(5781);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (int k = 0; k < 20; ++k) {
    const lie::SO3d R_MO = lie::SO3d::Random(gen);
    const Eigen::Vector3d p_MO(u(gen), u(gen), u(gen));
    Pose T_OB;
    T_OB.R = lie::SO3d::Random(gen);
    T_OB.p = Eigen::Vector3d(u(gen), u(gen), u(gen));
    const Pose T_MO = ex57_8_1::mapOdomMeasurement(slamPose(R_MO, p_MO, T_OB), T_OB);
    REQUIRE_NEAR(T_MO.R.matrix(), R_MO.matrix(), 1e-12);
    REQUIRE_NEAR(T_MO.p, p_MO, 1e-12);
  }
}

TEST_CASE("57.8.1 (b) the covariance of T_MO on three hand-worked cases", "[ex57.8.1]") {
  Pose T_OB;  // the base at the odom origin
  PoseMeasurement z = slamPose(yaw(0.7), Eigen::Vector3d(1.0, 2.0, 0.3), T_OB);
  Eigen::Matrix<double, 6, 1> sd;
  sd << 0.01, 0.02, 0.03, 0.04, 0.05, 0.06;
  z.cov = sd.cwiseAbs2().asDiagonal();
  // 1. Exact odometry, the base at the odom origin: T_MO is as uncertain as the SLAM pose.
  REQUIRE_NEAR(ex57_8_1::mapOdomMeasurement(z, T_OB).cov, z.cov, 1e-15);

  // 2. Exact SLAM, the odometry's yaw uncertain by sigma, the base 1 m along the odom x axis, map
  //    and odom aligned: an odometry yaw error turns T_MO the other way, which moves the base's
  //    image along +y by the same amount: var(dtheta_z) = var(dp_y) = -cov(dtheta_z, dp_y).
  const double sigma = 0.01;
  T_OB.p = Eigen::Vector3d(1.0, 0.0, 0.0);
  T_OB.cov.setZero();
  T_OB.cov(2, 2) = sigma * sigma;
  z = slamPose(lie::SO3d(), Eigen::Vector3d(3.0, -1.0, 0.0), T_OB);
  z.cov.setZero();
  Matrix6d expected = Matrix6d::Zero();
  expected(2, 2) = expected(4, 4) = sigma * sigma;
  expected(2, 4) = expected(4, 2) = -sigma * sigma;
  REQUIRE_NEAR(ex57_8_1::mapOdomMeasurement(z, T_OB).cov, expected, 1e-15);

  // 3. Exact SLAM, the odometry's position uncertain (x 2 cm, y 1 cm, z 3 cm), odom turned by
  //    90 deg in the map: x and y swap.
  T_OB.cov.setZero();
  T_OB.cov.bottomRightCorner<3, 3>() = Eigen::Vector3d(4e-4, 1e-4, 9e-4).asDiagonal();
  z = slamPose(yaw(M_PI / 2), Eigen::Vector3d(3.0, -1.0, 0.0), T_OB);
  z.cov.setZero();
  expected.setZero();
  expected.bottomRightCorner<3, 3>() = Eigen::Vector3d(1e-4, 4e-4, 9e-4).asDiagonal();
  REQUIRE_NEAR(ex57_8_1::mapOdomMeasurement(z, T_OB).cov, expected, 1e-15);
}

TEST_CASE("57.8.1 (b) the covariance of T_MO against a Monte Carlo of the exact transform",
          "[ex57.8.1]") {
  // A SLAM pose and an odometry pose, 6 m from the odom origin (the lever arm matters), with
  // errors of about 10 mrad and 5 cm; 20000 draws of both errors, pushed through T_MB (T_OB)^-1.
  std::mt19937 gen(57811);
  Pose T_OB;
  T_OB.R = lie::SO3d::Random(gen);
  T_OB.p = Eigen::Vector3d(4.0, -4.0, 0.5);
  T_OB.cov = randomCovariance(gen, 0.01, 0.05);
  PoseMeasurement z = slamPose(lie::SO3d::Random(gen), Eigen::Vector3d(2.0, 1.0, -0.5), T_OB);
  z.cov = randomCovariance(gen, 0.01, 0.05);
  const Pose T_MO = ex57_8_1::mapOdomMeasurement(z, T_OB);

  constexpr int kDraws = 20000;
  Matrix6d sample = Matrix6d::Zero();
  for (int k = 0; k < kDraws; ++k) {
    const Eigen::Matrix<double, 6, 1> e_s = draw(gen, z.cov), e_o = draw(gen, T_OB.cov);
    const lie::SO3d R_MB = lie::SO3d::Exp(e_s.head<3>()) * z.R_MB;
    const Eigen::Vector3d p_MB = z.p_MB + e_s.tail<3>();
    const lie::SO3d R_OB = lie::SO3d::Exp(e_o.head<3>()) * T_OB.R;
    const Eigen::Vector3d p_OB = T_OB.p + e_o.tail<3>();
    const lie::SO3d R_MO = R_MB * R_OB.inverse();
    Eigen::Matrix<double, 6, 1> e;  // T_MO's (dtheta, dp) from the estimate
    e << (R_MO * T_MO.R.inverse()).Log(), p_MB - R_MO.matrix() * p_OB - T_MO.p;
    sample += e * e.transpose() / kDraws;
  }
  // Each entry within 5 % of sqrt(C_ii C_jj): 5 standard errors of a 20000-draw estimate.
  const Eigen::Matrix<double, 6, 1> sd = T_MO.cov.diagonal().cwiseSqrt();
  const Matrix6d normalised = (sample - T_MO.cov).cwiseQuotient(sd * sd.transpose());
  INFO("Monte Carlo covariance\n" << sample << "\nyour covariance\n" << T_MO.cov);
  REQUIRE_NEAR(normalised.cwiseAbs().maxCoeff(), 0.0, 0.05);
}

TEST_CASE("57.8.1 (c) the odometry history interpolates and never extrapolates", "[ex57.8.1]") {
  // 700 poses at 1 kHz of a constant body rate and a constant velocity in a buffer of 500: the
  // poses of the last 0.5 s are held.
  const lie::SO3d R0 = lie::SO3d::Exp(Eigen::Vector3d(0.1, -0.2, 0.3));
  const Eigen::Vector3d omega(0.3, -0.5, 1.2), v(0.8, 0.2, -0.1), p0(1.0, 2.0, 0.3);
  const auto truth = [&](double t) {
    Pose T;
    T.R = R0 * lie::SO3d::Exp(omega * t);
    T.p = p0 + v * t;
    T.cov = (1.0 + t) * Matrix6d::Identity();
    return T;
  };
  OdomHistory history(500);
  for (int k = 0; k < 700; ++k) history.push(0.001 * k, truth(0.001 * k));

  for (const double t : {0.2, 0.2004, 0.35, 0.6543, 0.699}) {
    INFO("t = " << t);
    const Pose got = history.at(t), expected = truth(t);
    REQUIRE_NEAR(got.R.matrix(), expected.R.matrix(), 1e-12);
    REQUIRE_NEAR(got.p, expected.p, 1e-12);
    REQUIRE_NEAR(got.cov, expected.cov, 1e-12);  // linear in t
  }
  // Older than the buffer, in the future, not a time: refused.
  REQUIRE_THROWS_AS(history.at(0.1999), std::out_of_range);
  REQUIRE_THROWS_AS(history.at(0.6991), std::out_of_range);
  REQUIRE_THROWS_AS(history.at(NAN), std::out_of_range);
  REQUIRE_THROWS_AS(OdomHistory(4).at(0.0), std::out_of_range);
  // Out of time order, not a time, no room: refused.
  REQUIRE_THROWS_AS(history.push(0.699, truth(0.699)), std::invalid_argument);
  REQUIRE_THROWS_AS(history.push(NAN, truth(0.7)), std::invalid_argument);
  REQUIRE_THROWS_AS(OdomHistory(0).push(0.0, truth(0.0)), std::invalid_argument);
}

TEST_CASE("57.8.1 (d) the odometry at the SLAM stamp, not at its arrival", "[ex57.8.1]") {
  // The odometry at 1 kHz for 1 s, the base walking at 1 m/s; the map is odom turned by 30 deg and
  // shifted. A SLAM pose stamped 0.8 s reaches the estimator 80 ms later, at 0.88 s.
  const lie::SO3d R_MO = yaw(M_PI / 6);
  const Eigen::Vector3d p_MO(2.0, -1.0, 0.1);
  const double speed = 1.0, latency = 0.08, t_stamp = 0.8;
  for (const double yaw_rate : {0.0, 0.5}) {
    const auto odom = [&](double t) {
      Pose T;
      T.R = yaw(0.2 + yaw_rate * t);
      T.p = Eigen::Vector3d(speed * t, 0.0, 0.3);  // along the odom x axis
      return T;
    };
    OdomHistory history(500);
    for (int k = 0; k <= 1000; ++k) history.push(0.001 * k, odom(0.001 * k));
    PoseMeasurement z = slamPose(R_MO, p_MO, odom(t_stamp));
    z.t = t_stamp;
    z.t_arrival = t_stamp + latency;

    const Pose at_stamp = ex57_8_1::mapOdomMeasurement(z, history.at(z.t));
    const Pose at_arrival = ex57_8_1::mapOdomMeasurement(z, history.at(z.t_arrival));
    const double position_error = (at_arrival.p - p_MO).norm();
    const double angle_error = (at_arrival.R * R_MO.inverse()).Log().norm();
    INFO("yaw rate " << yaw_rate << " rad/s: the odometry at the arrival puts T_MO off by "
                     << position_error << " m and " << angle_error << " rad");
    REQUIRE_NEAR(at_stamp.p, p_MO, 1e-9);
    REQUIRE_NEAR(at_stamp.R.matrix(), R_MO.matrix(), 1e-9);
    // 80 ms of walking at 1 m/s: 8 cm; a turn at 0.5 rad/s adds 0.04 rad of heading.
    if (yaw_rate == 0.0) REQUIRE_NEAR(position_error, speed * latency, 1e-9);
    REQUIRE_NEAR(angle_error, yaw_rate * latency, 1e-9);
  }
}
