// The shipped robots of config/robots/ (public URDFs whose meshes are not shipped) through the
// kit's kinematics (MujocoLegKinematics, MuJoCo) against an independent implementation: orocos-kdl
// with kdl_parser and urdfdom (Debian's, linked by this test only). For each robot: its settings
// file loads; every foot's position in the base frame and its Jacobian agree with KDL's chain from
// the base to the foot at random joint angles; the IMU extrinsic written in the settings file is
// the URDF's pose of the IMU link in the base.
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/tree.hpp>
#include <kdl_parser/kdl_parser.hpp>

#include <catch2/catch.hpp>
#include <ios>
#include <random>
#include <string>
#include <vector>

#include "estimation/settings.hpp"
#include "model/mujoco_kinematics.hpp"

using namespace legkit;

namespace {

struct ShippedRobot {
  const char* settings;  // under config/robots/
  const char* imu_link;  // the URDF link the settings' imu.extrinsic places
};

constexpr ShippedRobot kRobots[] = {
    {"go1.yaml", "imu_link"}, {"go2.yaml", "imu"},
    {"a1.yaml", "imu_link"},  {"aliengo.yaml", "imu_link"},
    {"b2.yaml", "imu_link"},  {"g1.yaml", "imu_in_pelvis"},
    {"h1.yaml", "imu_link"},  {"icub.yaml", "root_link_imu_frame"},
};

KDL::Tree kdlTree(const std::string& urdf) {
  KDL::Tree tree;
  REQUIRE(kdl_parser::treeFromFile(urdf, tree));
  return tree;
}

KDL::Chain kdlChain(const KDL::Tree& tree, const std::string& from, const std::string& to) {
  KDL::Chain chain;
  INFO(from << " -> " << to);
  REQUIRE(tree.getChain(from, to, chain));
  return chain;
}

// The index in the kit's joint order of each movable joint of `chain`, in chain order.
std::vector<int> kitColumns(const KDL::Chain& chain, const model::MujocoLegKinematics& legs) {
  std::vector<int> columns;
  for (const KDL::Segment& segment : chain.segments) {
    if (segment.getJoint().getType() == KDL::Joint::None) continue;
    int column = -1;
    for (int k = 0; k < legs.numJoints(); ++k) {
      if (legs.jointName(k) == segment.getJoint().getName()) column = k;
    }
    INFO("joint " << segment.getJoint().getName() << " moves a foot but is not a leg joint");
    REQUIRE(column >= 0);
    columns.push_back(column);
  }
  return columns;
}

}  // namespace

TEST_CASE(
    "Shipped robots: feet, their orientations and Jacobians equal orocos-kdl's, the IMU pose the "
    "URDF's",
    "[57.11][model][robot][mujoco]") {
  std::mt19937 gen(2211);
  std::uniform_real_distribution<double> angle(-1.5, 1.5);
  for (const ShippedRobot& robot : kRobots) {
    const Settings settings =
        loadSettings(std::string(LEGKIT_SOURCE_DIR) + "/config/robots/" + robot.settings);
    const RobotSettings& r = settings.robot;
    INFO(robot.settings << ": " << r.model);
    // Loads although the URDF names meshes that are not there.
    const auto legs = model::MujocoLegKinematics::fromFile(r.model, r.base, r.feet, r.joints);
    const KDL::Tree tree = kdlTree(r.model);

    double worst_p = 0.0, worst_J = 0.0, worst_R = 0.0, worst_Jw = 0.0;
    for (int f = 0; f < legs.numFeet(); ++f) {
      const KDL::Chain chain = kdlChain(tree, r.base, legs.footName(f));
      const std::vector<int> columns = kitColumns(chain, legs);
      KDL::ChainFkSolverPos_recursive kdl_fk(chain);
      KDL::ChainJntToJacSolver kdl_jac(chain);  // base axes, reference point at the foot
      for (int draw = 0; draw < 50; ++draw) {
        model::LegJointVector q = model::LegJointVector::Zero();
        for (int k = 0; k < legs.numJoints(); ++k) q[k] = angle(gen);
        KDL::JntArray q_chain(chain.getNrOfJoints());
        for (std::size_t i = 0; i < columns.size(); ++i) q_chain(i) = q[columns[i]];
        KDL::Frame frame;
        KDL::Jacobian J_kdl(chain.getNrOfJoints());
        REQUIRE(kdl_fk.JntToCart(q_chain, frame) >= 0);
        REQUIRE(kdl_jac.JntToJac(q_chain, J_kdl) >= 0);

        Eigen::Vector3d p;
        model::FootJacobian J;
        legs.foot(f, q, p, J);
        worst_p = std::max(worst_p, (p - Eigen::Vector3d(frame.p.data)).cwiseAbs().maxCoeff());
        model::FootJacobian J_ref = model::FootJacobian::Zero();  // other legs' columns stay 0
        for (std::size_t i = 0; i < columns.size(); ++i) {
          J_ref.col(columns[i]) = J_kdl.data.block<3, 1>(0, static_cast<Eigen::Index>(i));
        }
        worst_J = std::max(worst_J, (J - J_ref).cwiseAbs().maxCoeff());

        // The foot frame's orientation and rotational Jacobian (flat feet): KDL's M and the
        // Jacobian's angular rows, both in the base's axes.
        Eigen::Matrix3d R_BF;
        model::FootJacobian J_w;
        REQUIRE(legs.footRotation(f, q, R_BF, J_w));
        const Eigen::Matrix3d R_kdl =
            Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(frame.M.data);
        worst_R = std::max(worst_R, (R_BF - R_kdl).cwiseAbs().maxCoeff());
        J_ref.setZero();
        for (std::size_t i = 0; i < columns.size(); ++i) {
          J_ref.col(columns[i]) = J_kdl.data.block<3, 1>(3, static_cast<Eigen::Index>(i));
        }
        worst_Jw = std::max(worst_Jw, (J_w - J_ref).cwiseAbs().maxCoeff());
      }
    }
    INFO("worst |p - p_KDL| " << std::scientific << worst_p << " m, |J - J_KDL| " << worst_J
                              << ", |R_BF - R_KDL| " << worst_R << ", |J_w - J_w,KDL| "
                              << worst_Jw);
    CHECK(worst_p < 1e-9);
    CHECK(worst_J < 1e-9);
    CHECK(worst_R < 1e-9);
    CHECK(worst_Jw < 1e-9);

    // The settings' IMU pose is the URDF's, at zero angles (the H1's IMU is behind a joint).
    const KDL::Chain to_imu = kdlChain(tree, r.base, robot.imu_link);
    KDL::ChainFkSolverPos_recursive imu_fk(to_imu);
    KDL::Frame T_BI;
    REQUIRE(imu_fk.JntToCart(KDL::JntArray(to_imu.getNrOfJoints()), T_BI) >= 0);
    double x, y, z, w;
    T_BI.M.GetQuaternion(x, y, z, w);
    const Eigen::Quaterniond q_BI(w, x, y, z);
    CHECK((settings.imu_extrinsic.p_BI - Eigen::Vector3d(T_BI.p.data)).norm() < 1e-9);
    CHECK(settings.imu_extrinsic.q_BI.angularDistance(q_BI) < 1e-9);
  }
}
