// Exercise 57.3.2: the trot's stacked leg-kinematic Jacobian and its null space, checked against
// the kit (estimation/leg_odometry/observability.hpp).
#include <Eigen/QR>
#include <catch2/catch.hpp>
#include <lie/so3.hpp>

#include "estimation/leg_odometry/observability.hpp"
#include "ex57_3_2.hpp"
#include "exercises/exercise_check.hpp"
#include "model/quadruped.hpp"

namespace lo = legkit::leg_odometry;

namespace {

struct Trot {
  Eigen::Vector3d p{0.4, 1.1, 0.3};
  Eigen::Matrix3d R = lie::SO3d::Exp(Eigen::Vector3d(-0.03, 0.05, -2.1)).matrix();
  Eigen::Vector3d v{0.8, -0.1, 0.02};
  Eigen::Matrix3Xd d;  // FL and RR on the ground
  Trot() : d(3, 2) {
    const legkit::model::QuadrupedKinematics kin;
    d.col(0) = p + R * kin.footPosition(legkit::model::FL, Eigen::Vector3d(0.05, 0.9, -1.6));
    d.col(1) = p + R * kin.footPosition(legkit::model::RR, Eigen::Vector3d(-0.05, 0.7, -1.4));
  }
};

// Largest distance of B's columns from the span of A's columns.
double spanDistance(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  const Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(A).householderQ() *
                            Eigen::MatrixXd::Identity(A.rows(), A.cols());
  return (B - Q * (Q.transpose() * B)).cwiseAbs().maxCoeff();
}

}  // namespace

TEST_CASE("57.3.2 the stacked Jacobian equals the kit's", "[ex57.3.2][hint 1]") {
  const Trot s;
  for (bool with_gravity : {false, true}) {
    const Eigen::MatrixXd mine = ex57_3_2::stackedJacobian(s.p, s.R, s.v, s.d, with_gravity);
    const Eigen::MatrixXd kit = lo::legKinematicsJacobian(s.p, s.R, s.v, s.d, with_gravity);
    INFO("with_gravity = " << with_gravity);
    REQUIRE_NEAR(mine, kit, 1e-14);
  }
}

TEST_CASE("57.3.2 null space in trot: 4 directions, translations and yaw", "[ex57.3.2][hint 2]") {
  const Trot s;
  const Eigen::MatrixXd H = lo::legKinematicsJacobian(s.p, s.R, s.v, s.d, true);
  const ex57_3_2::NullSpace mine = ex57_3_2::nullSpace(H);
  REQUIRE(mine.dimension == lo::nullSpaceDimension(H));
  REQUIRE(mine.dimension == 4);
  REQUIRE(mine.basis.cols() == 4);
  REQUIRE_NEAR(mine.basis.transpose() * mine.basis, Eigen::Matrix4d::Identity(), 1e-12);
  const Eigen::MatrixXd U = lo::unobservableDirections(s.p, s.v, s.d);
  REQUIRE_BELOW(spanDistance(U, mine.basis), 1e-9);
  REQUIRE_BELOW(spanDistance(mine.basis, U), 1e-9);
}

TEST_CASE("57.3.2 your Jacobian's null space: 6 with the legs alone, 4 with gravity",
          "[ex57.3.2][hint 1]") {
  const Trot s;
  const ex57_3_2::NullSpace legs =
      ex57_3_2::nullSpace(ex57_3_2::stackedJacobian(s.p, s.R, s.v, s.d, false));
  const ex57_3_2::NullSpace with_g =
      ex57_3_2::nullSpace(ex57_3_2::stackedJacobian(s.p, s.R, s.v, s.d, true));
  REQUIRE(legs.dimension == 6);
  REQUIRE(with_g.dimension == 4);
  // Tipping the base about the stance diagonal (footholds fixed) is in the legs-only null space
  // but not in the one with gravity.
  const Eigen::Vector3d u = (s.d.col(1) - s.d.col(0)).normalized();
  Eigen::VectorXd tip = Eigen::VectorXd::Zero(15);
  tip.segment<3>(0) = u.cross(s.p - s.d.col(0));
  tip.segment<3>(3) = u;
  tip.segment<3>(6) = u.cross(s.v);
  REQUIRE_BELOW(spanDistance(legs.basis, tip), 1e-9);
  REQUIRE_ABOVE(spanDistance(with_g.basis, tip), 0.1);
}
