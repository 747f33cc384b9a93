#include "model/mjcf.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <locale>
#include <sstream>
#include <stdexcept>
#include <string>

namespace legkit::model {
namespace {

// Collision shapes of the links (primitives in the spirit of the Go2's public collision model):
// the trunk box's full size, the thigh and calf capsules' radii [m]. The calf capsule ends at the
// foot sphere's centre, so with a radius below foot_radius the sphere always touches flat ground
// first.
const Eigen::Vector3d kTrunkSize(0.38, 0.09, 0.11);
constexpr double kThighRadius = 0.02;
constexpr double kCalfRadius = 0.012;

// Contact bits: robot geoms have contype 2 and conaffinity 1, world geoms keep MuJoCo's default
// 1 / 1, so a robot geom meets a world geom (1 & 1) but never another robot geom (2 & 1 = 0).
constexpr int kRobotContype = 2;
constexpr int kRobotConaffinity = 1;

[[noreturn]] void bad(const std::string& what) {
  throw std::invalid_argument("quadrupedMjcf: " + what);
}

void requireFinite(double x, const std::string& name) {
  if (!std::isfinite(x)) bad(name + " is not finite");
}

void requirePositive(double x, const std::string& name) {
  requireFinite(x, name);
  if (x <= 0.0) bad(name + " must be positive (got " + std::to_string(x) + ")");
}

void requireNonNegative(double x, const std::string& name) {
  requireFinite(x, name);
  if (x < 0.0) bad(name + " must not be negative (got " + std::to_string(x) + ")");
}

void requireFinite(const Eigen::Vector3d& x, const std::string& name) {
  if (!x.allFinite()) bad(name + " is not finite");
}

void requireNonNegative(const Eigen::Vector3d& x, const std::string& name) {
  for (int k = 0; k < 3; ++k) requireNonNegative(x[k], name + "[" + std::to_string(k) + "]");
}

void checkOptions(const MjcfOptions& o) {
  requirePositive(o.timestep, "options.timestep");
  requireNonNegative(o.gravity, "options.gravity");
  requireNonNegative(o.ground_friction, "options.ground_friction");
  requireNonNegative(o.foot_friction, "options.foot_friction");
  requireFinite(o.base_position, "options.base_position");
}

void checkGeometry(const QuadrupedGeometry& g) {
  requirePositive(g.thigh_length, "geometry.thigh_length");
  requirePositive(g.calf_length, "geometry.calf_length");
  requirePositive(g.foot_radius, "geometry.foot_radius");
  requireNonNegative(g.abduction_offset, "geometry.abduction_offset");
  if (g.foot_radius <= kCalfRadius) {
    bad("geometry.foot_radius must exceed the calf capsule radius " + std::to_string(kCalfRadius));
  }
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const std::string n = legName(leg);
    const std::string q_min = "geometry.q_min[" + n + "]", q_max = "geometry.q_max[" + n + "]";
    requireFinite(g.hip_offset[leg], "geometry.hip_offset[" + n + "]");
    requireFinite(g.q_min[leg], q_min);
    requireFinite(g.q_max[leg], q_max);
    if ((g.q_min[leg].array() > g.q_max[leg].array()).any()) {
      bad(std::string(q_min).append(" exceeds ").append(q_max));
    }
  }
}

void checkLink(const LinkInertia& link, const std::string& name) {
  requirePositive(link.mass, name + ".mass");
  requireFinite(link.com, name + ".com");
  if (!link.inertia.allFinite()) bad(name + ".inertia is not finite");
  // An inertia tensor is symmetric and positive definite (MuJoCo checks the triangle inequality).
  if (!(link.inertia - link.inertia.transpose()).isZero(1e-12 * link.inertia.norm())) {
    bad(name + ".inertia is not symmetric");
  }
  if (!(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(link.inertia).eigenvalues().array() > 0.0)
           .all()) {
    bad(name + ".inertia is not positive definite");
  }
}

void checkInertia(const QuadrupedInertia& in) {
  checkLink(in.trunk, "inertia.trunk");
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const std::string n = legName(leg);
    checkLink(in.hip[leg], "inertia.hip[" + n + "]");
    checkLink(in.thigh[leg], "inertia.thigh[" + n + "]");
    checkLink(in.calf[leg], "inertia.calf[" + n + "]");
  }
  requireNonNegative(in.torque_limit, "inertia.torque_limit");
  requireNonNegative(in.armature, "inertia.armature");
  requireNonNegative(in.damping, "inertia.damping");
}

// A stream that writes doubles with 17 significant digits (round trip) and a '.' decimal point.
std::ostringstream exactStream() {
  std::ostringstream s;
  s.imbue(std::locale::classic());
  s.precision(17);
  return s;
}

std::string vec(double x, double y, double z) {
  std::ostringstream s = exactStream();
  s << x << ' ' << y << ' ' << z;
  return s.str();
}

std::string vec(const Eigen::Vector3d& v) {
  return vec(v.x(), v.y(), v.z());
}

// <inertial> in principal form: the centre of mass, the principal moments (diaginertia) and the
// rotation from the principal axes to the link frame (quat, w x y z). Eigen's symmetric eigensolver
// is exact to rounding; MJCF's fullinertia would instead go through MuJoCo's own iterative
// diagonalisation, whose axes leave the inertia ~1e-6 (relative) off the one given.
std::string inertial(const LinkInertia& link) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(link.inertia);
  Eigen::Matrix3d axes = eig.eigenvectors();
  if (axes.determinant() < 0.0) axes.col(2) = -axes.col(2);  // a rotation, not a reflection
  const Eigen::Quaterniond q(axes);
  std::ostringstream s = exactStream();
  s << "<inertial pos='" << vec(link.com) << "' mass='" << link.mass << "' quat='" << q.w() << ' '
    << q.x() << ' ' << q.y() << ' ' << q.z() << "' diaginertia='" << vec(eig.eigenvalues())
    << "'/>";
  return s.str();
}

constexpr const char* kJointNames[3] = {"abduction", "hip", "knee"};

}  // namespace

std::string quadrupedMjcf(const QuadrupedGeometry& g, const QuadrupedInertia& in,
                          const MjcfOptions& o) {
  checkOptions(o);
  checkGeometry(g);
  checkInertia(in);

  std::ostringstream s = exactStream();
  s << "<mujoco model='legkit_quadruped'>\n"
    << "  <compiler angle='radian' inertiafromgeom='false'/>\n"
    << "  <option timestep='" << o.timestep << "' gravity='" << vec(0.0, 0.0, -o.gravity)
    << "' integrator='Euler' solver='Newton' cone='elliptic' impratio='10'/>\n"
    << "  <default>\n"
    << "    <default class='robot'>\n"
    << "      <geom contype='" << kRobotContype << "' conaffinity='" << kRobotConaffinity
    << "' friction='" << o.foot_friction << " 0.005 0.0001'/>\n"
    << "    </default>\n"
    << "  </default>\n"
    << "  <worldbody>\n"
    << "    <geom name='ground' type='plane' size='0 0 1' friction='" << o.ground_friction
    << " 0.005 0.0001'/>\n"
    << o.extra_worldbody << "\n"
    << "    <body name='base' pos='" << vec(o.base_position) << "' childclass='robot'>\n"
    << "      <freejoint name='base'/>\n"
    << "      " << inertial(in.trunk) << "\n"
    << "      <geom name='trunk' type='box' size='" << vec(0.5 * kTrunkSize) << "'/>\n"
    << "      <site name='imu' pos='0 0 0'/>\n";
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const std::string n = legName(leg);
    // One hinge per joint j: axis x for the abduction, y for hip and knee (quadruped.hpp).
    const auto joint = [&](int j, const char* axis) {
      std::ostringstream js = exactStream();
      js << "<joint name='" << n << '_' << kJointNames[j] << "' type='hinge' axis='" << axis
         << "' limited='true' range='" << g.q_min[leg][j] << ' ' << g.q_max[leg][j]
         << "' armature='" << in.armature[j] << "' damping='" << in.damping[j] << "'/>";
      return js.str();
    };
    s << "      <body name='" << n << "_hip' pos='" << vec(g.hip_offset[leg]) << "'>\n"
      << "        " << inertial(in.hip[leg]) << "\n"
      << "        " << joint(0, "1 0 0") << "\n"
      << "        <body name='" << n << "_thigh' pos='"
      << vec(0.0, lateralSign(leg) * g.abduction_offset, 0.0) << "'>\n"
      << "          " << inertial(in.thigh[leg]) << "\n"
      << "          " << joint(1, "0 1 0") << "\n"
      << "          <geom name='" << n << "_thigh' type='capsule' size='" << kThighRadius
      << "' fromto='0 0 0 " << vec(0.0, 0.0, -g.thigh_length) << "'/>\n"
      << "          <body name='" << n << "_calf' pos='" << vec(0.0, 0.0, -g.thigh_length) << "'>\n"
      << "            " << inertial(in.calf[leg]) << "\n"
      << "            " << joint(2, "0 1 0") << "\n"
      << "            <geom name='" << n << "_calf' type='capsule' size='" << kCalfRadius
      << "' fromto='0 0 0 " << vec(0.0, 0.0, -g.calf_length) << "'/>\n"
      << "            <geom name='" << n << "_foot' type='sphere' size='" << g.foot_radius
      << "' pos='" << vec(0.0, 0.0, -g.calf_length) << "'/>\n"
      << "            <site name='" << n << "_foot' pos='" << vec(0.0, 0.0, -g.calf_length)
      << "'/>\n"
      << "          </body>\n"
      << "        </body>\n"
      << "      </body>\n";
  }
  s << "    </body>\n"
    << "  </worldbody>\n"
    << "  <actuator>\n";
  for (int leg = 0; leg < kNumLegs; ++leg) {
    for (int j = 0; j < 3; ++j) {
      const std::string name = std::string(legName(leg)) + '_' + kJointNames[j];
      s << "    <motor name='" << name << "' joint='" << name
        << "' gear='1' ctrllimited='true' ctrlrange='" << -in.torque_limit[j] << ' '
        << in.torque_limit[j] << "'/>\n";
    }
  }
  s << "  </actuator>\n"
    << "</mujoco>\n";
  return s.str();
}

}  // namespace legkit::model
