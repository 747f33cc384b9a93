// Exercise 57.8.2: leg-odometry preintegration with a velocity bias: its increments on hand-worked
// cases, the bias correction through the Jacobian, and a 2 % leg-length error absorbed by the bias
// (and why the bias must keep being re-estimated).
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "ex57_8_2.hpp"
#include "exercises/exercise_check.hpp"

using ex57_8_2::LegDelta;
using ex57_8_2::LegSample;

namespace {

// A walk at 1 kHz: constant body-frame velocity v_B and yaw rate, for `duration` seconds, from
// the pose (R, p), moved to the end. The legs measure (1 + scale_error) v_B: a leg-length error
// scales the kinematic velocity of every stance foot (its lever arm and its Jacobian alike).
std::vector<LegSample> walk(const Eigen::Vector3d& v_B, double yaw_rate, double duration,
                            double scale_error, lie::SO3d& R, Eigen::Vector3d& p) {
  constexpr double kDt = 0.001;
  const int n = static_cast<int>(std::lround(duration / kDt));
  std::vector<LegSample> samples(n);
  for (LegSample& s : samples) {
    s.omega = Eigen::Vector3d(0.0, 0.0, yaw_rate);
    s.v = (1.0 + scale_error) * v_B;
    s.dt = kDt;
    p += R.matrix() * v_B * kDt;  // the truth, held over the sample as the preintegration does
    R = R * lie::SO3d::Exp(s.omega * kDt);
  }
  return samples;
}

}  // namespace

TEST_CASE("57.8.2 the increments of a straight walk and of a turn, worked by hand", "[ex57.8.2]") {
  // Straight: 1 s at (0.5, 0.1, 0) m/s with the bias (0.01, 0, 0.02) m/s.
  const std::vector<LegSample> straight(
      100, LegSample{Eigen::Vector3d::Zero(), Eigen::Vector3d(0.5, 0.1, 0.0), 0.01});
  const LegDelta s = ex57_8_2::preintegrate(straight, Eigen::Vector3d(0.01, 0.0, 0.02));
  REQUIRE_NEAR(s.dp, Eigen::Vector3d(0.49, 0.1, -0.02), 1e-12);
  REQUIRE_NEAR(s.dp_db_v, (-1.0 * Eigen::Matrix3d::Identity()).eval(), 1e-12);
  REQUIRE_NEAR(s.dR.matrix(), Eigen::Matrix3d::Identity(), 1e-15);

  // A turn: N samples at yaw rate w and forward speed u: sample k is rotated by k theta,
  // theta = w dt, and sum_k (cos k theta, sin k theta) has a closed form.
  const int n = 200;
  const double dt = 0.005, w = 0.8, u = 0.6, theta = w * dt;
  const std::vector<LegSample> turn(
      n, LegSample{Eigen::Vector3d(0.0, 0.0, w), Eigen::Vector3d(u, 0.0, 0.0), dt});
  const LegDelta d = ex57_8_2::preintegrate(turn, Eigen::Vector3d::Zero());
  const double c = std::sin(n * theta / 2) * std::cos((n - 1) * theta / 2) / std::sin(theta / 2);
  const double sn = std::sin(n * theta / 2) * std::sin((n - 1) * theta / 2) / std::sin(theta / 2);
  REQUIRE_NEAR(d.dp, Eigen::Vector3d(u * dt * c, u * dt * sn, 0.0), 1e-12);
  Eigen::Matrix3d J;
  J << c, -sn, 0.0, sn, c, 0.0, 0.0, 0.0, n;
  REQUIRE_NEAR(d.dp_db_v, (-dt * J).eval(), 1e-12);
  REQUIRE_NEAR(d.dR.matrix(), lie::SO3d::Exp(Eigen::Vector3d(0.0, 0.0, n * theta)).matrix(), 1e-12);
}

TEST_CASE("57.8.2 another velocity bias through the Jacobian equals integrating again",
          "[ex57.8.2]") {
  // Unlike the IMU's increments (dR depends on b_g through Exp), dp_ij is linear in b_v: the
  // correction is exact, for any bias, not only near the linearisation point.
  std::mt19937 gen(5782);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<LegSample> samples(300);
  for (LegSample& s : samples)
    s = LegSample{Eigen::Vector3d(u(gen), u(gen), u(gen)), Eigen::Vector3d(u(gen), u(gen), u(gen)),
                  0.001 + 0.002 * std::abs(u(gen))};
  const Eigen::Vector3d b1(0.05, -0.02, 0.01), b2(-0.3, 0.4, 0.2);
  const LegDelta d1 = ex57_8_2::preintegrate(samples, b1);
  REQUIRE_NEAR(ex57_8_2::correctedDelta(d1, b2), ex57_8_2::preintegrate(samples, b2).dp, 1e-12);
}

TEST_CASE("57.8.2 a 2 % leg-length error is a velocity bias: two poses recover it", "[ex57.8.2]") {
  // Walking a circle (0.5 m/s forward, 0.05 m/s sideways, 0.3 rad/s) with legs 2 % too long.
  // Keyframe 0 -> 1 s: two exteroceptive poses give b_v. Keyframe 1 -> 11 s: the leg odometry's
  // displacement with and without that bias, against the truth.
  const Eigen::Vector3d v_B(0.5, 0.05, 0.0);
  lie::SO3d R = lie::SO3d::Exp(Eigen::Vector3d(0.0, 0.0, 0.4));
  Eigen::Vector3d p(1.0, -2.0, 0.3);
  const lie::SO3d R_0 = R;
  const Eigen::Vector3d p_0 = p;
  const std::vector<LegSample> first = walk(v_B, 0.3, 1.0, 0.02, R, p);
  const Eigen::Vector3d b_v = ex57_8_2::velocityBiasFromPoses(
      ex57_8_2::preintegrate(first, Eigen::Vector3d::Zero()), R_0, p_0, p);
  REQUIRE_NEAR(b_v, (0.02 * v_B).eval(), 1e-12);

  const lie::SO3d R_1 = R;
  const Eigen::Vector3d p_1 = p;
  const std::vector<LegSample> rest = walk(v_B, 0.3, 10.0, 0.02, R, p);
  const Eigen::Vector3d truth = p - p_1;
  const auto error = [&](const Eigen::Vector3d& bias) {
    return (R_1.matrix() * ex57_8_2::preintegrate(rest, bias).dp - truth).norm();
  };
  const double without = error(Eigen::Vector3d::Zero()), with = error(b_v);
  INFO("over 10 s (" << truth.norm() << " m from keyframe 1): without b_v " << without
                     << " m, with b_v " << with << " m");
  REQUIRE_NEAR(without, 0.02 * truth.norm(), 1e-9);  // 2 % of the displacement
  REQUIRE_NEAR(with, 0.0, 1e-9);
}

TEST_CASE("57.8.2 the leg-length bias scales with the speed: it must keep being estimated",
          "[ex57.8.2]") {
  // Straight at 0.5 m/s for 1 s (b_v estimated there), then 10 s at 0.25 m/s: the old b_v is
  // now 0.005 m/s too large, as wrong as no bias at all (0.05 m both); b_v estimated again over
  // the first second at the new speed removes the error.
  const Eigen::Vector3d fast(0.5, 0.0, 0.0), slow(0.25, 0.0, 0.0);
  lie::SO3d R;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  const std::vector<LegSample> first = walk(fast, 0.0, 1.0, 0.02, R, p);
  const Eigen::Vector3d b_fast =
      ex57_8_2::velocityBiasFromPoses(ex57_8_2::preintegrate(first, Eigen::Vector3d::Zero()),
                                      lie::SO3d(), Eigen::Vector3d::Zero(), p);
  const Eigen::Vector3d p_1 = p;
  const std::vector<LegSample> second = walk(slow, 0.0, 1.0, 0.02, R, p);
  const Eigen::Vector3d b_slow = ex57_8_2::velocityBiasFromPoses(
      ex57_8_2::preintegrate(second, Eigen::Vector3d::Zero()), R, p_1, p);
  const Eigen::Vector3d p_2 = p;
  const std::vector<LegSample> rest = walk(slow, 0.0, 10.0, 0.02, R, p);
  const auto error = [&](const Eigen::Vector3d& bias) {
    return (ex57_8_2::preintegrate(rest, bias).dp - (p - p_2)).norm();
  };
  INFO("10 s at 0.25 m/s: no b_v " << error(Eigen::Vector3d::Zero()) << " m, b_v from 0.5 m/s "
                                   << error(b_fast) << " m, b_v re-estimated " << error(b_slow)
                                   << " m");
  REQUIRE_NEAR(error(b_fast), 0.05, 1e-9);
  REQUIRE_NEAR(error(Eigen::Vector3d::Zero()), 0.05, 1e-9);
  REQUIRE_NEAR(error(b_slow), 0.0, 1e-9);
}
