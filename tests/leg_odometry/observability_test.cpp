// Section 57.3 observability: the stacked leg-kinematic Jacobian has a 4-dimensional null space
// (3 translations + yaw) in stand and in trot once gravity pins roll and pitch; 6 without it.
#include <Eigen/QR>
#include <catch2/catch.hpp>
#include <lie/so3.hpp>
#include <limits>

#include "estimation/leg_odometry/observability.hpp"
#include "model/quadruped.hpp"

namespace lo = legkit::leg_odometry;
using legkit::model::QuadrupedKinematics;

namespace {

struct Scene {
  Eigen::Vector3d p = Eigen::Vector3d(0.7, -0.4, 0.31);
  Eigen::Matrix3d R = lie::SO3d::Exp(Eigen::Vector3d(0.04, -0.06, 0.9)).matrix();
  Eigen::Vector3d v = Eigen::Vector3d(0.6, 0.2, -0.03);

  // World positions of the listed stance feet under the standing posture.
  Eigen::Matrix3Xd feet(std::initializer_list<int> legs) const {
    const QuadrupedKinematics kin;
    Eigen::Matrix3Xd d(3, static_cast<Eigen::Index>(legs.size()));
    int i = 0;
    for (int leg : legs) d.col(i++) = p + R * kin.footPosition(leg, Eigen::Vector3d(0, 0.8, -1.5));
    return d;
  }
};

// Largest distance of the columns of B from the span of A (both with orthonormalised columns).
double spanDistance(const lo::StateDirections& A, const lo::StateDirections& B) {
  const Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(A).householderQ() *
                            Eigen::MatrixXd::Identity(A.rows(), A.cols());
  return (B - Q * (Q.transpose() * B)).cwiseAbs().maxCoeff();
}

void checkTranslationsAndYaw(const Scene& s, const Eigen::Matrix3Xd& d, int feet) {
  const lo::ObservabilityJacobian H = lo::legKinematicsJacobian(s.p, s.R, s.v, d, true);
  CHECK(H.cols() == 9 + 3 * feet);
  const lo::NullSpace N = lo::nullSpace(H);
  CHECK(N.dimension == 4);
  CHECK(lo::nullSpaceDimension(H) == 4);
  const lo::StateDirections U = lo::unobservableDirections(s.p, s.v, d);
  // The analytic directions are in the null space, and the computed basis is exactly their span.
  CHECK((H * U).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(spanDistance(U, N.basis) < 1e-9);
  CHECK(spanDistance(N.basis, U) < 1e-9);
  // Yaw alone (without the translations that accompany it) is the direction
  // dtheta = e_z, dp = e_z x p, dv = e_z x v, dd_i = e_z x d_i: check its attitude part.
  CHECK((U.block(3, 3, 3, 1) - Eigen::Vector3d::UnitZ()).norm() == 0.0);
}

}  // namespace

TEST_CASE("stand (4 feet): null space = 3 translations + yaw", "[57.3][observability]") {
  const Scene s;
  checkTranslationsAndYaw(s, s.feet({0, 1, 2, 3}), 4);
}

TEST_CASE("trot (2 diagonal feet): null space = 3 translations + yaw", "[57.3][observability]") {
  const Scene s;
  checkTranslationsAndYaw(s, s.feet({legkit::model::FL, legkit::model::RR}), 2);
  checkTranslationsAndYaw(s, s.feet({legkit::model::FR, legkit::model::RL}), 2);
}

TEST_CASE("one foot, and the legs without gravity", "[57.3][observability]") {
  const Scene s;
  CHECK(lo::nullSpaceDimension(lo::legKinematicsJacobian(s.p, s.R, s.v, s.feet({1}), true)) == 4);
  // Legs alone cannot tell any rigid rotation of the whole scene: 3 translations + 3 rotations.
  for (const Eigen::Matrix3Xd& d : {s.feet({0, 1, 2, 3}), s.feet({0, 3}), s.feet({2})}) {
    CHECK(lo::nullSpaceDimension(lo::legKinematicsJacobian(s.p, s.R, s.v, d, false)) == 6);
  }
}

TEST_CASE("trot: rotating about the stance diagonal is seen through gravity only",
          "[57.3][observability]") {
  const Scene s;
  const Eigen::Matrix3Xd d = s.feet({legkit::model::FL, legkit::model::RR});
  // Tip the base about the line through both stance feet, footholds fixed: every leg
  // measurement stays the same to first order, so only the gravity rows notice it.
  const Eigen::Vector3d u = (d.col(1) - d.col(0)).normalized();
  Eigen::Matrix<double, 15, 1> x = Eigen::Matrix<double, 15, 1>::Zero();
  x.segment<3>(0) = u.cross(s.p - d.col(0));
  x.segment<3>(3) = u;
  x.segment<3>(6) = u.cross(s.v);
  const lo::ObservabilityJacobian legs = lo::legKinematicsJacobian(s.p, s.R, s.v, d, false);
  const lo::ObservabilityJacobian with_g = lo::legKinematicsJacobian(s.p, s.R, s.v, d, true);
  CHECK((legs * x).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((with_g * x).norm() > 0.5);  // the diagonal is nearly horizontal: gravity sees the tilt
}

TEST_CASE("observability: bad input is rejected", "[57.3][observability]") {
  const Scene s;
  using Catch::Matchers::Contains;
  CHECK_THROWS_WITH(lo::legKinematicsJacobian(s.p, s.R, s.v, Eigen::Matrix3Xd(3, 0), true),
                    Contains("stance feet"));
  CHECK_THROWS_WITH(lo::legKinematicsJacobian(s.p, s.R, s.v, Eigen::Matrix3Xd::Zero(3, 9), true),
                    Contains("got 9"));
  Eigen::Matrix3Xd d = s.feet({0, 1});
  d(2, 1) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(lo::legKinematicsJacobian(s.p, s.R, s.v, d, true), Contains("not finite"));
  CHECK_THROWS_AS(lo::nullSpace(lo::ObservabilityJacobian()), std::invalid_argument);
}
