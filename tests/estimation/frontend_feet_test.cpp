// The feet of the front end (issue 14, items 3 and 5 on the use side): foot-velocity columns,
// the causal differentiator of foot positions against J dq, leg odometry that refuses to run on
// nothing, and generic joints through a model::LegKinematics (a small one of the test's own).
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "estimation/contact_pipeline.hpp"
#include "estimation/invariant/eskf.hpp"
#include "estimation/leg_odometry/leg_odometry_estimator.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "model/quadruped_leg_kinematics.hpp"
#include "trot_log.hpp"

using namespace legkit;

namespace {

// A joint log turned into the robot-agnostic one: each foot's FK(q) of the log's (measured)
// angles as a base-frame foot column, a 1 mm diagonal covariance, no velocity columns.
io::Log footColumnLog(const io::Log& joints) {
  const model::QuadrupedKinematics kinematics;
  io::Log log = joints;
  log.layout.joints = false;
  log.layout.torque = false;
  log.layout.foot_columns = io::FootCovariance::kDiagonal;
  for (io::LogRow& row : log.rows) {
    for (int foot = 0; foot < io::kNumLegs; ++foot) {
      row.feet[foot].p_body = kinematics.footPosition(foot, row.q.segment<3>(3 * foot));
      row.feet[foot].cov = 1e-6 * Eigen::Matrix3d::Identity();
    }
    row.q.setZero();
    row.dq.setZero();
    row.tau.setZero();
  }
  return log;
}

io::Log genericJointLog(const io::Log& joints) {
  io::Log log = joints;
  log.layout.joints = false;
  log.layout.torque = false;
  log.layout.num_joints = io::kNumJoints;
  for (io::LogRow& row : log.rows) {
    row.joint_q.head<io::kNumJoints>() = row.q;
    row.joint_dq.head<io::kNumJoints>() = row.dq;
    row.q.setZero();
    row.dq.setZero();
    row.tau.setZero();
  }
  return log;
}

}  // namespace

TEST_CASE("foot velocity: the differentiator's backward difference, low pass and touchdown reset",
          "[57.11][frontend]") {
  std::array<Eigen::Vector3d, io::kMaxFeet> p;
  p.fill(Eigen::Vector3d::Zero());
  std::array<bool, io::kMaxFeet> down{};
  const double dt = 1e-3;
  const Eigen::Vector3d v_swing(1.0, 0.0, 0.5), v_stance(-0.4, 0.1, 0.0);
  FootVelocityDifferentiator d(0.015);
  d.update(p, down, 1, 0.0);
  CHECK_FALSE(d.velocity(0));  // one position: no velocity yet
  p[0] += v_swing * dt;
  d.update(p, down, 1, dt);
  REQUIRE(d.velocity(0));
  CHECK(d.velocity(0)->isApprox(v_swing, 1e-9));  // its first difference, unfiltered
  // In stance the swing's velocity would linger for tau; the touchdown forgets it.
  down[0] = true;
  p[0] += v_stance * dt;
  d.update(p, down, 1, dt);
  CHECK(d.velocity(0)->isApprox(v_stance, 1e-9));
  // The next stance difference replaces the touchdown's (the mean of one), the one after is
  // averaged with it (n = 2), and from n = 16 = (tau + dt) / dt on the low pass's weight holds.
  p[0] += (v_stance + Eigen::Vector3d(0.2, 0, 0)) * dt;
  d.update(p, down, 1, dt);
  CHECK(d.velocity(0)->x() == Approx(-0.2).epsilon(1e-9));
  p[0] += (v_stance - Eigen::Vector3d(0.2, 0, 0)) * dt;
  d.update(p, down, 1, dt);
  CHECK(d.velocity(0)->x() == Approx(-0.4).epsilon(1e-9));
  for (int n = 3; n <= 16; ++n) {
    p[0] += v_stance * dt;
    d.update(p, down, 1, dt);
  }
  CHECK(d.velocity(0)->isApprox(v_stance, 1e-9));
  p[0] += (v_stance + Eigen::Vector3d(0.16, 0, 0)) * dt;
  d.update(p, down, 1, dt);
  CHECK(d.velocity(0)->x() == Approx(-0.4 + 0.16 * dt / (0.015 + dt)).epsilon(1e-9));
  // Two rows at one instant keep the velocity.
  const Eigen::Vector3d held = *d.velocity(0);
  d.update(p, down, 1, 0.0);
  CHECK(*d.velocity(0) == held);
  d.reset();
  CHECK_FALSE(d.velocity(0));
  CHECK_THROWS_WITH(FootVelocityDifferentiator(-1.0), Catch::Contains("tau must be >= 0"));
}

TEST_CASE("foot velocity: foot<k>_v columns are the stance feet's v_body", "[57.11][frontend]") {
  io::Log log = footColumnLog(test::trotLog(0.05, 2, false));
  log.layout.foot_velocity = true;
  for (io::LogRow& row : log.rows) row.feet[1].v_body = Eigen::Vector3d(0.1, -0.2, 0.3);
  const StepInput in =
      LogFrontend(log.layout, model::QuadrupedKinematics()).input(log.rows[10], 1e-3);
  bool seen = false;
  for (const ContactMeasurement& c : in.stance()) {
    REQUIRE(c.v_body);
    CHECK(*c.v_body == log.rows[10].feet[c.foot].v_body);
    seen = seen || c.foot == 1;
  }
  CHECK(seen);
}

TEST_CASE("foot velocity: differentiated foot columns against J dq on a simulated trot",
          "[57.11][frontend]") {
  const io::Log joints = test::trotLog(5.0, 7, false);  // encoder noise 1.75e-4 rad
  const io::Log exact = test::trotLog(5.0, 7, true);
  const io::Log feet = footColumnLog(joints);
  const model::QuadrupedKinematics kinematics;
  const LogFrontend frontend(feet.layout, kinematics);
  REQUIRE(frontend.differentiatesFeet());
  // RMS of (v_body - J dq) over every stance sample, J dq from the exact joints.
  const auto rmsError = [&](double tau) {
    FootVelocityDifferentiator velocities(tau);
    double sum = 0.0;
    int n = 0;
    for (std::size_t k = 0; k < feet.rows.size(); ++k) {
      const double dt = k == 0 ? 0.0 : feet.rows[k].t - feet.rows[k - 1].t;
      const StepInput in = frontend.input(feet.rows[k], dt, &velocities);
      if (k == 0) continue;
      for (const ContactMeasurement& c : in.stance()) {
        REQUIRE(c.v_body);
        const Eigen::Vector3d q = exact.rows[k].q.segment<3>(3 * c.foot);
        const Eigen::Vector3d J_dq =
            kinematics.footJacobian(c.foot, q) * exact.rows[k].dq.segment<3>(3 * c.foot);
        sum += (*c.v_body - J_dq).squaredNorm();
        ++n;
      }
    }
    return std::sqrt(sum / n);
  };
  const double filtered = rmsError(kFootVelocityTau), raw = rmsError(0.0);
  INFO("differentiated foot velocity against J dq: RMS "
       << filtered << " m/s with tau = " << kFootVelocityTau << " s, " << raw << " m/s unfiltered");
  CHECK(filtered < 0.03);
  CHECK(filtered < 0.3 * raw);
  // A longer time constant lags the stance's changing velocity: 15 ms is worse, not better.
  CHECK(rmsError(0.015) > 1.5 * filtered);
}

TEST_CASE("leg odometry never runs silently on nothing", "[57.11][frontend]") {
  const io::Log joints = test::trotLog(5.0, 3, false);
  const io::Log feet = footColumnLog(joints);
  const EstimateSample x0 = eval::initialState(joints);
  leg_odometry::LegOdometryEstimator lo;
  // Stance feet without v_body (the front end without a differentiator): refused, by name.
  const LogFrontend frontend(feet.layout, model::QuadrupedKinematics());
  lo.reset(x0);
  lo.step(frontend.input(feet.rows[0], 0.0));  // a first sample: x0 gives the velocity
  const StepInput blind = frontend.input(feet.rows[1], feet.rows[1].t - feet.rows[0].t);
  REQUIRE(blind.num_contacts > 0);
  const EstimateSample before = lo.estimate();
  CHECK_THROWS_WITH(lo.step(blind), Catch::Contains("has no velocity (v_body)"));
  CHECK(lo.estimate().p == before.p);  // before anything changed

  // The runner and the pipeline differentiate: leg odometry measures with the legs, within
  // 2 cm of the joint log's run (5 s).
  const eval::Metrics on_joints = eval::compare(
      joints,
      eval::runOnLog(lo, joints, LogFrontend(joints.layout, model::QuadrupedKinematics()), x0)
          .trajectory);
  const eval::RunResult run = eval::runOnLog(lo, feet, frontend, x0);
  REQUIRE_FALSE(run.failed());
  const eval::Metrics on_feet = eval::compare(feet, run.trajectory);
  PipelineOptions options;
  ContactPipeline pipeline(frontend, options);
  const eval::RunResult piped = eval::runOnLog(lo, feet, pipeline, x0);
  REQUIRE_FALSE(piped.failed());
  const eval::Metrics on_pipeline = eval::compare(feet, piped.trajectory);
  // Without legs, the IMU alone, as leg odometry used to report on such a log.
  io::Log no_legs = feet;
  for (io::LogRow& row : no_legs.rows) row.contact.fill(false);
  const eval::Metrics imu_only =
      eval::compare(feet, eval::runOnLog(lo, no_legs, frontend, x0).trajectory);
  INFO("leg odometry, 5 s trot: position RMSE "
       << on_joints.position_rmse << " m on joints, " << on_feet.position_rmse
       << " m on differentiated foot columns (" << on_pipeline.position_rmse
       << " m through the pipeline), " << imu_only.position_rmse << " m IMU alone");
  CHECK(on_feet.position_rmse < on_joints.position_rmse + 0.02);
  CHECK(on_pipeline.position_rmse < on_joints.position_rmse + 0.02);
  CHECK(on_feet.position_rmse < 0.2 * imu_only.position_rmse);
}

TEST_CASE("generic joints: a LegKinematics gives the quadruped path's feet", "[57.11][frontend]") {
  const io::Log joints = test::trotLog(2.0, 5, false);
  const io::Log generic = genericJointLog(joints);
  const model::QuadrupedLegKinematics legs;  // joint k = 3 leg + j
  const LogFrontend quadruped(joints.layout, model::QuadrupedKinematics());
  const LogFrontend frontend(generic.layout, legs);
  for (std::size_t k : {std::size_t{0}, std::size_t{333}, std::size_t{1500}}) {
    const StepInput a = quadruped.input(joints.rows[k], 1e-3);
    const StepInput b = frontend.input(generic.rows[k], 1e-3);
    REQUIRE(a.num_contacts > 0);
    REQUIRE(b.num_contacts == a.num_contacts);
    for (int i = 0; i < a.num_contacts; ++i) {
      CHECK(b.contacts[i].foot == a.contacts[i].foot);
      CHECK(b.contacts[i].p_body == a.contacts[i].p_body);
      CHECK(b.contacts[i].v_body->isApprox(*a.contacts[i].v_body, 1e-14));
      CHECK(b.contacts[i].cov.isApprox(a.contacts[i].cov, 1e-14));
    }
    // What a detector sees: the same FK and J dq.
    const contact::ContactSignals sa = quadruped.signals(joints.rows[k], 1e-3, {});
    const contact::ContactSignals sb = frontend.signals(generic.rows[k], 1e-3, {});
    for (int foot = 0; foot < io::kNumLegs; ++foot) {
      CHECK(sb.feet[foot].has_kinematics);
      CHECK(sb.feet[foot].p_body == sa.feet[foot].p_body);
      CHECK(sb.feet[foot].v_body.isApprox(sa.feet[foot].v_body, 1e-14));
    }
  }
  // A whole run: the ESKF on either log, to rounding.
  const EstimateSample x0 = eval::initialState(joints);
  invariant::Eskf filter;
  const eval::Metrics m_q =
      eval::compare(joints, eval::runOnLog(filter, joints, quadruped, x0).trajectory);
  const eval::Metrics m_g =
      eval::compare(generic, eval::runOnLog(filter, generic, frontend, x0).trajectory);
  CHECK(m_g.position_rmse == Approx(m_q.position_rmse).epsilon(1e-6));
  CHECK(m_g.velocity_rmse == Approx(m_q.velocity_rmse).epsilon(1e-6));

  // The robot must match the log.
  CHECK_THROWS_WITH(LogFrontend(generic.layout, model::QuadrupedKinematics()),
                    Catch::Contains("give the robot's LegKinematics"));
  io::LogLayout six = generic.layout;
  six.num_joints = 6;
  CHECK_THROWS_WITH(LogFrontend(six, legs),
                    Catch::Contains("the log has 6 joints and 4 feet, the robot's kinematics 12 "
                                    "joints and 4 feet"));
  CHECK_THROWS_WITH(LogFrontend(joints.layout, legs), Catch::Contains("generic joint columns"));
}
