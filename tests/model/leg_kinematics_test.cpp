// The legs behind model::LegKinematics: the analytic Go2 (QuadrupedLegKinematics) against
// QuadrupedKinematics, and the kit's own quadruped MJCF, written to a file and loaded through
// MujocoLegKinematics, against the analytic Go2 to 1e-12; no allocation per call.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "model/mjcf.hpp"
#include "model/mujoco_kinematics.hpp"
#include "model/quadruped_inertia.hpp"
#include "model/quadruped_leg_kinematics.hpp"
#include "scratch_folder.hpp"

using namespace legkit::model;

namespace {

// Joint angles of the twelve Go2 joints drawn uniformly within their limits (joint k = 3 leg + j).
LegJointVector randomGo2Angles(std::mt19937& gen) {
  const QuadrupedGeometry g = QuadrupedGeometry::go2();
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  LegJointVector q = LegJointVector::Zero();
  for (int leg = 0; leg < kNumLegs; ++leg) {
    for (int j = 0; j < 3; ++j) {
      q[3 * leg + j] = g.q_min[leg][j] + (g.q_max[leg][j] - g.q_min[leg][j]) * unit(gen);
    }
  }
  return q;
}

// The kit's quadruped MJCF as a file in `folder`.
std::string writeGo2Mjcf(const legkit::test::ScratchFolder& folder) {
  const std::string path = (folder.path / "go2.xml").string();
  std::ofstream(path) << quadrupedMjcf(QuadrupedGeometry::go2(), QuadrupedInertia::go2());
  return path;
}

const std::vector<std::string> kGo2Feet = {"FL_foot", "FR_foot", "RL_foot", "RR_foot"};

}  // namespace

TEST_CASE("QuadrupedLegKinematics is QuadrupedKinematics with joint k = 3 leg + j",
          "[57.11][model][robot]") {
  const QuadrupedLegKinematics legs;
  const QuadrupedKinematics& kin = legs.kinematics();
  CHECK(legs.numFeet() == 4);
  CHECK(legs.numJoints() == 12);
  std::mt19937 gen(5711);
  for (int draw = 0; draw < 50; ++draw) {
    const LegJointVector q = randomGo2Angles(gen);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      Eigen::Vector3d p;
      FootJacobian J;
      J.setConstant(7.0);  // every column is written
      legs.foot(leg, q, p, J);
      const Eigen::Vector3d q_leg = q.segment<3>(3 * leg);
      CHECK(p == kin.footPosition(leg, q_leg));
      CHECK(J.middleCols<3>(3 * leg) == kin.footJacobian(leg, q_leg));
      CHECK(J.leftCols(3 * leg).isZero(0.0));
      CHECK(J.rightCols(kMaxLegJoints - 3 * leg - 3).isZero(0.0));
    }
  }
  CHECK(legs.footName(RL) == "RL");
  Eigen::Vector3d p;
  FootJacobian J;
  CHECK_THROWS_AS(legs.foot(4, LegJointVector::Zero(), p, J), std::invalid_argument);
  CHECK_THROWS_AS(legs.foot(-1, LegJointVector::Zero(), p, J), std::invalid_argument);
}

TEST_CASE("The kit's quadruped MJCF through MuJoCo equals the analytic Go2 to 1e-12",
          "[57.11][model][robot][mujoco]") {
  const legkit::test::ScratchFolder folder("robot_go2");
  const MujocoLegKinematics mujoco =
      MujocoLegKinematics::fromFile(writeGo2Mjcf(folder), "base", kGo2Feet);
  const QuadrupedLegKinematics analytic;
  // The default joints: every hinge below the base in model order, which is the kit's layout.
  REQUIRE(mujoco.numFeet() == 4);
  REQUIRE(mujoco.numJoints() == 12);
  const char* kJoint[3] = {"abduction", "hip", "knee"};
  for (int k = 0; k < 12; ++k) {
    CHECK(mujoco.jointName(k) == std::string(legName(k / 3)) + "_" + kJoint[k % 3]);
  }
  CHECK(mujoco.footName(RR) == "RR_foot");

  std::mt19937 gen(2211);
  double worst_position = 0.0, worst_jacobian = 0.0;
  constexpr int kDraws = 300;
  for (int draw = 0; draw < kDraws; ++draw) {
    const LegJointVector q = randomGo2Angles(gen);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      Eigen::Vector3d p_mujoco, p_analytic;
      FootJacobian J_mujoco, J_analytic;
      mujoco.foot(leg, q, p_mujoco, J_mujoco);
      analytic.foot(leg, q, p_analytic, J_analytic);
      worst_position = std::max(worst_position, (p_mujoco - p_analytic).norm());
      worst_jacobian = std::max(worst_jacobian, (J_mujoco - J_analytic).cwiseAbs().maxCoeff());
    }
  }
  CHECK(worst_position < 1e-12);
  CHECK(worst_jacobian < 1e-12);
  WARN("worst over " << kDraws << " draws x 4 feet: |p_MuJoCo - p_FK| = " << worst_position
                     << " m, max |J_MuJoCo - J_FK| = " << worst_jacobian << " m/rad");
}

TEST_CASE("Named joints set the column order", "[57.11][model][robot][mujoco]") {
  const legkit::test::ScratchFolder folder("robot_go2_order");
  // The rear legs first: column k of J belongs to the k-th named joint.
  const std::vector<std::string> joints = {
      "RL_abduction", "RL_hip", "RL_knee", "RR_abduction", "RR_hip", "RR_knee",
      "FL_abduction", "FL_hip", "FL_knee", "FR_abduction", "FR_hip", "FR_knee"};
  const MujocoLegKinematics mujoco =
      MujocoLegKinematics::fromFile(writeGo2Mjcf(folder), "base", kGo2Feet, joints);
  const QuadrupedLegKinematics analytic;
  std::mt19937 gen(7);
  const LegJointVector q = randomGo2Angles(gen);
  LegJointVector q_named = LegJointVector::Zero();
  q_named.head<6>() = q.segment<6>(6);
  q_named.segment<6>(6) = q.head<6>();
  for (int leg = 0; leg < kNumLegs; ++leg) {
    Eigen::Vector3d p_mujoco, p_analytic;
    FootJacobian J_mujoco, J_analytic;
    mujoco.foot(leg, q_named, p_mujoco, J_mujoco);
    analytic.foot(leg, q, p_analytic, J_analytic);
    const int column = leg < 2 ? 3 * leg + 6 : 3 * leg - 6;
    CHECK((p_mujoco - p_analytic).norm() < 1e-12);
    CHECK((J_mujoco.middleCols<3>(column) - J_analytic.middleCols<3>(3 * leg)).norm() < 1e-12);
    CHECK(std::abs(J_mujoco.norm() - J_analytic.norm()) < 1e-12);  // nothing in other columns
  }
}

TEST_CASE("MujocoLegKinematics::foot allocates nothing", "[57.11][model][robot][mujoco]") {
  const legkit::test::ScratchFolder folder("robot_go2_alloc");
  const MujocoLegKinematics mujoco =
      MujocoLegKinematics::fromFile(writeGo2Mjcf(folder), "base", kGo2Feet);
  std::mt19937 gen(3);
  std::vector<LegJointVector> qs;
  for (int i = 0; i < 100; ++i) qs.push_back(randomGo2Angles(gen));
  Eigen::Vector3d p, sum = Eigen::Vector3d::Zero();
  FootJacobian J;
  const long before = legkit::test::allocationCount();
  for (const LegJointVector& q : qs) {
    for (int foot = 0; foot < mujoco.numFeet(); ++foot) {
      mujoco.foot(foot, q, p, J);
      sum += p;
    }
  }
  CHECK(legkit::test::allocationCount() == before);
  CHECK(sum.allFinite());
  CHECK_THROWS_AS(mujoco.foot(4, qs[0], p, J), std::out_of_range);
  LegJointVector bad = qs[0];
  bad[5] = std::nan("");
  CHECK_THROWS_AS(mujoco.foot(0, bad, p, J), std::invalid_argument);
}

TEST_CASE("makeLegKinematics: the Go2 without a model file, else the file's robot",
          "[57.11][model][robot][mujoco]") {
  const std::unique_ptr<LegKinematics> go2 = makeLegKinematics("", "", {}, {});
  REQUIRE(dynamic_cast<const QuadrupedLegKinematics*>(go2.get()) != nullptr);
  const legkit::test::ScratchFolder folder("robot_make");
  const std::string path = writeGo2Mjcf(folder);
  const std::unique_ptr<LegKinematics> file = makeLegKinematics(path, "base", {"FL_foot"}, {});
  const auto* mujoco = dynamic_cast<const MujocoLegKinematics*>(file.get());
  REQUIRE(mujoco != nullptr);
  CHECK(mujoco->path() == path);
  CHECK(mujoco->numFeet() == 1);
  CHECK_THROWS_WITH(makeLegKinematics("", "base", {}, {}), Catch::Matchers::Contains("no model"));
  CHECK_THROWS_WITH(makeLegKinematics("", "", {"FL_foot"}, {}),
                    Catch::Matchers::Contains("no model"));
  CHECK_THROWS_WITH(makeLegKinematics(path, "trunk", {"FL_foot"}, {}),
                    Catch::Matchers::Contains("no body named 'trunk'"));
}
