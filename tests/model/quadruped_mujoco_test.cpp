// The kit's quadruped in MuJoCo: the MJCF generated from model/'s data (quadrupedMjcf, loaded with
// loadMjcf) against the analytic model. Kinematics (foot positions and foot Jacobians) on random
// base poses and joint angles within the limits, mass properties, names and index layout, contact
// filtering, and the errors of bad input.
#include <mujoco/mujoco.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include "model/mjcf.hpp"
#include "model/mujoco.hpp"
#include "model/quadruped.hpp"
#include "model/quadruped_inertia.hpp"

using namespace legkit::model;

namespace {

constexpr const char* kJointNames[3] = {"abduction", "hip", "knee"};

int id(const mjModel& m, mjtObj type, const std::string& name) {
  const int i = mj_name2id(&m, type, name.c_str());
  INFO("MuJoCo object " << name);
  REQUIRE(i >= 0);
  return i;
}

std::string name(int leg, const char* what) {
  return std::string(legName(leg)) + "_" + what;
}

Eigen::Vector3d vec3(const mjtNum* x) {
  return Eigen::Vector3d(x[0], x[1], x[2]);
}

// The 3x3 inertia MuJoCo holds for body b: principal moments body_inertia in the principal axes
// body_iquat (w, x, y, z), back in the body frame.
Eigen::Matrix3d mujocoInertia(const mjModel& m, int b) {
  const mjtNum* q = m.body_iquat + 4 * b;
  const Eigen::Matrix3d R = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
  return R * vec3(m.body_inertia + 3 * b).asDiagonal() * R.transpose();
}

Eigen::Vector3d sortedEigenvalues(const Eigen::Matrix3d& I) {
  Eigen::Vector3d e = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues();
  std::sort(e.data(), e.data() + 3);
  return e;
}

// Message of the std::invalid_argument that quadrupedMjcf throws (empty when it does not throw).
std::string mjcfError(const QuadrupedGeometry& g, const QuadrupedInertia& in,
                      const MjcfOptions& o) {
  try {
    quadrupedMjcf(g, in, o);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("MuJoCo's foot positions and foot Jacobians equal the analytic model's to 1e-9",
          "[57.3][model][mujoco]") {
  const QuadrupedKinematics kin;
  const QuadrupedGeometry& g = kin.geometry();
  const MjModelPtr m = loadMjcf(quadrupedMjcf(g, QuadrupedInertia::go2()));
  REQUIRE(m->nq == 7 + 3 * kNumLegs);
  REQUIRE(m->nv == 6 + 3 * kNumLegs);
  const MjDataPtr d = makeData(*m);
  int foot_site[kNumLegs];
  for (int leg = 0; leg < kNumLegs; ++leg) foot_site[leg] = id(*m, mjOBJ_SITE, name(leg, "foot"));

  std::mt19937 gen(573);
  std::uniform_real_distribution<double> unit(0.0, 1.0), position(-2.0, 2.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor> jacp(3, m->nv);
  double worst_position = 0.0, worst_jacobian = 0.0;
  constexpr int kDraws = 250;
  for (int draw = 0; draw < kDraws; ++draw) {
    const Eigen::Vector3d p(position(gen), position(gen), position(gen));
    const Eigen::Quaterniond quat =
        Eigen::Quaterniond(normal(gen), normal(gen), normal(gen), normal(gen)).normalized();
    for (int k = 0; k < 3; ++k) d->qpos[k] = p[k];
    d->qpos[3] = quat.w();  // MuJoCo stores (w, x, y, z)
    d->qpos[4] = quat.x();
    d->qpos[5] = quat.y();
    d->qpos[6] = quat.z();
    Eigen::Vector3d q[kNumLegs];
    for (int leg = 0; leg < kNumLegs; ++leg) {
      for (int j = 0; j < 3; ++j) {
        q[leg][j] = g.q_min[leg][j] + (g.q_max[leg][j] - g.q_min[leg][j]) * unit(gen);
        d->qpos[7 + 3 * leg + j] = q[leg][j];
      }
    }
    mj_kinematics(m.get(), d.get());
    mj_comPos(m.get(), d.get());  // the Jacobians need cdof and subtree_com
    const Eigen::Matrix3d R = quat.toRotationMatrix();
    for (int leg = 0; leg < kNumLegs; ++leg) {
      // B_p_f = R^T (x_site - p): the site in the body frame.
      const Eigen::Vector3d site = R.transpose() * (vec3(d->site_xpos + 3 * foot_site[leg]) - p);
      const double position_error = (site - kin.footPosition(leg, q[leg])).norm();
      // mj_jacSite's translational part is world-frame; the leg's three joint columns rotated by
      // R^T are the body-frame Jacobian B_J.
      mj_jacSite(m.get(), d.get(), jacp.data(), nullptr, foot_site[leg]);
      const Eigen::Matrix3d J = R.transpose() * jacp.middleCols<3>(6 + 3 * leg);
      const double jacobian_error = (J - kin.footJacobian(leg, q[leg])).cwiseAbs().maxCoeff();
      worst_position = std::max(worst_position, position_error);
      worst_jacobian = std::max(worst_jacobian, jacobian_error);
      CHECK(position_error < 1e-9);
      CHECK(jacobian_error < 1e-9);
    }
  }
  // Printed on every run: the agreement the chapter quotes.
  WARN("worst over " << kDraws << " draws x 4 feet: |MuJoCo - FK| = " << worst_position
                     << " m, max |MuJoCo - B_J| = " << worst_jacobian << " m/rad");
}

TEST_CASE("MuJoCo's masses and inertias are QuadrupedInertia's", "[57.3][model][mujoco]") {
  const QuadrupedInertia in = QuadrupedInertia::go2();
  CHECK(std::abs(in.totalMass() - 15.206408) < 1e-12);  // 6.921 + 4 (0.678 + 1.152 + 0.241352)
  const MjModelPtr m = loadMjcf(quadrupedMjcf(QuadrupedGeometry::go2(), in));
  CHECK(std::abs(mj_getTotalmass(m.get()) - in.totalMass()) < 1e-12);

  double worst_inertia = 0.0;  // relative
  const auto check = [&](const std::string& body, const LinkInertia& link) {
    INFO("body " << body);
    const int b = id(*m, mjOBJ_BODY, body);
    CHECK(m->body_mass[b] == link.mass);
    CHECK((vec3(m->body_ipos + 3 * b) - link.com).norm() < 1e-15);
    // MuJoCo diagonalises the full inertia: same principal moments, same matrix back.
    const double scale = link.inertia.norm();
    Eigen::Vector3d moments = vec3(m->body_inertia + 3 * b);
    std::sort(moments.data(), moments.data() + 3);
    CHECK((moments - sortedEigenvalues(link.inertia)).norm() < 1e-12 * scale);
    const double error = (mujocoInertia(*m, b) - link.inertia).norm() / scale;
    worst_inertia = std::max(worst_inertia, error);
    CHECK(error < 1e-12);
  };
  check("base", in.trunk);
  for (int leg = 0; leg < kNumLegs; ++leg) {
    check(name(leg, "hip"), in.hip[leg]);
    check(name(leg, "thigh"), in.thigh[leg]);
    check(name(leg, "calf"), in.calf[leg]);
  }
  // The published model mirrors its links: left/right through y, front/rear hips through x.
  CHECK(in.hip[FR].com.y() == -in.hip[FL].com.y());
  CHECK(in.hip[RL].com.x() == -in.hip[FL].com.x());
  CHECK(in.thigh[RR].inertia(0, 1) == -in.thigh[FL].inertia(0, 1));
  CHECK(in.calf[RL].inertia == in.calf[FL].inertia);
  WARN("worst |MuJoCo inertia - QuadrupedInertia| / |I| over 13 bodies: " << worst_inertia);
}

TEST_CASE("Generated model: names, index layout, limits, drives and contact filtering",
          "[57.3][model][mujoco]") {
  const QuadrupedGeometry g = QuadrupedGeometry::go2();
  const QuadrupedInertia in = QuadrupedInertia::go2();
  MjcfOptions o;
  o.ground_friction = 0.7;
  o.extra_worldbody = "<geom name='patch' type='box' pos='1 0 0' size='0.5 0.5 0.001'/>";
  const MjModelPtr m = loadMjcf(quadrupedMjcf(g, in, o));

  CHECK(m->opt.timestep == o.timestep);
  CHECK(m->opt.integrator == mjINT_EULER);
  CHECK(m->opt.solver == mjSOL_NEWTON);
  CHECK(m->opt.cone == mjCONE_ELLIPTIC);
  CHECK(m->opt.impratio == 10.0);
  CHECK(m->opt.gravity[2] == -o.gravity);

  const int base = id(*m, mjOBJ_JOINT, "base");
  CHECK(m->jnt_type[base] == mjJNT_FREE);
  CHECK(m->jnt_qposadr[base] == 0);
  CHECK(vec3(m->qpos0) == o.base_position);
  const int imu = id(*m, mjOBJ_SITE, "imu");
  CHECK(m->site_bodyid[imu] == id(*m, mjOBJ_BODY, "base"));
  CHECK(vec3(m->site_pos + 3 * imu).isZero(0.0));
  CHECK(m->site_quat[4 * imu] == 1.0);

  REQUIRE(m->nu == 3 * kNumLegs);
  for (int leg = 0; leg < kNumLegs; ++leg) {
    // 17 significant digits carry the very doubles of the geometry.
    CHECK(vec3(m->body_pos + 3 * id(*m, mjOBJ_BODY, name(leg, "hip"))) == g.hip_offset[leg]);
    for (int j = 0; j < 3; ++j) {
      INFO("joint " << name(leg, kJointNames[j]));
      const int joint = id(*m, mjOBJ_JOINT, name(leg, kJointNames[j]));
      CHECK(m->jnt_qposadr[joint] == 7 + 3 * leg + j);
      CHECK(m->jnt_dofadr[joint] == 6 + 3 * leg + j);
      CHECK(m->jnt_limited[joint] == 1);
      CHECK(m->jnt_range[2 * joint] == g.q_min[leg][j]);
      CHECK(m->jnt_range[2 * joint + 1] == g.q_max[leg][j]);
      CHECK(m->dof_armature[6 + 3 * leg + j] == in.armature[j]);
      CHECK(m->dof_damping[6 + 3 * leg + j] == in.damping[j]);
      const int motor = id(*m, mjOBJ_ACTUATOR, name(leg, kJointNames[j]));
      CHECK(motor == 3 * leg + j);
      CHECK(m->actuator_trnid[2 * motor] == joint);
      CHECK(m->actuator_gear[6 * motor] == 1.0);
      CHECK(m->actuator_ctrllimited[motor] == 1);
      CHECK(m->actuator_ctrlrange[2 * motor] == -in.torque_limit[j]);
      CHECK(m->actuator_ctrlrange[2 * motor + 1] == in.torque_limit[j]);
    }
    const int foot = id(*m, mjOBJ_GEOM, name(leg, "foot"));
    CHECK(m->geom_type[foot] == mjGEOM_SPHERE);
    CHECK(m->geom_size[3 * foot] == g.foot_radius);
    CHECK(m->geom_friction[3 * foot] == o.foot_friction);
  }

  // Geom pair (a, b) can collide when contype_a & conaffinity_b or contype_b & conaffinity_a.
  const auto collides = [&](int a, int b) {
    return (m->geom_contype[a] & m->geom_conaffinity[b]) ||
           (m->geom_contype[b] & m->geom_conaffinity[a]);
  };
  const int ground = id(*m, mjOBJ_GEOM, "ground"), patch = id(*m, mjOBJ_GEOM, "patch");
  CHECK(m->geom_type[ground] == mjGEOM_PLANE);
  CHECK(m->geom_friction[3 * ground] == o.ground_friction);
  int robot_geoms = 0;
  for (int a = 0; a < m->ngeom; ++a) {
    if (m->geom_bodyid[a] == 0) continue;  // world geoms
    ++robot_geoms;
    INFO("geom " << mj_id2name(m.get(), mjOBJ_GEOM, a));
    CHECK(collides(a, ground));
    CHECK(collides(a, patch));
    for (int b = 0; b < m->ngeom; ++b) {
      if (b != a && m->geom_bodyid[b] != 0) CHECK_FALSE(collides(a, b));
    }
  }
  CHECK(robot_geoms == 1 + 3 * kNumLegs);  // trunk, then thigh, calf and foot of every leg
}

TEST_CASE("Bad options and bad geometry are errors naming the field", "[57.3][model][mujoco]") {
  const QuadrupedGeometry g = QuadrupedGeometry::go2();
  const QuadrupedInertia in = QuadrupedInertia::go2();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  CHECK(mjcfError(g, in, {}).empty());

  MjcfOptions o;
  o.ground_friction = -0.1;
  CHECK_THAT(mjcfError(g, in, o), Catch::Contains("options.ground_friction"));
  o = {};
  o.foot_friction = nan;
  CHECK_THAT(mjcfError(g, in, o), Catch::Contains("options.foot_friction"));
  o = {};
  o.timestep = 0.0;
  CHECK_THAT(mjcfError(g, in, o), Catch::Contains("options.timestep"));
  o = {};
  o.timestep = -1e-3;
  CHECK_THAT(mjcfError(g, in, o), Catch::Contains("options.timestep"));
  o = {};
  o.base_position.z() = inf;
  CHECK_THAT(mjcfError(g, in, o), Catch::Contains("options.base_position"));

  QuadrupedGeometry bad = g;
  bad.thigh_length = nan;
  CHECK_THAT(mjcfError(bad, in, {}), Catch::Contains("geometry.thigh_length"));
  bad = g;
  bad.hip_offset[RL].y() = inf;
  CHECK_THAT(mjcfError(bad, in, {}), Catch::Contains("geometry.hip_offset[RL]"));
  bad = g;
  bad.q_max[FR].z() = bad.q_min[FR].z() - 0.1;
  CHECK_THAT(mjcfError(bad, in, {}), Catch::Contains("geometry.q_min[FR]"));

  QuadrupedInertia heavy = in;
  heavy.calf[RR].mass = 0.0;
  CHECK_THAT(mjcfError(g, heavy, {}), Catch::Contains("inertia.calf[RR].mass"));
  heavy = in;
  heavy.trunk.inertia(0, 1) += 1e-3;
  CHECK_THAT(mjcfError(g, heavy, {}), Catch::Contains("inertia.trunk.inertia is not symmetric"));
  heavy = in;
  heavy.damping.y() = -1.0;
  CHECK_THAT(mjcfError(g, heavy, {}), Catch::Contains("inertia.damping[1]"));
}

TEST_CASE("loadMjcf reports MuJoCo's own message", "[57.3][model][mujoco]") {
  const auto message = [](const std::string& xml) -> std::string {
    try {
      loadMjcf(xml, "broken.xml");
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  };
  // Malformed XML: the parser's message.
  const std::string parse = message("<mujoco><worldbody><body></mujoco>");
  CHECK_THAT(parse, Catch::Contains("broken.xml") && Catch::Contains("XML parse error"));
  // Well-formed but invalid model: the compiler's message.
  const std::string compile =
      message("<mujoco><worldbody><geom type='sphere' size='-1'/></worldbody></mujoco>");
  CHECK_THAT(compile, Catch::Contains("sizes must be positive"));
  // An extra_worldbody that breaks the document fails in MuJoCo, not silently.
  MjcfOptions o;
  o.extra_worldbody = "<geom type='box'";
  CHECK_THAT(message(quadrupedMjcf(QuadrupedGeometry::go2(), QuadrupedInertia::go2(), o)),
             Catch::Contains("XML parse error"));
}
