// Exercise 57.3.1: the FR foot's explicit base-velocity expression, checked against the kit's
// kinematics (model/quadruped.hpp) and leg odometry (estimation/leg_odometry/base_velocity.hpp).
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <lie/so3.hpp>
#include <random>

#include "estimation/leg_odometry/base_velocity.hpp"
#include "ex57_3_1.hpp"
#include "exercises/exercise_check.hpp"
#include "model/quadruped.hpp"

namespace {

using legkit::model::FR;

struct Draw {
  std::mt19937 gen;
  explicit Draw(unsigned seed) : gen(seed) {}
  // Joint angles within the FR leg's limits.
  Eigen::Vector3d q(const legkit::model::QuadrupedGeometry& g) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    return g.q_min[FR] +
           (g.q_max[FR] - g.q_min[FR]).cwiseProduct(Eigen::Vector3d(u(gen), u(gen), u(gen)));
  }
  Eigen::Vector3d vec(double scale) {
    std::normal_distribution<double> n(0.0, scale);
    return {n(gen), n(gen), n(gen)};
  }
};

}  // namespace

TEST_CASE("57.3.1 FR foot position equals the kit's FK", "[ex57.3.1][hint 1]") {
  const legkit::model::QuadrupedKinematics kin;
  Draw draw(31);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d q = draw.q(kin.geometry());
    REQUIRE_NEAR(ex57_3_1::frFootPosition(q), kin.footPosition(FR, q), 1e-12);
  }
}

TEST_CASE("57.3.1 FR foot Jacobian equals the kit's analytic Jacobian", "[ex57.3.1][hint 2]") {
  const legkit::model::QuadrupedKinematics kin;
  Draw draw(32);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d q = draw.q(kin.geometry());
    REQUIRE_NEAR(ex57_3_1::frFootJacobian(q), kin.footJacobian(FR, q), 1e-12);
  }
}

TEST_CASE("57.3.1 explicit base velocity equals the kit's leg odometry", "[ex57.3.1][hint 3]") {
  const legkit::model::QuadrupedKinematics kin;
  Draw draw(33);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d q = draw.q(kin.geometry()), dq = draw.vec(3.0), w = draw.vec(1.0);
    const Eigen::Matrix3d R = lie::SO3d::Exp(draw.vec(1.0)).matrix();
    const Eigen::Vector3d kit = legkit::leg_odometry::baseVelocityFromFoot(
        R, w, kin.footPosition(FR, q), kin.footJacobian(FR, q) * dq);
    const Eigen::Vector3d v_b = ex57_3_1::frBaseVelocityBody(w, q, dq);
    REQUIRE_NEAR(R * v_b, kit, 1e-11);
  }
}

TEST_CASE("57.3.1 turning in place over a fixed FR foot gives zero base velocity",
          "[ex57.3.1][hint 3]") {
  const legkit::model::QuadrupedKinematics kin;
  Draw draw(34);
  for (int i = 0; i < 50; ++i) {
    // Standing posture, random body rate; the joint rates that keep the foot still in the world
    // satisfy J dq = -w x r.
    const Eigen::Vector3d q(0.05, 0.8, -1.5), w = draw.vec(1.0);
    const Eigen::Vector3d r = kin.footPosition(FR, q);
    const Eigen::Vector3d dq = kin.footJacobian(FR, q).lu().solve(-w.cross(r));
    REQUIRE_NEAR(ex57_3_1::frBaseVelocityBody(w, q, dq), Eigen::Vector3d::Zero(), 1e-12);
  }
}
