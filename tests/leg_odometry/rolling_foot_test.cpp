// The rolling foot (estimation/leg_odometry/rolling_foot.hpp): a foot sphere that rolls without
// slipping on flat ground while the leg pivots over it. The corrected stance point stays where the
// sphere touched down; the sphere's centre (what FK gives) does not.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>

#include "estimation/leg_odometry/rolling_foot.hpp"

using Eigen::Matrix3d;
using Eigen::Vector3d;
using legkit::ContactMeasurement;
using legkit::StepInput;
using legkit::io::JointVector;
using legkit::leg_odometry::RollingFoot;
using legkit::model::QuadrupedGeometry;
using legkit::model::QuadrupedKinematics;

namespace {

Matrix3d Rx(double a) {
  return Eigen::AngleAxisd(a, Vector3d::UnitX()).toRotationMatrix();
}
Matrix3d Ry(double a) {
  return Eigen::AngleAxisd(a, Vector3d::UnitY()).toRotationMatrix();
}
Matrix3d Rz(double a) {
  return Eigen::AngleAxisd(a, Vector3d::UnitZ()).toRotationMatrix();
}

// One leg (FL) in stance while the base turns and the joints move smoothly: base attitude R(t),
// joint angles q(t) and rates dq(t), all in closed form.
struct PivotingLeg {
  static constexpr int kLeg = 0;
  Matrix3d R(double t) const { return Rz(0.4 * t) * Ry(0.1 * std::sin(2.0 * t)); }
  // Body-frame base rate: R^T dR/dt for R = Rz(a t) Ry(b(t)).
  Vector3d w(double t) const {
    return Ry(-0.1 * std::sin(2.0 * t)) * Vector3d(0.0, 0.0, 0.4) +
           Vector3d(0.0, 0.2 * std::cos(2.0 * t), 0.0);
  }
  Vector3d q(double t) const {
    return {0.08 * std::sin(3.0 * t), 0.7 + 0.9 * t, -1.5 + 0.6 * t - 0.3 * t * t};
  }
  Vector3d dq(double t) const { return {0.24 * std::cos(3.0 * t), 0.9, 0.6 - 0.6 * t}; }
  // The calf's (and the sphere's) attitude in the world: R Rx(q1) Ry(q2 + q3).
  Matrix3d calf(double t) const {
    const Vector3d a = q(t);
    return R(t) * Rx(a.x()) * Ry(a.y() + a.z());
  }
  // The calf's world angular velocity by differencing its attitude (independent of the code's
  // joint-rate formula).
  Vector3d calfRate(double t) const {
    const double h = 1e-6;
    const Eigen::AngleAxisd d(calf(t + h) * calf(t - h).transpose());
    return d.angle() / (2.0 * h) * d.axis();
  }
};

StepInput stanceInput(double t, double dt, const QuadrupedKinematics& kin, const Vector3d& q,
                      const Vector3d& dq, const Vector3d& w) {
  StepInput in;
  in.t = t;
  in.dt = dt;
  in.imu.w_m = w;
  ContactMeasurement& c = in.contacts[0];
  c.foot = PivotingLeg::kLeg;
  c.p_body = kin.footPosition(PivotingLeg::kLeg, q);
  c.v_body = kin.footJacobian(PivotingLeg::kLeg, q) * dq;
  c.cov = 1e-6 * Matrix3d::Identity();
  in.num_contacts = 1;
  return in;
}

}  // namespace

TEST_CASE("rolling foot: the corrected stance point of a rolling sphere stays still",
          "[57.3][leg_odometry][rolling_foot]") {
  const QuadrupedGeometry g = QuadrupedGeometry::go2();
  const QuadrupedKinematics kin(g);
  const double r = g.foot_radius;
  const PivotingLeg leg;
  RollingFoot rolling(g);

  // The sphere rolls without slipping: its centre moves at w_calf x (r e_z), integrated here with
  // 100 midpoint substeps per 1 ms sample. The base position follows from the centre and the
  // kinematics: p = c - R FK(q).
  const double dt = 1e-3, duration = 0.3;
  const int substeps = 100;
  Vector3d c(0.3, 0.15, r);  // sphere centre in the world, resting on z = 0
  const Vector3d ground0 = c - r * Vector3d::UnitZ();
  double worst_point = 0.0, worst_centre = 0.0, worst_speed = 0.0, centre_speed = 0.0;
  const int n = static_cast<int>(std::lround(duration / dt));
  for (int k = 0; k <= n; ++k) {
    const double t = k * dt;
    if (k > 0) {
      const double h = dt / substeps;
      for (int j = 0; j < substeps; ++j) {
        const double tm = t - dt + (j + 0.5) * h;
        c += h * leg.calfRate(tm).cross(r * Vector3d::UnitZ());
      }
    }
    const Vector3d q = leg.q(t), dq = leg.dq(t), w = leg.w(t);
    const Matrix3d R = leg.R(t);
    StepInput in = stanceInput(t, k == 0 ? 0.0 : dt, kin, q, dq, w);
    const Vector3d p = c - R * in.contacts[0].p_body;  // base position
    // Base velocity: dc/dt - d(R c_b)/dt.
    const Vector3d v = leg.calfRate(t).cross(r * Vector3d::UnitZ()) -
                       R * (w.cross(in.contacts[0].p_body) + *in.contacts[0].v_body);
    JointVector Q = JointVector::Zero(), DQ = JointVector::Zero();
    Q.segment<3>(0) = q;
    DQ.segment<3>(0) = dq;
    rolling.apply(in, R, in.imu.w_m, Q, DQ);
    const ContactMeasurement& m = in.contacts[0];
    worst_point = std::max(worst_point, (p + R * m.p_body - ground0).norm());
    worst_centre = std::max(worst_centre, (c - r * Vector3d::UnitZ() - ground0).norm());
    worst_speed = std::max(worst_speed, (v + R * (w.cross(m.p_body) + *m.v_body)).norm());
    centre_speed = std::max(centre_speed, leg.calfRate(t).cross(r * Vector3d::UnitZ()).norm());
  }
  INFO("corrected point moved " << worst_point << " m, centre " << worst_centre << " m");
  // The calf turns about 0.5 rad over the stance: the centre travels about 1 cm (0.0106 m).
  CHECK(worst_centre > 0.008);
  CHECK(centre_speed > 0.03);
  // The trapezoidal rule at 1 kHz on this smooth motion: well under a micrometre.
  CHECK(worst_point < 1e-6);
  // The corrected point's world velocity v + R (w x p' + v') vanishes (to the differencing of
  // calfRate, ~1e-9).
  CHECK(worst_speed < 1e-6);
}

TEST_CASE("rolling foot: touchdown restarts the rolled distance; swing feet are untouched",
          "[57.3][leg_odometry][rolling_foot]") {
  const QuadrupedGeometry g = QuadrupedGeometry::go2();
  const QuadrupedKinematics kin(g);
  RollingFoot rolling(g);
  const PivotingLeg leg;
  JointVector Q = JointVector::Zero(), DQ = JointVector::Zero();
  const auto step = [&](double t, double dt) {
    Q.segment<3>(0) = leg.q(t);
    DQ.segment<3>(0) = leg.dq(t);
    StepInput in = stanceInput(t, dt, kin, leg.q(t), leg.dq(t), leg.w(t));
    rolling.apply(in, leg.R(t), in.imu.w_m, Q, DQ);
    return in;
  };
  for (int k = 0; k < 100; ++k) step(k * 1e-3, k == 0 ? 0.0 : 1e-3);
  CHECK(rolling.rolled(0).norm() > 1e-3);
  // A sample without the foot (swing): nothing to correct, and the foot's roll is forgotten.
  StepInput swing;
  swing.t = 0.1;
  swing.dt = 1e-3;
  rolling.apply(swing, leg.R(0.1), swing.imu.w_m, Q, DQ);
  CHECK(swing.num_contacts == 0);
  CHECK(rolling.rolled(0).norm() == 0.0);
  // Touchdown again: the point is the sphere's lowest point now, centre - r R^T e_z.
  const StepInput td = step(0.101, 1e-3);
  const Vector3d centre = kin.footPosition(0, leg.q(0.101));
  const Vector3d expected = centre - g.foot_radius * leg.R(0.101).transpose() * Vector3d::UnitZ();
  CHECK((td.contacts[0].p_body - expected).norm() < 1e-15);
  CHECK(rolling.rolled(0).norm() == 0.0);
}

TEST_CASE("rolling foot: bad input", "[57.3][leg_odometry][rolling_foot]") {
  QuadrupedGeometry g = QuadrupedGeometry::go2();
  RollingFoot rolling(g);
  const QuadrupedKinematics kin(g);
  const JointVector Q = JointVector::Zero(), DQ = JointVector::Zero();
  StepInput in =
      stanceInput(0.5, 1e-3, kin, Vector3d(0.0, 0.7, -1.5), Vector3d::Zero(), Vector3d::Zero());
  in.contacts[0].foot = 4;
  CHECK_THROWS_WITH(rolling.apply(in, Matrix3d::Identity(), in.imu.w_m, Q, DQ),
                    Catch::Contains("foot id 4") && Catch::Contains("t = 0.5"));
  in.contacts[0].foot = 1;
  in.contacts[0].v_body.reset();
  const Vector3d before = in.contacts[0].p_body;
  CHECK_THROWS_WITH(rolling.apply(in, Matrix3d::Identity(), in.imu.w_m, Q, DQ),
                    Catch::Contains("v_body"));
  CHECK(in.contacts[0].p_body == before);
  g.foot_radius = -0.01;
  CHECK_THROWS_AS(RollingFoot(g), std::invalid_argument);
}
