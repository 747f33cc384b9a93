// MujocoLegKinematics on robots the kit writes itself (tests/model/test_robots.hpp): a URDF biped
// (feet are links on fixed joints, a prismatic joint, no free joint) and an MJCF hexapod (feet are
// sites, a free joint), each against its own FK, the Jacobians against central differences of
// that FK; then every load error, each naming the file and what is wrong.
#include <catch2/catch.hpp>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "model/mujoco_kinematics.hpp"
#include "model/test_robots.hpp"
#include "scratch_folder.hpp"

using namespace legkit::model;
using Catch::Matchers::Contains;
using legkit::test::Biped;
using legkit::test::Hexapod;
using legkit::test::ScratchFolder;

namespace {

std::string write(const ScratchFolder& folder, const std::string& name, const std::string& text) {
  const std::string path = (folder.path / name).string();
  std::ofstream(path) << text;
  return path;
}

struct Agreement {
  double position = 0.0;  // worst |p_MuJoCo - p_FK| [m]
  double jacobian = 0.0;  // worst |J_MuJoCo - J_central difference| [m/rad or m/m]
};

// Compares `robot` with the reference FK `fk(foot, q)` at `draws` random q (uniform in +-range).
template <typename Fk>
Agreement compare(const MujocoLegKinematics& robot, const Fk& fk, double range, int draws) {
  const int n = robot.numJoints();
  std::mt19937 gen(1411);
  std::uniform_real_distribution<double> angle(-range, range);
  Agreement worst;
  constexpr double h = 1e-6;
  for (int draw = 0; draw < draws; ++draw) {
    Eigen::VectorXd q(n);
    for (int k = 0; k < n; ++k) q[k] = angle(gen);
    LegJointVector q_robot = LegJointVector::Zero();
    q_robot.head(n) = q;
    for (int foot = 0; foot < robot.numFeet(); ++foot) {
      Eigen::Vector3d p;
      FootJacobian J;
      robot.foot(foot, q_robot, p, J);
      worst.position = std::max(worst.position, (p - fk(foot, q)).norm());
      for (int k = 0; k < n; ++k) {
        Eigen::VectorXd plus = q, minus = q;
        plus[k] += h;
        minus[k] -= h;
        const Eigen::Vector3d column = (fk(foot, plus) - fk(foot, minus)) / (2.0 * h);
        worst.jacobian = std::max(worst.jacobian, (J.col(k) - column).cwiseAbs().maxCoeff());
      }
      CHECK(J.rightCols(kMaxLegJoints - n).isZero(0.0));
    }
  }
  return worst;
}

}  // namespace

TEST_CASE("A URDF biped: sole links, a prismatic joint, no free joint, against its own FK",
          "[57.11][model][robot][mujoco]") {
  const ScratchFolder folder("robot_biped");
  const Biped biped;
  const std::string path = write(folder, "biped.urdf", biped.urdf());
  const std::vector<std::string> joints = biped.legJoints();
  REQUIRE(joints.size() == 14);

  // Default joints: every hinge and slide below the pelvis, 14 of them.
  const MujocoLegKinematics defaults = MujocoLegKinematics::fromFile(path, "pelvis", biped.feet);
  REQUIRE(defaults.numJoints() == 14);
  // MuJoCo numbers joints depth-first through the tree: for this file, the file's order.
  for (int k = 0; k < 14; ++k) CHECK(defaults.jointName(k) == joints[k]);
  CHECK(defaults.footName(1) == "r_sole");

  const MujocoLegKinematics robot =
      MujocoLegKinematics::fromFile(path, "pelvis", biped.feet, joints);
  REQUIRE(robot.numJoints() == 14);
  REQUIRE(robot.numFeet() == 2);
  const Agreement worst = compare(
      robot, [&](int foot, const Eigen::VectorXd& q) { return biped.foot(foot, q); }, 1.0, 100);
  CHECK(worst.position < 1e-12);
  CHECK(worst.jacobian < 1e-8);
  WARN("biped, 100 draws x 2 feet: |p - FK| = "
       << worst.position << " m, max |J - central difference| = " << worst.jacobian);

  // A URDF with its own <mujoco> element: the loader's settings join it (or its <compiler>).
  for (const std::string element : {"<mujoco/>", "<mujoco><compiler angle=\"radian\"/></mujoco>",
                                    "<mujoco>\n<!-- a comment with <compiler> in it -->\n<option "
                                    "timestep=\"0.001\"/></mujoco>"}) {
    INFO(element);
    const std::string own = write(folder, "own.urdf", biped.urdf(element));
    const MujocoLegKinematics with_own =
        MujocoLegKinematics::fromFile(own, "pelvis", biped.feet, joints);
    const Agreement same = compare(
        with_own, [&](int foot, const Eigen::VectorXd& q) { return biped.foot(foot, q); }, 1.0, 3);
    CHECK(same.position < 1e-12);
  }
  // A compiler setting the file gives is left alone: fused, the pelvis is part of the world.
  const std::string fused =
      write(folder, "fused.urdf", biped.urdf("<mujoco><compiler fusestatic=\"true\"/></mujoco>"));
  CHECK_THROWS_WITH(MujocoLegKinematics::fromFile(fused, "pelvis", biped.feet),
                    Contains(fused) && Contains("no body named 'pelvis'"));
}

TEST_CASE("An MJCF hexapod: foot sites, a free joint, against its closed-form FK",
          "[57.11][model][robot][mujoco]") {
  const ScratchFolder folder("robot_hexapod");
  const Hexapod hexapod;
  const std::string path = write(folder, "hexapod.xml", hexapod.mjcf());
  const MujocoLegKinematics robot = MujocoLegKinematics::fromFile(path, "thorax", hexapod.feet());
  REQUIRE(robot.numFeet() == 6);
  REQUIRE(robot.numJoints() == 18);  // the free joint "root" is not a leg joint
  CHECK(robot.jointName(0) == "L1_coxa");
  CHECK(robot.jointName(17) == "R3_tibia");
  const Agreement worst = compare(
      robot, [&](int foot, const Eigen::VectorXd& q) { return hexapod.foot(foot, q); }, 1.2, 100);
  CHECK(worst.position < 1e-12);
  CHECK(worst.jacobian < 1e-8);
  WARN("hexapod, 100 draws x 6 feet: |p - FK| = "
       << worst.position << " m, max |J - central difference| = " << worst.jacobian);
  // A body as a foot frame: its origin (the tibia joint, at the femur's end).
  const MujocoLegKinematics bodies = MujocoLegKinematics::fromFile(path, "thorax", {"L2_tibia"});
  LegJointVector q = LegJointVector::Zero();
  q[3] = 0.3;  // L2 coxa
  Eigen::Vector3d p;
  FootJacobian J;
  bodies.foot(0, q, p, J);
  const Eigen::Vector3d expected =
      hexapod.hip(1) +
      (hexapod.coxa + hexapod.femur) * Eigen::Vector3d(std::cos(1.5707963267948966 + 0.3),
                                                       std::sin(1.5707963267948966 + 0.3), 0.0);
  CHECK((p - expected).norm() < 1e-12);

  // A base that is turned and offset in the world: the L2 coxa. Its own hinge moves the base, not
  // the foot relative to it, so the foot sits at (x, 0, z) of the header's FK in the coxa frame.
  const MujocoLegKinematics coxa =
      MujocoLegKinematics::fromFile(path, "L2_coxa", {"L2_foot"}, {"L2_femur", "L2_tibia"});
  Eigen::VectorXd q_hexapod = Eigen::VectorXd::Zero(18);
  q_hexapod.segment<3>(3) << 0.0, 0.4, -0.9;  // L2: coxa at zero, femur, tibia
  q.setZero();
  q.head<2>() << 0.4, -0.9;
  coxa.foot(0, q, p, J);
  const Eigen::Vector3d in_coxa = hexapod.foot(1, q_hexapod) - hexapod.hip(1);
  const Eigen::Vector3d turned(std::cos(1.5707963267948966), std::sin(1.5707963267948966), 0.0);
  CHECK((p - Eigen::Vector3d(in_coxa.dot(turned), 0.0, in_coxa.z())).norm() < 1e-12);
}

TEST_CASE("Robot model errors name the file and what is wrong", "[57.11][model][robot][mujoco]") {
  const ScratchFolder folder("robot_errors");
  const Biped biped;
  const Hexapod hexapod;
  const std::string urdf = write(folder, "biped.urdf", biped.urdf());
  const std::string mjcf = write(folder, "hexapod.xml", hexapod.mjcf());
  const auto load = [](const std::string& path, const std::string& base,
                       const std::vector<std::string>& feet,
                       const std::vector<std::string>& joints = {}) {
    return MujocoLegKinematics::fromFile(path, base, feet, joints);
  };

  const std::string missing = (folder.path / "nowhere.urdf").string();
  CHECK_THROWS_WITH(load(missing, "pelvis", biped.feet),
                    Contains(missing) && Contains("cannot open"));

  const std::string broken = write(folder, "broken.urdf", "<robot name='x'>\n<link name='a'>\n");
  CHECK_THROWS_WITH(load(broken, "pelvis", biped.feet),
                    Contains(broken) && Contains("MuJoCo cannot load it") && Contains("XML"));
  const std::string bad_mjcf = write(folder, "bad.xml",
                                     "<mujoco><worldbody><body><joint type='spiral'/></body>"
                                     "</worldbody></mujoco>");
  CHECK_THROWS_WITH(load(bad_mjcf, "base", {"foot"}),
                    Contains(bad_mjcf) && Contains("MuJoCo cannot load it") && Contains("spiral"));

  CHECK_THROWS_WITH(load(urdf, "torso", biped.feet),
                    Contains(urdf) && Contains("no body named 'torso'") && Contains("pelvis"));
  // An empty name never matches an unnamed object (MuJoCo's own lookup would).
  const std::string unnamed = write(
      folder, "unnamed.xml",
      hexapod.mjcf("<body pos='0 0 0.05'><joint axis='0 1 0'/><inertial pos='0 0 0' mass='0.1' "
                   "diaginertia='1e-4 1e-4 1e-4'/><site/></body>"));
  CHECK_THROWS_WITH(load(unnamed, "", {"L1_foot"}), Contains("no body named '' for the base"));
  CHECK_THROWS_WITH(load(unnamed, "thorax", {""}), Contains("no site or body named ''"));
  CHECK_THROWS_WITH(load(unnamed, "thorax", {"L1_foot"}, {""}), Contains("no joint named ''"));
  CHECK(load(unnamed, "thorax", {"L1_foot"}).jointName(18) ==
        "#19");  // by its MuJoCo id (root is 0)
  CHECK_THROWS_WITH(load(urdf, "pelvis", {"l_sole", "l_toe"}),
                    Contains("no site or body named 'l_toe'") && Contains("l_sole"));
  CHECK_THROWS_WITH(load(mjcf, "thorax", {"L1_toe"}), Contains("no site or body named 'L1_toe'") &&
                                                          Contains("L1_foot") &&
                                                          Contains("L1_tibia"));
  CHECK_THROWS_WITH(load(urdf, "pelvis", biped.feet, {"l_knee", "l_ankle_yaw"}),
                    Contains("no joint named 'l_ankle_yaw'") && Contains("l_ankle_roll"));

  std::vector<std::string> seven = hexapod.feet();
  seven.push_back("L1_tibia");
  CHECK_THROWS_WITH(load(mjcf, "thorax", seven),
                    Contains(mjcf) && Contains("7 feet named") && Contains("at most 6"));
  CHECK_THROWS_WITH(load(mjcf, "thorax", {}), Contains("no foot named"));

  // 25 hinges below the base: too many by default, and too many named.
  std::string chain, close;
  std::vector<std::string> names;
  for (int i = 0; i < 25; ++i) {
    names.push_back("j" + std::to_string(i));
    chain += "<body name='b" + std::to_string(i) + "' pos='0 0 -0.1'><joint name='" + names.back() +
             "' axis='0 1 0'/><inertial pos='0 0 0' mass='0.1' diaginertia='1e-4 1e-4 1e-4'/>";
    close += "</body>";
  }
  const std::string snake =
      write(folder, "snake.xml",
            "<mujoco><worldbody><body name='base'><freejoint/><inertial pos='0 0 0' mass='1' "
            "diaginertia='0.01 0.01 0.01'/>" +
                chain + "<site name='tip'/>" + close + "</body></worldbody></mujoco>");
  CHECK_THROWS_WITH(load(snake, "base", {"tip"}), Contains(snake) &&
                                                      Contains("25 hinge and slide joints") &&
                                                      Contains("at most 24"));
  CHECK_THROWS_WITH(load(snake, "base", {"tip"}, names),
                    Contains("25 joints named") && Contains("at most 24"));
  names.pop_back();
  CHECK(load(snake, "base", {"tip"}, names).numJoints() == 24);

  CHECK_THROWS_WITH(
      load(mjcf, "L1_coxa", {"L1_foot", "R1_foot"}),
      Contains("foot 'R1_foot' (on body 'R1_tibia') is not below the base 'L1_coxa'"));
  CHECK_THROWS_WITH(load(mjcf, "thorax", {"imu"}),
                    Contains("foot 'imu'") && Contains("is not below the base"));
  CHECK_THROWS_WITH(load(mjcf, "L1_coxa", {"L1_foot"}, {"L1_femur", "R1_femur"}),
                    Contains("joint 'R1_femur' is not a hinge or slide joint below the base"));
  CHECK_THROWS_WITH(load(mjcf, "thorax", {"L1_foot"}, {"root"}),
                    Contains("joint 'root' is not a hinge or slide joint below the base"));
  CHECK_THROWS_WITH(load(mjcf, "thorax", {"L1_foot", "L1_foot"}),
                    Contains("foot 'L1_foot' named twice"));
  CHECK_THROWS_WITH(load(mjcf, "thorax", {"L1_foot"}, {"L1_coxa", "L1_coxa"}),
                    Contains("joint 'L1_coxa' named twice"));
  CHECK_THROWS_WITH(load(urdf, "l_foot", {"l_sole"}),  // a fixed joint between them
                    Contains("no hinge or slide joint below the base 'l_foot'"));
}
