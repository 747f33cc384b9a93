// Section 57.3 leg odometry: base velocity from each stance foot against an analytic truth, the
// chapter's turn-in-place self check, multi-foot fusion, position observations and bad input.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "estimation/leg_odometry/base_velocity.hpp"
#include "estimation/leg_odometry/position_observation.hpp"
#include "estimation/leg_odometry/velocity_fusion.hpp"
#include "leg_odometry/stance_motion.hpp"

namespace lo = legkit::leg_odometry;
using legkit::ContactMeasurement;
using legkit::model::kNumLegs;
using legkit::model::QuadrupedKinematics;
using legkit::test::StanceMotion;

namespace {

std::vector<ContactMeasurement> allContacts(const StanceMotion& m, const QuadrupedKinematics& kin,
                                            double t) {
  std::vector<ContactMeasurement> c;
  for (int leg = 0; leg < kNumLegs; ++leg) c.push_back(m.contact(kin, leg, t));
  return c;
}

}  // namespace

TEST_CASE("turn in place: pure rotation gives zero linear velocity from every foot",
          "[57.3][leg_odometry]") {
  const QuadrupedKinematics kin;
  StanceMotion m = StanceMotion::standing(kin);
  m.w_b = Eigen::Vector3d(0.1, -0.08, 0.8);  // mostly yaw, with some roll and pitch
  double worst = 0.0, worst_wrong_frame = 0.0;
  for (double t = 0.0; t <= 0.3; t += 0.01) {
    const Eigen::Matrix3d R = m.R(t);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      const Eigen::Vector3d q = m.q(kin, leg, t), qdot = m.qdot(kin, leg, t);
      const Eigen::Vector3d r = kin.footPosition(leg, q);
      const Eigen::Vector3d r_dot = kin.footJacobian(leg, q) * qdot;
      const Eigen::Vector3d v = lo::baseVelocityFromFoot(R, m.w_b, r, r_dot);
      worst = std::max(worst, v.norm());
      // The pitfall: the body-frame foot velocity used as if it were a world-frame one.
      const Eigen::Vector3d v_wrong = -(R * m.w_b.cross(r) + r_dot);
      worst_wrong_frame = std::max(worst_wrong_frame, v_wrong.norm());
    }
  }
  INFO("turn in place: worst |v| " << worst << " m/s; with the Jacobian's frame mixed up "
                                   << worst_wrong_frame << " m/s");
  CHECK(worst < 1e-8);
  CHECK(worst_wrong_frame > 1e-2);
}

TEST_CASE("each stance foot gives the analytic base velocity", "[57.3][leg_odometry]") {
  const QuadrupedKinematics kin;
  StanceMotion m = StanceMotion::standing(kin);
  m.R0 = lie::SO3d::Exp(Eigen::Vector3d(0.05, -0.1, 0.7)).matrix();
  for (int leg = 0; leg < kNumLegs; ++leg) {
    m.d[leg] = m.p0 + m.R0 * kin.footPosition(leg, Eigen::Vector3d(0.0, 0.8, -1.5));
  }
  m.v0 = Eigen::Vector3d(0.3, -0.1, 0.05);
  m.a = Eigen::Vector3d(-0.4, 0.2, -0.1);
  m.w_b = Eigen::Vector3d(-0.2, 0.15, 0.5);
  double worst = 0.0;
  for (double t = 0.0; t <= 0.2; t += 0.02) {
    for (int leg = 0; leg < kNumLegs; ++leg) {
      const ContactMeasurement c = m.contact(kin, leg, t);
      const Eigen::Vector3d v = lo::baseVelocityFromFoot(m.R(t), m.w_b, c);
      worst = std::max(worst, (v - m.v(t)).norm());
    }
  }
  INFO("worst |v_foot - v_true| over 4 feet x 11 instants: " << worst << " m/s");
  CHECK(worst < 1e-8);
}

TEST_CASE("world-frame and body-frame forms of the rotation term agree", "[57.3][leg_odometry]") {
  // -R (w_b x r + r_dot) = -(w x (R r) + R r_dot) with w = R w_b (the chapter's form).
  const Eigen::Matrix3d R = lie::SO3d::Exp(Eigen::Vector3d(0.3, -1.2, 2.0)).matrix();
  const Eigen::Vector3d w_b(0.4, -0.3, 1.1), r(0.2, -0.14, -0.3), r_dot(0.05, 0.3, -0.2);
  const Eigen::Vector3d chapter = -((R * w_b).cross(R * r) + R * r_dot);
  CHECK((lo::baseVelocityFromFoot(R, w_b, r, r_dot) - chapter).norm() < 1e-14);
}

TEST_CASE("fusion: mean, force-weighted mean and stacked measurements", "[57.3][leg_odometry]") {
  const QuadrupedKinematics kin;
  StanceMotion m = StanceMotion::standing(kin);
  m.v0 = Eigen::Vector3d(0.5, 0.1, 0.0);
  m.w_b = Eigen::Vector3d(0.0, 0.0, 0.6);
  const double t = 0.1;
  const Eigen::Matrix3d R = m.R(t);
  std::vector<ContactMeasurement> c = allContacts(m, kin, t);

  SECTION("consistent feet: every variant returns the truth") {
    CHECK((lo::meanVelocity(R, m.w_b, c) - m.v(t)).norm() < 1e-8);
    CHECK(
        (lo::forceWeightedVelocity(R, m.w_b, c, Eigen::Vector4d(40, 30, 20, 10)) - m.v(t)).norm() <
        1e-8);
    const lo::StackedVelocityMeasurement z = lo::stackVelocityMeasurements(R, m.w_b, c, {});
    CHECK(z.feet() == 4);
    CHECK(z.z.size() == 12);
    CHECK(z.residual(m.v(t)).norm() < 1e-8);
    CHECK((lo::fuseStacked(z).v - m.v(t)).norm() < 1e-8);
  }

  SECTION("a slipping foot: each variant weighs it as documented") {
    // RR slips: its foot velocity relative to the body is off by 0.2 m/s along body x, so its
    // own estimate of v is off by -R (0.2, 0, 0).
    const Eigen::Vector3d slip = -R * Eigen::Vector3d(0.2, 0.0, 0.0);
    *c[3].v_body += Eigen::Vector3d(0.2, 0.0, 0.0);
    CHECK((lo::meanVelocity(R, m.w_b, c) - (m.v(t) + slip / 4.0)).norm() < 1e-8);
    // Force weights 30, 30, 30, 10: the light foot moves the estimate by a tenth of its error.
    CHECK((lo::forceWeightedVelocity(R, m.w_b, c, Eigen::Vector4d(30, 30, 30, 10)) -
           (m.v(t) + slip / 10.0))
              .norm() < 1e-8);
    // An unloaded foot (zero or a slightly negative reading) does not count at all.
    CHECK((lo::forceWeightedVelocity(R, m.w_b, c, Eigen::Vector4d(30, 30, 30, -0.5)) - m.v(t))
              .norm() < 1e-8);
    // Stacked: the slipping foot declared 100x noisier in r_dot pulls far less than in the mean.
    lo::FootVelocityNoise noise;
    lo::StackedVelocityMeasurement z = lo::stackVelocityMeasurements(R, m.w_b, c, noise);
    CHECK(z.residual(m.v(t)).segment<3>(9).isApprox(slip, 1e-6));
    CHECK(z.residual(m.v(t)).head<9>().norm() < 1e-8);
    const Eigen::Matrix3d Rn_slip = z.Rn.block<3, 3>(9, 9);
    z.Rn.block<3, 3>(9, 9) = 100.0 * Rn_slip;
    const lo::FusedVelocity fused = lo::fuseStacked(z);
    CHECK((fused.v - m.v(t)).norm() < 0.05 * (slip / 4.0).norm());
    CHECK(fused.P.isApprox(fused.P.transpose(), 1e-12));
  }

  SECTION("stacked fusion with equal covariances is the mean with covariance Sigma / k") {
    std::vector<ContactMeasurement> same = c;
    for (ContactMeasurement& x : same) x.p_body = c[0].p_body, x.v_body = c[0].v_body;
    const lo::StackedVelocityMeasurement z = lo::stackVelocityMeasurements(R, m.w_b, same, {});
    const lo::FusedVelocity fused = lo::fuseStacked(z);
    CHECK((fused.v - lo::meanVelocity(R, m.w_b, same)).norm() < 1e-12);
    CHECK(fused.P.isApprox(z.Rn.block<3, 3>(0, 0) / 4.0, 1e-9));
  }
}

TEST_CASE("velocity covariance matches the linearisation of v(w_b, r, r_dot)",
          "[57.3][leg_odometry]") {
  const Eigen::Matrix3d R = lie::SO3d::Exp(Eigen::Vector3d(0.2, 0.4, -0.9)).matrix();
  const Eigen::Vector3d w_b(0.3, -0.5, 1.2), r(0.19, -0.13, -0.3), r_dot(0.1, -0.2, 0.05);
  lo::FootVelocityNoise noise;
  noise.gyro_cov = Eigen::Vector3d(1e-4, 2e-4, 3e-4).asDiagonal();
  noise.r_dot_cov = Eigen::Vector3d(4e-4, 1e-4, 2e-4).asDiagonal();
  const Eigen::Matrix3d r_cov = Eigen::Vector3d(1e-6, 3e-6, 2e-6).asDiagonal();
  // Numerical Jacobians of v with respect to each input (v is linear in each, so exact).
  Eigen::Matrix3d J_w, J_r, J_rd;
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(j);
    const Eigen::Vector3d v0 = lo::baseVelocityFromFoot(R, w_b, r, r_dot);
    J_w.col(j) = lo::baseVelocityFromFoot(R, w_b + e, r, r_dot) - v0;
    J_r.col(j) = lo::baseVelocityFromFoot(R, w_b, r + e, r_dot) - v0;
    J_rd.col(j) = lo::baseVelocityFromFoot(R, w_b, r, r_dot + e) - v0;
  }
  const Eigen::Matrix3d expected = J_w * noise.gyro_cov * J_w.transpose() +
                                   J_r * r_cov * J_r.transpose() +
                                   J_rd * noise.r_dot_cov * J_rd.transpose();
  CHECK(lo::baseVelocityCovariance(R, w_b, r, r_cov, noise).isApprox(expected, 1e-10));
}

TEST_CASE("position observations: base from a foothold, foot height, filter Jacobians",
          "[57.3][leg_odometry]") {
  const QuadrupedKinematics kin;
  const Eigen::Matrix3d R = lie::SO3d::Exp(Eigen::Vector3d(0.05, -0.08, 1.3)).matrix();
  const Eigen::Vector3d p(1.0, -2.0, 0.31);
  const Eigen::Vector3d r = kin.footPosition(legkit::model::FL, Eigen::Vector3d(0.1, 0.7, -1.4));
  const Eigen::Vector3d d = lo::footWorldPosition(p, R, r);
  CHECK((lo::basePositionFromFoot(d, R, r) - p).norm() < 1e-15);
  // Ground at the contact point's height: the base height is recovered from the foot alone.
  const double rho = kin.geometry().foot_radius;
  const double ground = lo::footContactHeight(p, R, r, rho);
  CHECK(ground == Approx(d.z() - rho).margin(1e-15));
  CHECK(lo::baseHeightFromFoot(ground, R, r, rho) == Approx(p.z()).margin(1e-15));

  // y = R^T (d - p): analytic Jacobians against central differences (attitude on the left).
  Eigen::Matrix3d J_p, J_theta, J_d;
  const Eigen::Vector3d y = lo::footMeasurement(p, R, d, &J_p, &J_theta, &J_d);
  CHECK((y - r).norm() < 1e-14);
  constexpr double h = 1e-6;
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(j);
    const Eigen::Matrix3d Rp = lie::SO3d::Exp(e).matrix() * R, Rm = lie::SO3d::Exp(-e).matrix() * R;
    const Eigen::Vector3d fd_p =
        (lo::footMeasurement(p + e, R, d) - lo::footMeasurement(p - e, R, d)) / (2 * h);
    const Eigen::Vector3d fd_t =
        (lo::footMeasurement(p, Rp, d) - lo::footMeasurement(p, Rm, d)) / (2 * h);
    const Eigen::Vector3d fd_d =
        (lo::footMeasurement(p, R, d + e) - lo::footMeasurement(p, R, d - e)) / (2 * h);
    CHECK((J_p.col(j) - fd_p).norm() < 1e-8);
    CHECK((J_theta.col(j) - fd_t).norm() < 1e-8);
    CHECK((J_d.col(j) - fd_d).norm() < 1e-8);
  }
}

TEST_CASE("bad inputs give clear errors, never a silent estimate", "[57.3][leg_odometry]") {
  using Catch::Matchers::Contains;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d w(0, 0, 1), r(0.2, -0.1, -0.3), rd(0.1, 0, 0);
  CHECK_THROWS_WITH(lo::baseVelocityFromFoot(I, Eigen::Vector3d(nan, 0, 0), r, rd),
                    Contains("w_b") && Contains("not finite"));
  CHECK_THROWS_WITH(lo::baseVelocityFromFoot(I, w, Eigen::Vector3d(0, nan, 0), rd),
                    Contains("foot position"));
  CHECK_THROWS_WITH(lo::baseVelocityFromFoot(I, w, r, Eigen::Vector3d(0, 0, nan)),
                    Contains("foot velocity"));
  Eigen::Matrix3d R_nan = I;
  R_nan(1, 2) = nan;
  CHECK_THROWS_WITH(lo::baseVelocityFromFoot(R_nan, w, r, rd), Contains("attitude R"));
  CHECK_THROWS_WITH(lo::baseVelocityFromFoot(2.0 * I, w, r, rd), Contains("not a rotation"));
  CHECK_THROWS_WITH(lo::baseVelocityFromFoot(-I, w, r, rd), Contains("not a rotation"));

  const std::vector<ContactMeasurement> none;
  CHECK_THROWS_WITH(lo::meanVelocity(I, w, none), Contains("empty"));
  CHECK_THROWS_WITH(lo::forceWeightedVelocity(I, w, none, Eigen::VectorXd()), Contains("empty"));
  CHECK_THROWS_WITH(lo::stackVelocityMeasurements(I, w, none, {}), Contains("empty"));

  ContactMeasurement c{2, r, I * 1e-6, std::nullopt};
  const std::vector<ContactMeasurement> one{c};
  CHECK_THROWS_WITH(lo::meanVelocity(I, w, one), Contains("foot 2") && Contains("v_body"));
  c.v_body = rd;
  const std::vector<ContactMeasurement> two{c, c};
  CHECK_THROWS_WITH(lo::forceWeightedVelocity(I, w, two, Eigen::Vector3d(1, 1, 1)),
                    Contains("3 normal forces for 2 contacts"));
  CHECK_THROWS_WITH(lo::forceWeightedVelocity(I, w, two, Eigen::Vector2d(0, -1)),
                    Contains("positive load"));
  CHECK_THROWS_WITH(lo::forceWeightedVelocity(I, w, two, Eigen::Vector2d(nan, 1)),
                    Contains("normal force"));
  const std::vector<ContactMeasurement> many(lo::kMaxContacts + 1, c);
  CHECK_THROWS_WITH(lo::meanVelocity(I, w, many), Contains("kMaxContacts"));
  CHECK_THROWS_WITH(lo::basePositionFromFoot(Eigen::Vector3d(nan, 0, 0), I, r),
                    Contains("world foot position"));
  CHECK_THROWS_AS(lo::baseHeightFromFoot(0.0, I, r, -0.01), std::invalid_argument);
}
