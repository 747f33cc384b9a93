// The kit's quadruped in MuJoCo: the MJCF generated from model/'s data (quadrupedMjcf) against
// QuadrupedKinematics and QuadrupedInertia.
#include <mujoco/mujoco.h>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <random>

#include "model/mjcf.hpp"
#include "model/mujoco.hpp"
#include "model/quadruped.hpp"
#include "model/quadruped_inertia.hpp"

using namespace legkit::model;

TEST_CASE("FK agrees with MuJoCo's kinematics to 1e-9 m", "[57.3][model][mujoco]") {
  const QuadrupedKinematics kin;
  const QuadrupedGeometry& g = kin.geometry();
  const MjModelPtr m = loadMjcf(quadrupedMjcf(g, QuadrupedInertia::go2()));
  REQUIRE(m->nq == 7 + 3 * kNumLegs);
  const MjDataPtr d = makeData(*m);

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
      const int site =
          mj_name2id(m.get(), mjOBJ_SITE, (std::string(legName(leg)) + "_foot").c_str());
      REQUIRE(site >= 0);
      const Eigen::Vector3d x(d->site_xpos[3 * site], d->site_xpos[3 * site + 1],
                              d->site_xpos[3 * site + 2]);
      const Eigen::Vector3d ours = p + R * kin.footPosition(leg, q[leg]);
      worst = std::max(worst, (x - ours).norm());
      CHECK((x - ours).norm() < 1e-9);
    }
  }
  INFO("worst |MuJoCo - FK| over 20 random poses x 4 feet: " << worst << " m");
  CHECK(worst < 1e-9);
}

TEST_CASE("Go2 inertia: total mass and MuJoCo's total", "[57.3][model][mujoco]") {
  const QuadrupedInertia in = QuadrupedInertia::go2();
  CHECK(in.totalMass() == Approx(15.206408).margin(1e-12));
  const MjModelPtr m = loadMjcf(quadrupedMjcf(QuadrupedGeometry::go2(), in));
  CHECK(std::abs(mj_getTotalmass(m.get()) - in.totalMass()) < 1e-12);
}
