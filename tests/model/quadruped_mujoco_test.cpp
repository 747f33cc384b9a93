// FK of QuadrupedKinematics against MuJoCo's own kinematics on a model of the same robot built
// from primitives (floating base, three hinges per leg, a site at the foot-sphere centre).
#include <mujoco/mujoco.h>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cstring>
#include <memory>
#include <random>
#include <sstream>
#include <string>

#include "model/quadruped.hpp"

using legkit::model::kNumLegs;
using legkit::model::QuadrupedGeometry;
using legkit::model::QuadrupedKinematics;

namespace {

std::string vec(double x, double y, double z) {
  std::ostringstream s;
  s.precision(17);
  s << x << " " << y << " " << z;
  return s.str();
}

// MJCF of the robot: hinge axes are abduction about x, hip and knee about y, as in quadruped.hpp.
std::string mjcf(const QuadrupedGeometry& g) {
  std::ostringstream s;
  s << "<mujoco model='legkit_quadruped'>\n"
       "  <compiler angle='radian'/>\n"
       "  <worldbody>\n"
       "    <body name='base'>\n"
       "      <freejoint/>\n"
       "      <geom type='box' size='0.19 0.05 0.05' mass='6'/>\n";
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const std::string n = legkit::model::legName(leg);
    const Eigen::Vector3d& h = g.hip_offset[leg];
    const double y0 = legkit::model::lateralSign(leg) * g.abduction_offset;
    s << "      <body name='" << n << "_hip' pos='" << vec(h.x(), h.y(), h.z()) << "'>\n"
      << "        <joint name='" << n << "_abduction' type='hinge' axis='1 0 0'/>\n"
      << "        <geom type='sphere' size='0.03' mass='0.5'/>\n"
      << "        <body name='" << n << "_thigh' pos='" << vec(0, y0, 0) << "'>\n"
      << "          <joint name='" << n << "_hip' type='hinge' axis='0 1 0'/>\n"
      << "          <geom type='capsule' fromto='0 0 0 0 0 " << -g.thigh_length
      << "' size='0.02' mass='1'/>\n"
      << "          <body name='" << n << "_calf' pos='" << vec(0, 0, -g.thigh_length) << "'>\n"
      << "            <joint name='" << n << "_knee' type='hinge' axis='0 1 0'/>\n"
      << "            <geom type='capsule' fromto='0 0 0 0 0 " << -g.calf_length
      << "' size='0.015' mass='0.2'/>\n"
      << "            <site name='" << n << "_foot' pos='" << vec(0, 0, -g.calf_length)
      << "' size='" << g.foot_radius << "'/>\n"
      << "          </body>\n"
      << "        </body>\n"
      << "      </body>\n";
  }
  s << "    </body>\n  </worldbody>\n</mujoco>\n";
  return s.str();
}

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
struct VfsDeleter {
  void operator()(mjVFS* v) const {
    mj_deleteVFS(v);
    delete v;
  }
};

std::unique_ptr<mjModel, ModelDeleter> loadFromString(const std::string& xml) {
  std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);
  mj_defaultVFS(vfs.get());
  const char* name = "legkit_quadruped.xml";
  REQUIRE(mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) == 0);
  const int i = mj_findFileVFS(vfs.get(), name);
  REQUIRE(i >= 0);
  std::memcpy(vfs->filedata[i], xml.data(), xml.size());
  char error[1000] = "";
  std::unique_ptr<mjModel, ModelDeleter> m(mj_loadXML(name, vfs.get(), error, sizeof(error)));
  INFO("MuJoCo: " << error);
  REQUIRE(m != nullptr);
  return m;
}

}  // namespace

TEST_CASE("FK agrees with MuJoCo's kinematics to 1e-9 m", "[57.3][model][mujoco]") {
  const QuadrupedKinematics kin;
  const QuadrupedGeometry& g = kin.geometry();
  const auto m = loadFromString(mjcf(g));
  REQUIRE(m->nq == 7 + 3 * kNumLegs);
  REQUIRE(m->nsite == kNumLegs);
  std::unique_ptr<mjData, DataDeleter> d(mj_makeData(m.get()));

  std::mt19937 gen(573);
  std::uniform_real_distribution<double> unit(0.0, 1.0), pos(-2.0, 2.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  double worst = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector3d p(pos(gen), pos(gen), pos(gen));
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
    const Eigen::Matrix3d R = quat.toRotationMatrix();
    for (int leg = 0; leg < kNumLegs; ++leg) {
      const Eigen::Vector3d site(d->site_xpos[3 * leg], d->site_xpos[3 * leg + 1],
                                 d->site_xpos[3 * leg + 2]);
      const Eigen::Vector3d ours = p + R * kin.footPosition(leg, q[leg]);
      worst = std::max(worst, (site - ours).norm());
      CHECK((site - ours).norm() < 1e-9);
    }
  }
  // Shown with -s: the measured agreement the chapter quotes.
  INFO("worst |MuJoCo - FK| over 20 random poses x 4 feet: " << worst << " m");
  CHECK(worst < 1e-9);
}
