// Exercise 57.4.3: four of the kit linear KF's design choices, re-derived by the student and
// checked against the kit (estimation/linear_kf/linear_kf.hpp, estimation/leg_odometry).
#include <catch2/catch.hpp>
#include <lie/so3.hpp>
#include <random>

#include "estimation/leg_odometry/velocity_fusion.hpp"
#include "estimation/linear_kf/linear_kf.hpp"
#include "ex57_4_3.hpp"
#include "exercises/exercise_check.hpp"

namespace lkf = legkit::linear_kf;

namespace {

lkf::Matrix18 randomCovariance(std::mt19937& gen) {
  std::normal_distribution<double> n;
  lkf::Matrix18 A;
  for (int r = 0; r < 18; ++r)
    for (int c = 0; c < 18; ++c) A(r, c) = n(gen);
  const lkf::Matrix18 AAt = A * A.transpose() / 18.0;
  return 0.5 * (AAt + AAt.transpose()) + 0.1 * lkf::Matrix18::Identity();
}

}  // namespace

TEST_CASE("57.4.3 the accelerometer's Q block enters through B", "[ex57.4.3][hint 4]") {
  for (double dt : {0.001, 0.002, 0.01}) {
    const Eigen::Matrix2d mine = ex57_4_3::navigationNoisePerAxis(dt, 0.04);
    const lkf::Matrix6 kit =
        lkf::navigationNoise(dt, Eigen::Matrix3d::Identity() * (0.04 * 0.04 / dt));
    for (int a = 0; a < 3; ++a) {
      REQUIRE_REL(mine(0, 0), kit(a, a), 1e-12);
      REQUIRE_REL(mine(0, 1), kit(a, 3 + a), 1e-12);
      REQUIRE_REL(mine(1, 0), kit(3 + a, a), 1e-12);
      REQUIRE_REL(mine(1, 1), kit(3 + a, 3 + a), 1e-12);
    }
    // Not the integrated continuous noise's dt^3/3 on p: the sample is held over the step.
    REQUIRE_REL(mine(0, 0), 0.04 * 0.04 * dt * dt * dt / 4.0, 1e-12);
  }
}

TEST_CASE("57.4.3 F P F^T by blocks", "[ex57.4.3][hint 1]") {
  std::mt19937 gen(3);
  const lkf::Matrix18 P = randomCovariance(gen);
  const double dt = 0.002;
  const lkf::ProcessModel m = lkf::processModel(dt, {true, true, true, true}, lkf::ProcessNoise{});
  const lkf::Matrix18 mine = ex57_4_3::predictCovariance(P, dt);
  REQUIRE_NEAR(mine, m.F * P * m.F.transpose(), 1e-14);
  REQUIRE_NEAR(mine, mine.transpose(), 0.0);  // exactly symmetric
}

TEST_CASE("57.4.3 the Joseph update, expanded, for any gain", "[ex57.4.3][hint 2]") {
  std::mt19937 gen(4);
  std::normal_distribution<double> n;
  const lkf::Matrix18 P = randomCovariance(gen);
  const Eigen::Matrix3d Rn = Eigen::Vector3d(1e-2, 2e-2, 3e-2).asDiagonal();
  for (int foot = 0; foot < 4; ++foot) {
    lkf::Matrix18x3 K;
    for (int r = 0; r < 18; ++r)
      for (int c = 0; c < 3; ++c) K(r, c) = 0.1 * n(gen);
    const lkf::Matrix3x18 H = lkf::footMeasurementMatrix(foot);
    const lkf::Matrix18 A = lkf::Matrix18::Identity() - K * H;
    const lkf::Matrix18 dense = A * P * A.transpose() + K * Rn * K.transpose();
    const lkf::Matrix18 mine = ex57_4_3::josephUpdate(P, K, foot, Rn);
    INFO("foot " << foot);
    REQUIRE_NEAR(mine, dense, 1e-12);
    REQUIRE_NEAR(mine, mine.transpose(), 0.0);  // exactly symmetric
    lkf::Matrix18 kit = P;
    const lkf::Matrix18x3 N = P * H.transpose();
    lkf::josephUpdate(kit, K, N, H * N + Rn);
    REQUIRE_NEAR(mine, kit, 1e-12);
  }
}

TEST_CASE("57.4.3 the mean stance velocity is the centroid foot's", "[ex57.4.3][hint 3]") {
  std::mt19937 gen(5);
  std::normal_distribution<double> n;
  const auto vec = [&](double s) { return Eigen::Vector3d(s * n(gen), s * n(gen), s * n(gen)); };
  for (int k = 1; k <= 4; ++k) {
    const Eigen::Matrix3d R = lie::SO3d::Exp(vec(1.0)).matrix();
    const Eigen::Vector3d w = vec(0.5);
    std::vector<legkit::ContactMeasurement> stance(k);
    for (int i = 0; i < k; ++i) {
      stance[i].foot = i;
      stance[i].p_body =
          Eigen::Vector3d(i < 2 ? 0.19 : -0.19, i % 2 ? -0.14 : 0.14, -0.3) + vec(0.02);
      stance[i].cov = Eigen::Matrix3d::Identity() * 1e-6;
      stance[i].v_body = vec(0.5);
    }
    const Eigen::Vector3d mine = ex57_4_3::centroidVelocity(R, w, stance);
    const Eigen::Vector3d mean = legkit::leg_odometry::meanVelocity(
        R, w, legkit::leg_odometry::ContactSpan{stance.data(), stance.size()});
    REQUIRE_NEAR(mine, mean, 1e-12);
  }
}
