// QuadrupedDynamics (model/floating_base_dynamics.hpp) against MuJoCo's M (mj_fullM) and bias
// forces (qfrc_bias) on the kit's own MJCF (model/mjcf.hpp), on random states; then properties that
// need no simulator: M symmetric positive definite, the base block's mass, h at rest against the
// links' weights, the kinetic energy against the links' velocities, and the foot Jacobian against
// MuJoCo's mj_jacSite and finite differences of the FK. This program counts every heap allocation
// it makes (tests/allocation_counter.hpp; the dynamics must make none per call).
#include <mujoco/mujoco.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "allocation_counter.hpp"
#include "model/floating_base_dynamics.hpp"
#include "model/mjcf.hpp"
#include "model/mujoco.hpp"

using namespace legkit::model;

namespace {

constexpr int kStates = 200;  // random states per check

// A random state: base anywhere within 2 m with any attitude, base twist and joint rates of a
// lively gait or a fall (|v| ~ 1 m/s, |omega| ~ 2 rad/s, |dq| ~ 5 rad/s per axis), joint angles
// uniform within the limits.
FloatingBaseState randomState(const QuadrupedGeometry& g, std::mt19937& gen) {
  std::uniform_real_distribution<double> unit(0.0, 1.0), pos(-2.0, 2.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  FloatingBaseState x;
  x.p = Eigen::Vector3d(pos(gen), pos(gen), pos(gen));
  x.R = Eigen::Quaterniond(normal(gen), normal(gen), normal(gen), normal(gen))
            .normalized()
            .toRotationMatrix();
  x.v = Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
  x.omega = 2.0 * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
  for (int leg = 0; leg < kNumLegs; ++leg) {
    for (int j = 0; j < 3; ++j) {
      x.q[3 * leg + j] = g.q_min[leg][j] + (g.q_max[leg][j] - g.q_min[leg][j]) * unit(gen);
      x.dq[3 * leg + j] = 5.0 * normal(gen);
    }
  }
  return x;
}

// The state reached after moving for time t with the generalized velocity nu (from x):
// p + t v, R Exp(t omega) (omega in the body frame), q + t dq. Its derivative in t at 0 is the
// velocity nu, so central differences along it give d/dt of anything that depends on (p, R, q).
FloatingBaseState moved(const FloatingBaseState& x, const GeneralizedVector& nu, double t) {
  FloatingBaseState y = x;
  y.p += t * nu.head<3>();
  const Eigen::Vector3d phi = t * nu.segment<3>(3);
  if (phi.norm() > 0.0) y.R = x.R * Eigen::AngleAxisd(phi.norm(), phi.normalized());
  y.q += t * nu.tail<kNumJointDof>();
  return y;
}

struct Pose {
  Eigen::Matrix3d R;  // link to world
  Eigen::Vector3d p;  // link origin, world
};

// World poses of the 13 links (trunk, then hip, thigh, calf of each leg), from the link frames of
// model/quadruped_inertia.hpp: written here from that description, independently of the spatial
// algebra under test.
std::array<Pose, 13> linkPoses(const QuadrupedGeometry& g, const FloatingBaseState& x) {
  const auto rot = [](double angle, int axis) {
    return Eigen::AngleAxisd(angle, Eigen::Vector3d::Unit(axis)).toRotationMatrix();
  };
  std::array<Pose, 13> pose;
  pose[0] = {x.R, x.p};
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const int b = 1 + 3 * leg;
    const Pose& base = pose[0];
    pose[b] = {base.R * rot(x.q[3 * leg], 0), base.p + base.R * g.hip_offset[leg]};
    const Pose& hip = pose[b];
    pose[b + 1] = {hip.R * rot(x.q[3 * leg + 1], 1),
                   hip.p + hip.R * Eigen::Vector3d(0, lateralSign(leg) * g.abduction_offset, 0)};
    const Pose& thigh = pose[b + 1];
    pose[b + 2] = {thigh.R * rot(x.q[3 * leg + 2], 1),
                   thigh.p + thigh.R * Eigen::Vector3d(0, 0, -g.thigh_length)};
  }
  return pose;
}

std::array<LinkInertia, 13> links(const QuadrupedInertia& in) {
  std::array<LinkInertia, 13> l;
  l[0] = in.trunk;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    l[1 + 3 * leg] = in.hip[leg];
    l[2 + 3 * leg] = in.thigh[leg];
    l[3 + 3 * leg] = in.calf[leg];
  }
  return l;
}

constexpr double kStep = 1e-6;  // central-difference step [s]

// World-frame centre-of-mass Jacobian (3 x 18) of link b by central differences.
Eigen::Matrix<double, 3, kNumDof> comJacobian(const QuadrupedGeometry& g, const LinkInertia& link,
                                              int b, const FloatingBaseState& x) {
  Eigen::Matrix<double, 3, kNumDof> J;
  for (int k = 0; k < kNumDof; ++k) {
    const GeneralizedVector e = GeneralizedVector::Unit(k);
    const Pose a = linkPoses(g, moved(x, e, kStep))[b], c = linkPoses(g, moved(x, e, -kStep))[b];
    J.col(k) = ((a.p + a.R * link.com) - (c.p + c.R * link.com)) / (2.0 * kStep);
  }
  return J;
}

void toMujoco(const FloatingBaseState& x, const mjModel& m, mjData& d) {
  const Eigen::Quaterniond quat(x.R);
  for (int k = 0; k < 3; ++k) d.qpos[k] = x.p[k];
  d.qpos[3] = quat.w();  // MuJoCo's quaternion is (w, x, y, z)
  d.qpos[4] = quat.x();
  d.qpos[5] = quat.y();
  d.qpos[6] = quat.z();
  // nu is MuJoCo's qvel entry for entry (the mapping is the identity).
  Eigen::Map<GeneralizedVector>(d.qvel) = x.nu();
  for (int k = 0; k < kNumJointDof; ++k) d.qpos[7 + k] = x.q[k];
  mj_fwdPosition(&m, &d);
  mj_fwdVelocity(&m, &d);
}

struct Robot {
  QuadrupedGeometry geometry = QuadrupedGeometry::go2();
  QuadrupedInertia inertia = QuadrupedInertia::go2();
  QuadrupedDynamics dynamics{geometry, inertia};
};

}  // namespace

// Largest entry-wise differences of M and h from MuJoCo's over kStates random states.
struct MujocoComparison {
  double M = 0.0, h = 0.0;                  // worst |ours - MuJoCo|
  double largest_M = 0.0, largest_h = 0.0;  // largest |entry| of ours
};

MujocoComparison compareWithMujoco(const QuadrupedDynamics& dynamics, const QuadrupedGeometry& g,
                                   const mjModel& m, mjData& d) {
  std::mt19937 gen(576);
  MujocoComparison c;
  for (int trial = 0; trial < kStates; ++trial) {
    const FloatingBaseState x = randomState(g, gen);
    toMujoco(x, m, d);
    Eigen::Matrix<double, kNumDof, kNumDof, Eigen::RowMajor> M_mj;
    mj_fullM(&m, M_mj.data(), d.qM);
    const Eigen::Map<const GeneralizedVector> h_mj(d.qfrc_bias);
    const GeneralizedMatrix M = dynamics.massMatrix(x);
    const GeneralizedVector h = dynamics.biasForces(x);
    c.M = std::max(c.M, (M - M_mj).cwiseAbs().maxCoeff());
    c.h = std::max(c.h, (h - h_mj).cwiseAbs().maxCoeff());
    c.largest_M = std::max(c.largest_M, M.cwiseAbs().maxCoeff());
    c.largest_h = std::max(c.largest_h, h.cwiseAbs().maxCoeff());
  }
  return c;
}

TEST_CASE("spatial algebra: the structured operations equal their 6x6 matrices",
          "[57.6][model][dynamics]") {
  namespace sp = legkit::model::spatial;
  std::mt19937 gen(5760);
  std::normal_distribution<double> n(0.0, 1.0);
  const auto vec6 = [&] {
    sp::Vector6 x;
    for (int k = 0; k < 6; ++k) x[k] = n(gen);
    return x;
  };
  for (int trial = 0; trial < 100; ++trial) {
    sp::Transform X;
    X.R = Eigen::Quaterniond(n(gen), n(gen), n(gen), n(gen)).normalized().toRotationMatrix();
    X.r = Eigen::Vector3d(n(gen), n(gen), n(gen));
    LinkInertia link;
    link.mass = 1.0 + std::abs(n(gen));
    link.com = Eigen::Vector3d(n(gen), n(gen), n(gen));
    const Eigen::Matrix3d A = Eigen::Matrix3d::Random();
    link.inertia = A * A.transpose() + Eigen::Matrix3d::Identity();
    const sp::RigidBodyInertia I = sp::spatialInertia(link);
    const sp::Vector6 V = vec6(), W = vec6(), F = vec6();
    const sp::Matrix6 Xm = sp::motionToChildMatrix(X);
    // crm(V) = [[w]x, 0; [v]x, [w]x], crf(V) = -crm(V)^T.
    sp::Matrix6 crm;
    crm << lie::hat3(V.head<3>()), Eigen::Matrix3d::Zero(), lie::hat3(V.tail<3>()),
        lie::hat3(V.head<3>());
    REQUIRE((sp::crossMotion(V, W) - crm * W).cwiseAbs().maxCoeff() < 1e-12);
    REQUIRE((sp::crossForce(V, F) + crm.transpose() * F).cwiseAbs().maxCoeff() < 1e-12);
    REQUIRE((sp::motionToChild(X, V) - Xm * V).cwiseAbs().maxCoeff() < 1e-12);
    REQUIRE((sp::forceToParent(X, F) - Xm.transpose() * F).cwiseAbs().maxCoeff() < 1e-12);
    REQUIRE((I * V - I.matrix() * V).cwiseAbs().maxCoeff() < 1e-12);
    REQUIRE((sp::inertiaToParent(X, I).matrix() - Xm.transpose() * I.matrix() * Xm)
                .cwiseAbs()
                .maxCoeff() < 1e-12);
    // Power is frame-independent: F . V is the same in parent and child.
    REQUIRE(std::abs(sp::forceToParent(X, F).dot(V) - F.dot(sp::motionToChild(X, V))) < 1e-12);
    // The momentum of a link: linear m (v + w x c).
    const sp::Vector6 momentum = I * V;
    REQUIRE((momentum.tail<3>() - link.mass * (V.tail<3>() + V.head<3>().cross(link.com)))
                .cwiseAbs()
                .maxCoeff() < 1e-12);
  }
}

TEST_CASE("M and h agree with MuJoCo's mj_fullM and qfrc_bias to 1e-9 on random states",
          "[57.6][model][dynamics][mujoco]") {
  const Robot robot;
  const MjModelPtr m = loadMjcf(quadrupedMjcf(robot.geometry, robot.inertia));
  REQUIRE(m->nv == kNumDof);
  REQUIRE(m->nq == 7 + kNumJointDof);
  const MjDataPtr d = makeData(*m);

  // The same mass properties on both sides: quadrupedMjcf writes each inertia in principal form
  // with 17 digits, so MuJoCo holds the very doubles of QuadrupedInertia::go2().
  const MujocoComparison c = compareWithMujoco(robot.dynamics, robot.geometry, *m, *d);
  INFO("worst |M - M_mujoco| " << c.M << " (largest |M_ij| " << c.largest_M
                               << "), worst |h - h_mujoco| " << c.h << " (largest |h_i| "
                               << c.largest_h << ")");
  // Absolute, entry by entry: the entries are O(1)..O(100) in SI units (M up to the 15.2 kg mass,
  // h up to the weight plus the centrifugal forces of the random rates), so 1e-9 is a relative
  // 1e-11 of the largest and leaves no room for a missing term of any physical size.
  CHECK(c.M < 1e-9);
  CHECK(c.h < 1e-9);
  CHECK(c.largest_h > 100.0);  // the states did exercise large bias forces
}

TEST_CASE("M is symmetric positive definite and its base block holds the robot's mass",
          "[57.6][model][dynamics]") {
  const Robot robot;
  const double mass = robot.inertia.totalMass();
  std::mt19937 gen(5761);
  for (int trial = 0; trial < kStates; ++trial) {
    const FloatingBaseState x = randomState(robot.geometry, gen);
    const GeneralizedMatrix M = robot.dynamics.massMatrix(x);
    REQUIRE((M - M.transpose()).cwiseAbs().maxCoeff() == 0.0);
    const Eigen::SelfAdjointEigenSolver<GeneralizedMatrix> eig(M);
    REQUIRE(eig.eigenvalues().minCoeff() > 1e-4);
    // The v block: a pure translation of the whole robot, momentum m v.
    REQUIRE((M.topLeftCorner<3, 3>() - mass * Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <
            1e-12);
  }
}

TEST_CASE("h at rest is minus the generalized gravity, -sum_i J_ci^T m_i g",
          "[57.6][model][dynamics]") {
  const Robot robot;
  const auto l = links(robot.inertia);
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  std::mt19937 gen(5762);
  for (int trial = 0; trial < 100; ++trial) {
    FloatingBaseState x = randomState(robot.geometry, gen);
    x.v.setZero();
    x.omega.setZero();
    x.dq.setZero();
    GeneralizedVector gravity = GeneralizedVector::Zero();  // sum_i J_ci^T m_i g
    for (int b = 0; b < 13; ++b) {
      gravity += comJacobian(robot.geometry, l[b], b, x).transpose() * (l[b].mass * g);
    }
    const GeneralizedVector h = robot.dynamics.biasForces(x);
    INFO("h " << h.transpose() << "\n-G " << -gravity.transpose());
    REQUIRE((h + gravity).cwiseAbs().maxCoeff() < 1e-7);
  }
}

TEST_CASE("1/2 nu^T M nu is the links' kinetic energy plus the rotors'",
          "[57.6][model][dynamics]") {
  const Robot robot;
  const auto l = links(robot.inertia);
  std::mt19937 gen(5763);
  for (int trial = 0; trial < 100; ++trial) {
    const FloatingBaseState x = randomState(robot.geometry, gen);
    const GeneralizedVector nu = x.nu();
    // Each link's motion by central differences of its world pose along nu.
    const auto ahead = linkPoses(robot.geometry, moved(x, nu, kStep));
    const auto behind = linkPoses(robot.geometry, moved(x, nu, -kStep));
    double T = 0.0;
    for (int b = 0; b < 13; ++b) {
      const Eigen::Vector3d v_c =
          ((ahead[b].p + ahead[b].R * l[b].com) - (behind[b].p + behind[b].R * l[b].com)) /
          (2.0 * kStep);
      // Link-frame angular velocity: Log(R(-h)^T R(+h)) / 2h.
      const Eigen::AngleAxisd turn(behind[b].R.transpose() * ahead[b].R);
      const Eigen::Vector3d w = turn.angle() * turn.axis() / (2.0 * kStep);
      T += 0.5 * l[b].mass * v_c.squaredNorm() + 0.5 * w.dot(l[b].inertia * w);
    }
    for (int k = 0; k < kNumJointDof; ++k) {
      T += 0.5 * robot.inertia.armature[k % 3] * x.dq[k] *
           x.dq[k];  // rotor: armature on M's diagonal
    }
    const double T_M = 0.5 * nu.dot(robot.dynamics.massMatrix(x) * nu);
    INFO("T from M " << T_M << ", from the links " << T);
    REQUIRE(T > 1.0);
    REQUIRE(std::abs(T_M - T) < 1e-8 * T);
  }
}

TEST_CASE("footJacobian agrees with mj_jacSite and with finite differences of the FK",
          "[57.6][model][dynamics][mujoco]") {
  const Robot robot;
  const MjModelPtr m = loadMjcf(quadrupedMjcf(robot.geometry, robot.inertia));
  const MjDataPtr d = makeData(*m);
  const QuadrupedKinematics& kin = robot.dynamics.kinematics();
  std::mt19937 gen(5764);
  double worst_mj = 0.0, worst_fd = 0.0;
  for (int trial = 0; trial < kStates; ++trial) {
    const FloatingBaseState x = randomState(robot.geometry, gen);
    toMujoco(x, *m, *d);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      const ContactJacobian J = robot.dynamics.footJacobian(leg, x);
      const std::string site = std::string(legName(leg)) + "_foot";
      const int id = mj_name2id(m.get(), mjOBJ_SITE, site.c_str());
      REQUIRE(id >= 0);
      Eigen::Matrix<double, 3, kNumDof, Eigen::RowMajor> J_mj;
      mj_jacSite(m.get(), d.get(), J_mj.data(), nullptr, id);
      worst_mj = std::max(worst_mj, (J - J_mj).cwiseAbs().maxCoeff());
      // Foot in the world: p + R B_p_f(q), differentiated along each coordinate of nu.
      const auto foot = [&](const FloatingBaseState& y) {
        return Eigen::Vector3d(y.p + y.R * kin.footPosition(leg, y.q.segment<3>(3 * leg)));
      };
      for (int k = 0; k < kNumDof; ++k) {
        const GeneralizedVector e = GeneralizedVector::Unit(k);
        const Eigen::Vector3d fd =
            (foot(moved(x, e, kStep)) - foot(moved(x, e, -kStep))) / (2.0 * kStep);
        worst_fd = std::max(worst_fd, (J.col(k) - fd).cwiseAbs().maxCoeff());
      }
    }
  }
  INFO("worst |J - J_mujoco| " << worst_mj << ", worst |J - finite differences| " << worst_fd);
  CHECK(worst_mj < 1e-9);
  CHECK(worst_fd < 1e-7);
}

TEST_CASE("massMatrix, biasForces and footJacobian allocate nothing",
          "[57.6][model][dynamics][allocation]") {
  const Robot robot;
  std::mt19937 gen(5765);
  const FloatingBaseState x = randomState(robot.geometry, gen);
  double sink = 0.0;
  const long before = legkit::test::allocationCount();
  for (int i = 0; i < 10; ++i) {
    sink += robot.dynamics.massMatrix(x)(0, 0) + robot.dynamics.biasForces(x)[0] +
            robot.dynamics.footJacobian(i % kNumLegs, x)(0, 0);
  }
  const long allocations = legkit::test::allocationCount() - before;
  CHECK(allocations == 0);
  CHECK(std::isfinite(sink));
}

TEST_CASE("QuadrupedDynamics rejects bad mass properties and a bad leg id",
          "[57.6][model][dynamics]") {
  const Robot robot;
  QuadrupedInertia bad = robot.inertia;
  bad.thigh[FR].mass = -1.0;
  CHECK_THROWS_WITH(QuadrupedDynamics(robot.geometry, bad), Catch::Contains("FR thigh"));
  bad = robot.inertia;
  bad.armature.x() = -0.01;
  CHECK_THROWS_WITH(QuadrupedDynamics(robot.geometry, bad), Catch::Contains("armature"));
  CHECK_THROWS_AS(QuadrupedDynamics(robot.geometry, robot.inertia, std::nan("")),
                  std::invalid_argument);
  CHECK_THROWS_WITH(robot.dynamics.footJacobian(4, FloatingBaseState{}),
                    Catch::Contains("leg id 4"));
}
