// Kinematics of the Go2-class leg: geometry, Jacobian against finite differences, IK round
// trips, and input errors. (FK against MuJoCo lives in quadruped_mujoco_test.cpp.)
#include <rapidcheck/catch.h>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "model/quadruped.hpp"

using legkit::model::kNumLegs;
using legkit::model::QuadrupedGeometry;
using legkit::model::QuadrupedKinematics;

namespace {

constexpr int kSteps = 1 << 20;

// A joint configuration drawn uniformly within the leg's limits (2^20 steps per joint; the
// fixed nominal size keeps RapidCheck from crowding the first draws at the lower limits).
rc::Gen<Eigen::Vector3d> genJointsWithinLimits(const QuadrupedGeometry& g, int leg) {
  const auto step = rc::gen::resize(rc::kNominalSize, rc::gen::inRange(0, kSteps + 1));
  return rc::gen::map(rc::gen::tuple(step, step, step), [g,
                                                         leg](const std::tuple<int, int, int>& k) {
    const Eigen::Vector3d u(std::get<0>(k), std::get<1>(k), std::get<2>(k));
    return Eigen::Vector3d(g.q_min[leg] + (g.q_max[leg] - g.q_min[leg]).cwiseProduct(u / kSteps));
  });
}

// Height of the foot below the hip-flexion axis in the leg's own frame: the IK branch asks for
// z0 <= 0 (leg pointing down).
double legPlaneHeight(const QuadrupedGeometry& g, const Eigen::Vector3d& q) {
  return -g.thigh_length * std::cos(q.y()) - g.calf_length * std::cos(q.y() + q.z());
}

}  // namespace

TEST_CASE("go2 geometry: hips, offsets and link lengths as data", "[57.3][model]") {
  const QuadrupedGeometry g = QuadrupedGeometry::go2();
  CHECK(g.hip_offset[legkit::model::FL].isApprox(Eigen::Vector3d(0.1934, 0.0465, 0.0)));
  CHECK(g.hip_offset[legkit::model::FR].isApprox(Eigen::Vector3d(0.1934, -0.0465, 0.0)));
  CHECK(g.hip_offset[legkit::model::RL].isApprox(Eigen::Vector3d(-0.1934, 0.0465, 0.0)));
  CHECK(g.hip_offset[legkit::model::RR].isApprox(Eigen::Vector3d(-0.1934, -0.0465, 0.0)));
  CHECK(g.abduction_offset == 0.0955);
  CHECK(g.thigh_length == 0.213);
  CHECK(g.calf_length == 0.213);
  CHECK(g.foot_radius == 0.022);
  CHECK(legkit::model::lateralSign(legkit::model::FL) == 1.0);
  CHECK(legkit::model::lateralSign(legkit::model::RR) == -1.0);
  CHECK(std::string(legkit::model::legName(2)) == "RL");
}

TEST_CASE("FK at zero angles hangs the foot straight below the thigh", "[57.3][model]") {
  const QuadrupedKinematics kin;
  const QuadrupedGeometry& g = kin.geometry();
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const Eigen::Vector3d expected =
        g.hip_offset[leg] + Eigen::Vector3d(0.0, legkit::model::lateralSign(leg) * 0.0955, -0.426);
    CHECK((kin.footPosition(leg, Eigen::Vector3d::Zero()) - expected).norm() < 1e-15);
  }
  // Abducting a left leg by +90 deg swings its foot up to the left (rotation about +x).
  const Eigen::Vector3d p = kin.footPosition(legkit::model::FL, Eigen::Vector3d(M_PI / 2, 0, 0));
  CHECK((p - g.hip_offset[0] - Eigen::Vector3d(0.0, 0.426, 0.0955)).norm() < 1e-12);
}

TEST_CASE("foot Jacobian equals central finite differences of FK", "[57.3][model]") {
  const QuadrupedKinematics kin;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    rc::prop("leg " + std::to_string(leg), [&] {
      const Eigen::Vector3d q = *genJointsWithinLimits(kin.geometry(), leg);
      const Eigen::Matrix3d J = kin.footJacobian(leg, q);
      constexpr double h = 1e-6;
      Eigen::Matrix3d J_fd;
      for (int j = 0; j < 3; ++j) {
        const Eigen::Vector3d dq = h * Eigen::Vector3d::Unit(j);
        J_fd.col(j) = (kin.footPosition(leg, q + dq) - kin.footPosition(leg, q - dq)) / (2 * h);
      }
      // Central differences err by about h^2 |p'''| / 6 + eps |p| / h, i.e. well below 1e-9.
      RC_ASSERT((J - J_fd).cwiseAbs().maxCoeff() < 1e-9);
    });
  }
}

TEST_CASE("IK(FK(q)) = q over the workspace on the knee-backward branch", "[57.3][model]") {
  const QuadrupedKinematics kin;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    rc::prop("leg " + std::to_string(leg), [&] {
      const Eigen::Vector3d q = *genJointsWithinLimits(kin.geometry(), leg);
      RC_PRE(legPlaneHeight(kin.geometry(), q) < -1e-6);  // the branch IK solves on
      const Eigen::Vector3d p = kin.footPosition(leg, q);
      const Eigen::Vector3d q_ik = kin.inverseKinematics(leg, p);
      RC_ASSERT(q_ik.z() < 0.0);  // knee angle negative
      RC_ASSERT((q_ik - q).cwiseAbs().maxCoeff() < 1e-7);
      RC_ASSERT((kin.footPosition(leg, q_ik) - p).norm() < 1e-12);
    });
  }
}

TEST_CASE("IK of a standing foot returns the Go2 posture", "[57.3][model]") {
  const QuadrupedKinematics kin;
  const Eigen::Vector3d q_stand(0.0, 0.8, -1.5);
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const Eigen::Vector3d q = kin.inverseKinematics(leg, kin.footPosition(leg, q_stand));
    CHECK((q - q_stand).norm() < 1e-12);
  }
}

TEST_CASE("IK of an unreachable point names the leg and the point", "[57.3][model]") {
  const QuadrupedKinematics kin;
  using Catch::Matchers::Contains;
  // Far below the FR hip: beyond thigh + calf.
  CHECK_THROWS_AS(kin.inverseKinematics(legkit::model::FR, Eigen::Vector3d(0.19, -0.14, -0.6)),
                  std::domain_error);
  CHECK_THROWS_WITH(kin.inverseKinematics(legkit::model::FR, Eigen::Vector3d(0.19, -0.14, -0.6)),
                    Contains("FR") && Contains("(0.19, -0.14, -0.6)") && Contains("reach"));
  // At the hip itself: inside the abduction-offset cylinder.
  CHECK_THROWS_WITH(kin.inverseKinematics(legkit::model::RL, Eigen::Vector3d(-0.1934, 0.0465, 0)),
                    Contains("RL") && Contains("cylinder"));
  // Reachable by the chain but only with a knee bent further than its limit allows.
  CHECK_THROWS_WITH(kin.inverseKinematics(legkit::model::FL, Eigen::Vector3d(0.1934, 0.141, -0.02)),
                    Contains("FL") && Contains("joint limits"));
}

TEST_CASE("bad inputs to the kinematics are rejected with a clear message", "[57.3][model]") {
  const QuadrupedKinematics kin;
  using Catch::Matchers::Contains;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(kin.footPosition(4, Eigen::Vector3d::Zero()), Contains("leg id 4"));
  CHECK_THROWS_AS(kin.footJacobian(-1, Eigen::Vector3d::Zero()), std::invalid_argument);
  CHECK_THROWS_AS(kin.inverseKinematics(7, Eigen::Vector3d::Zero()), std::invalid_argument);
  CHECK_THROWS_WITH(kin.footPosition(1, Eigen::Vector3d(0, nan, 0)),
                    Contains("FR") && Contains("not finite"));
  CHECK_THROWS_AS(kin.footJacobian(0, Eigen::Vector3d(nan, 0, 0)), std::invalid_argument);
  CHECK_THROWS_AS(kin.inverseKinematics(0, Eigen::Vector3d(0, 0, nan)), std::invalid_argument);
  QuadrupedGeometry broken = QuadrupedGeometry::go2();
  broken.calf_length = -0.2;
  CHECK_THROWS_AS(QuadrupedKinematics(broken), std::invalid_argument);
}
