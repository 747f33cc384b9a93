// The estimator manager (57.11): on a physics trot fed sample by sample as a robot would send it,
// the same estimates as eval::runOnLog with the same pipeline and filter; the MPC query from its
// ring buffer; bad input refused with nothing changed; no allocation per update.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "estimation/contact_pipeline.hpp"
#include "estimation/estimators.hpp"
#include "estimation/state_estimator.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "model/mjcf.hpp"
#include "model/quadruped_inertia.hpp"
#include "sim/physics_simulator.hpp"

// This program counts its heap allocations (the header defines operator new: this file only).
#include "allocation_counter.hpp"

using namespace legkit;

namespace {

// A short physics trot (MuJoCo) with foot-force columns, shared by the tests of this file.
const io::Log& trotLog() {
  static const io::Log log = [] {
    sim::PhysicsOptions o = sim::PhysicsOptions::forScenario("physics-trot");
    o.duration = 3.0;
    o.seed = 7;
    return sim::simulatePhysics(o).log;
  }();
  return log;
}

// The manager's settings of these tests: the chapter's Schmitt trigger on the foot sensors, the
// filter started at the first sample (no stationary initialisation: its own test below).
Settings schmittSettings(const std::string& estimator) {
  Settings s;
  s.estimators = {estimator};
  s.pipeline.contact = "schmitt";
  s.initialisation.enabled = false;
  return s;
}

// Row k as the robot's three samples.
struct Samples {
  ImuSample imu;
  JointSample joints;
  ForceSample forces;
};
Samples samplesOf(const io::LogRow& row) {
  Samples s;
  s.imu = {row.t, row.gyro, row.acc};
  s.joints.q.head<io::kNumJoints>() = row.q;
  s.joints.dq.head<io::kNumJoints>() = row.dq;
  for (int f = 0; f < io::kNumLegs; ++f) s.forces.force[f] = row.force[f];
  s.forces.valid = true;
  return s;
}
const EstimatorOutput& feed(StateEstimator& m, const io::LogRow& row) {
  const Samples s = samplesOf(row);
  return m.update(s.imu, s.joints, s.forces);
}

bool sameState(const EstimateSample& a, const EstimateSample& b, double tol) {
  return a.t == b.t && (a.p - b.p).lpNorm<Eigen::Infinity>() <= tol &&
         (a.v - b.v).lpNorm<Eigen::Infinity>() <= tol &&
         (a.q.coeffs() - b.q.coeffs()).lpNorm<Eigen::Infinity>() <= tol;
}

}  // namespace

TEST_CASE("manager: equals runOnLog with the same pipeline and filter, and tracks the truth",
          "[57.11][physics]") {
  const io::Log& log = trotLog();
  REQUIRE(log.layout.force);
  const EstimateSample x0 = eval::initialState(log);  // the truth at row 0
  for (const char* name : {"invariant-ekf", "eskf", "linear-kf"}) {
    INFO(name);
    const Settings settings = schmittSettings(name);
    StateEstimator manager(settings);
    CHECK(manager.estimatorName() == name);
    CHECK(manager.contactSource() == "schmitt");
    manager.reset(x0);
    eval::Trajectory managed;
    for (const io::LogRow& row : log.rows) {
      const EstimatorOutput& out = feed(manager, row);
      REQUIRE(out.initialised);
      managed.push_back(out.x);
    }

    ContactPipeline pipeline(log.layout, model::QuadrupedKinematics(), settings.frontend,
                             settings.pipeline, contact::DetectorContext{});
    const std::unique_ptr<Estimator> e = makeEstimator(name);
    const eval::RunResult run = eval::runOnLog(*e, log, pipeline, x0);
    REQUIRE_FALSE(run.failed());
    REQUIRE(run.trajectory.size() == managed.size());
    bool same = true;
    for (std::size_t k = 0; k < managed.size(); ++k) {
      same = same && sameState(managed[k], run.trajectory[k], 1e-12);
    }
    CHECK(same);
    CHECK(manager.output().health.total() == run.health.total());

    // Measured on this 3 s log (seed 7; the WARN lines of test_state_estimator): position RMSE
    // 0.0146 / 0.0147 / 0.0075 m, velocity 0.026 / 0.026 / 0.047 m/s, tilt 0.24 / 0.24 / 0.33 deg
    // (invariant-ekf / eskf / linear-kf); the bounds leave about 2x.
    const eval::Metrics m = eval::compare(log, managed);
    WARN(name << ": position RMSE " << m.position_rmse << " m, velocity RMSE " << m.velocity_rmse
              << " m/s, tilt " << m.tilt_rmse_deg << " deg");
    CHECK(m.position_rmse < 0.03);
    CHECK(m.velocity_rmse < 0.1);
    CHECK(m.tilt_rmse_deg < 0.7);
  }
}

TEST_CASE("manager: without a start it begins at rest at the origin, tilt from the accelerometer",
          "[57.11][physics]") {
  const io::Log& log = trotLog();
  std::size_t k = 0;
  while (log.rows[k].t < 0.5) ++k;  // half-way through the scenario's 1 s stand
  StateEstimator manager(schmittSettings("invariant-ekf"));
  const EstimatorOutput& out = feed(manager, log.rows[k]);
  CHECK(out.initialised);
  CHECK(out.start == StartMode::kFirstSample);
  CHECK(out.has_covariance);
  CHECK(out.x.t == log.rows[k].t);
  CHECK(out.x.p.norm() < 1e-9);
  CHECK(out.x.v.norm() < 1e-9);
  // The attitude turns the measured specific force to world up, yaw 0.
  CHECK((out.x.q * log.rows[k].acc.normalized() - Eigen::Vector3d::UnitZ()).norm() < 1e-12);
  // One sample of the physics trot's accelerometer is that far from the truth (the robot stands):
  // why a robot should give the manager a start (reset(x0)) or a still window.
  const double tilt =
      eval::tiltError(out.x.q.toRotationMatrix(), log.rows[k].gt_q.toRotationMatrix());
  WARN("tilt of one accelerometer sample at t = 0.5 s: " << tilt * 180.0 / M_PI << " deg");
  CHECK(tilt > 0.0);
}

TEST_CASE("manager: stationary initialisation waits for a still window, then starts from it",
          "[57.11][physics]") {
  const io::Log& log = trotLog();
  Settings settings = schmittSettings("eskf");
  settings.initialisation.enabled = true;
  // The scenario stands for 1 s, with a vibrating body: 0.5 s windows of 25 ms block means spread
  // 0.021-0.030 rad/s and 0.16-0.34 m/s^2 per axis there, above the defaults (2 s, 0.02, 0.3).
  settings.initialisation.duration = 0.5;
  settings.initialisation.gyro_std_max = 0.05;
  settings.initialisation.accel_std_max = 0.5;
  StateEstimator manager(settings);
  std::size_t k = 0;
  for (; k < log.rows.size(); ++k) {
    const EstimatorOutput& out = feed(manager, log.rows[k]);
    if (out.initialised) break;
    CHECK(out.initialising);
    CHECK(manager.buffered() == 0);
  }
  REQUIRE(k < log.rows.size());
  const EstimatorOutput& out = manager.output();
  WARN("still window found at t = " << log.rows[k].t << " s");
  CHECK(log.rows[k].t >= 0.5);
  CHECK(log.rows[k].t <= 1.0);
  CHECK_FALSE(out.initialising);
  CHECK(out.x.t == log.rows[k].t);
  CHECK(out.x.p.norm() < 1e-3);
  CHECK(manager.buffered() == 1);
  CHECK(out.start == StartMode::kStillWindow);
  // The window's mean specific force: within 1 deg of the truth's tilt (one sample: 15.7 deg).
  const double tilt =
      eval::tiltError(out.x.q.toRotationMatrix(), log.rows[k].gt_q.toRotationMatrix());
  WARN("tilt from the still window: " << tilt * 180.0 / M_PI << " deg");
  CHECK(tilt < 1.0 * M_PI / 180.0);
  // Given a start, the manager does not wait.
  manager.reset(eval::initialState(log));
  CHECK(feed(manager, log.rows[0]).initialised);
  CHECK(manager.output().start == StartMode::kGiven);
}

TEST_CASE(
    "manager: when no still window comes within max_wait, the loop goes on from the tilt "
    "of the last samples",
    "[57.11][physics]") {
  const io::Log& log = trotLog();
  Settings settings = schmittSettings("invariant-ekf");
  settings.initialisation.enabled = true;  // the defaults (2 s window): never still on this stand
  settings.initialisation.max_wait = 0.8;  // within the scenario's 1 s stand
  StateEstimator manager(settings);
  std::size_t k = 0;
  for (; k < log.rows.size(); ++k) {
    if (feed(manager, log.rows[k]).initialised) break;
    CHECK(manager.output().start == StartMode::kNotStarted);
  }
  REQUIRE(k < log.rows.size());
  const EstimatorOutput& out = manager.output();
  CHECK(out.start == StartMode::kGaveUp);
  CHECK(std::string(startModeName(out.start)) == "gave up: tilt from the last samples");
  CHECK(log.rows[k].t >= 0.8);
  CHECK(log.rows[k].t < 0.81);
  CHECK(out.x.p.norm() < 1e-9);
  // The gravity direction of the last 0.1 s against one sample's. Measured (the WARN line): 0.15
  // deg against 7.9 deg at t = 0.8 s.
  const double tilt =
      eval::tiltError(out.x.q.toRotationMatrix(), log.rows[k].gt_q.toRotationMatrix());
  const Eigen::Quaterniond one_sample =
      Eigen::Quaterniond::FromTwoVectors(log.rows[k].acc.normalized(), Eigen::Vector3d::UnitZ());
  const double tilt_one =
      eval::tiltError(one_sample.toRotationMatrix(), log.rows[k].gt_q.toRotationMatrix());
  WARN("gave up at t = " << log.rows[k].t << " s: tilt " << tilt * 180.0 / M_PI
                         << " deg from the last samples, " << tilt_one * 180.0 / M_PI
                         << " deg from that one sample");
  CHECK(tilt < tilt_one);
  CHECK(tilt < 1.0 * M_PI / 180.0);
  // The robot's loop runs on to the end of the log: every later sample is an estimate.
  bool finite = true;
  for (++k; k < log.rows.size(); ++k) {
    const EstimatorOutput& o = feed(manager, log.rows[k]);
    finite = finite && o.initialised && o.x.p.allFinite() && o.start == StartMode::kGaveUp;
  }
  CHECK(finite);
  CHECK(manager.stateAt(log.rows.back().t).age == 0.0);
}

TEST_CASE("manager: the monitors report a stuck encoder and its leg leaves the filter",
          "[57.11][physics]") {
  const io::Log& log = trotLog();
  StateEstimator manager(schmittSettings("eskf"));
  manager.reset(eval::initialState(log));
  const double t_stuck = 2.0;  // trotting by then
  double q_frozen = 0.0;
  double found = -1.0;
  for (const io::LogRow& row : log.rows) {
    Samples s = samplesOf(row);
    if (row.t < t_stuck) q_frozen = row.q[2];  // FL knee
    if (row.t >= t_stuck) {
      s.joints.q[2] = q_frozen;
      s.joints.dq[2] = 0.0;
    }
    const EstimatorOutput& out = manager.update(s.imu, s.joints, s.forces);
    if (row.t < t_stuck) CHECK_FALSE(out.monitors.uncertain);
    if (found < 0.0 && out.monitors[engineering::Alarm::kStuckEncoder]) found = row.t;
  }
  WARN("stuck FL knee from " << t_stuck << " s found at " << found << " s");
  CHECK(found >= t_stuck);
  CHECK(found <= t_stuck + 0.2);
  CHECK(manager.output().x.p.allFinite());
}

TEST_CASE("manager: joints marked invalid give the filter the IMU alone", "[57.11][physics]") {
  const io::Log& log = trotLog();
  StateEstimator manager(schmittSettings("eskf"));
  const EstimateSample x0 = eval::initialState(log);
  manager.reset(x0);
  const std::unique_ptr<Estimator> imu_only = makeEstimator("eskf");
  imu_only->reset(x0);
  bool same = true;
  for (std::size_t k = 0; k < 300; ++k) {
    Samples s = samplesOf(log.rows[k]);
    s.joints.valid = false;
    s.joints.count = 0;  // not read when invalid
    const EstimatorOutput& out = manager.update(s.imu, s.joints, s.forces);
    StepInput in;
    in.t = log.rows[k].t;
    in.dt = k == 0 ? 0.0 : log.rows[k].t - log.rows[k - 1].t;
    in.imu = {log.rows[k].gyro, log.rows[k].acc};
    in.has_force = true;
    imu_only->step(in);
    same = same && sameState(out.x, imu_only->estimate(), 0.0);
    CHECK_FALSE(out.joints_valid);
  }
  CHECK(same);
}

TEST_CASE("manager: bad input throws naming what and when, and nothing changes",
          "[57.11][physics]") {
  const io::Log& log = trotLog();
  StateEstimator manager(schmittSettings("invariant-ekf"));
  StateEstimator twin(schmittSettings("invariant-ekf"));  // fed the valid samples only
  for (std::size_t k = 0; k < 50; ++k) {
    feed(manager, log.rows[k]);
    feed(twin, log.rows[k]);
  }
  const EstimateSample before = manager.output().x;
  const std::size_t buffered = manager.buffered();
  const Samples good = samplesOf(log.rows[50]);

  const auto refused = [&](const Samples& s, const std::string& what) {
    INFO(what);
    try {
      manager.update(s.imu, s.joints, s.forces);
      FAIL("no exception");
    } catch (const std::invalid_argument& e) {
      const std::string msg = e.what();
      CHECK(msg.find(what) != std::string::npos);
      CHECK(msg.find("t = ") != std::string::npos);
    }
    CHECK(sameState(manager.output().x, before, 0.0));
    CHECK(manager.buffered() == buffered);
  };
  Samples s = good;
  s.imu.t = log.rows[49].t;
  refused(s, "imu.t is not after");
  s = good;
  s.imu.t = log.rows[30].t;
  refused(s, "imu.t is not after");
  s = good;
  s.imu.gyro.y() = std::nan("");
  refused(s, "imu.gyro");
  s = good;
  s.imu.acc.z() = INFINITY;
  refused(s, "imu.acc");
  s = good;
  s.joints.q[7] = std::nan("");
  refused(s, "joints.q[7]");
  s = good;
  s.joints.count = 11;
  refused(s, "joints.count is 11");
  s = good;
  s.forces.force[2] = std::nan("");
  refused(s, "forces.force[2]");
  // A NaN where the sample says it is not valid is not read.
  s = good;
  s.forces.force[2] = std::nan("");
  s.forces.valid = false;
  CHECK_NOTHROW(manager.update(s.imu, s.joints, s.forces));
  CHECK_FALSE(manager.output().forces_valid);

  // The refused samples left no trace: from a fresh twin, the same sample gives the same state.
  StateEstimator clean(schmittSettings("invariant-ekf"));
  for (std::size_t k = 0; k < 50; ++k) feed(clean, log.rows[k]);
  clean.update(s.imu, s.joints, s.forces);
  CHECK(sameState(manager.output().x, clean.output().x, 0.0));
}

TEST_CASE("manager: the filter takes its parameters from the settings", "[57.11][physics]") {
  const io::Log& log = trotLog();
  const EstimateSample x0 = eval::initialState(log);
  Settings noisy = schmittSettings("eskf");
  noisy.imu.gyro_noise_density *= 100.0;  // a much worse gyro: the attitude grows uncertain
  StateEstimator plain(schmittSettings("eskf")), loud(noisy);
  plain.reset(x0);
  loud.reset(x0);
  for (std::size_t k = 0; k < 200; ++k) {
    feed(plain, log.rows[k]);
    feed(loud, log.rows[k]);
  }
  REQUIRE(plain.output().has_covariance);
  REQUIRE(loud.output().has_covariance);
  // The yaw variance (row 2 of BaseCovariance, the least observed angle) after 0.2 s: the
  // settings reached the filter. Measured (the WARN line): 1.02e-4 rad^2 (mostly the 0.01 rad
  // prior) against 1.21e-3 with 100x the density; the bound leaves about 2x.
  const double plain_yaw = plain.output().P.P(2, 2), loud_yaw = loud.output().P.P(2, 2);
  WARN("ESKF yaw variance after 0.2 s: " << plain_yaw << " rad^2, with 100x the gyro density "
                                         << loud_yaw);
  CHECK(loud_yaw > 5.0 * plain_yaw);
}

TEST_CASE(
    "manager: the IMU extrinsic of the settings reaches the front end, the output is the base",
    "[57.11][physics]") {
  const io::Log& log = trotLog();
  const EstimateSample x0 = eval::initialState(log);
  // A mount the log's IMU does not have (it sits at the base): what counts here is that the
  // manager and the runner with the same front end agree, and differ from the unmounted run.
  model::ImuExtrinsic mount;
  mount.q_BI =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d(0.3, -0.5, 1.0).normalized()));
  mount.p_BI = Eigen::Vector3d(0.15, -0.1, 0.09);
  Settings settings = schmittSettings("eskf");
  settings.imu_extrinsic = mount;
  StateEstimator manager(settings), plain(schmittSettings("eskf"));
  manager.reset(x0);
  plain.reset(x0);
  eval::Trajectory managed;
  double apart = 0.0;  // the mounted and the plain manager's position difference
  for (const io::LogRow& row : log.rows) {
    managed.push_back(feed(manager, row).x);
    apart = std::max(apart, (managed.back().p - feed(plain, row).x.p).norm());
  }
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics(), settings.frontend, mount);
  ContactPipeline pipeline(frontend, settings.pipeline, contact::DetectorContext{});
  const std::unique_ptr<Estimator> e = makeEstimator("eskf");
  const eval::RunResult run = eval::runOnLog(*e, log, pipeline, x0);
  REQUIRE(run.trajectory.size() == managed.size());
  bool same = true;
  for (std::size_t k = 0; k < managed.size(); ++k) {
    same = same && sameState(managed[k], run.trajectory[k], 1e-9);
  }
  CHECK(same);
  // Measured: 0.049 m.
  WARN("a 0.2 m, 5.7 deg mount the log does not have moves the estimate by up to " << apart
                                                                                   << " m");
  CHECK(apart > 1e-3);
}

TEST_CASE("manager: a robot of generic joints through its model file (the Go2 as MJCF)",
          "[57.11][physics]") {
  const io::Log& log = trotLog();
  const EstimateSample x0 = eval::initialState(log);
  const std::string path = "state_estimator_test_go2.xml";
  std::ofstream(path) << model::quadrupedMjcf(model::QuadrupedGeometry::go2(),
                                              model::QuadrupedInertia::go2());
  // Without the rolling foot, which needs the quadruped's own joints (ContactPipeline).
  Settings plain = schmittSettings("invariant-ekf");
  plain.pipeline.rolling_foot = false;
  Settings settings = plain;
  settings.robot.model = path;
  settings.robot.base = "base";
  settings.robot.feet = {"FL_foot", "FR_foot", "RL_foot", "RR_foot"};
  StateEstimator generic(settings), quadruped(plain);
  std::remove(path.c_str());  // read at construction
  CHECK(generic.numJoints() == 12);
  CHECK(generic.numFeet() == 4);
  CHECK(generic.layout().num_joints == 12);
  generic.reset(x0);
  quadruped.reset(x0);
  double apart = 0.0;
  for (const io::LogRow& row : log.rows) {
    const Samples s = samplesOf(row);  // joint k = 3 leg + j, the MJCF's hinge order
    const EstimatorOutput& g = generic.update(s.imu, s.joints, s.forces);
    REQUIRE(g.initialised);
    apart = std::max(apart, (g.x.p - quadruped.update(s.imu, s.joints, s.forces).x.p).norm());
  }
  WARN("generic joints (MJCF Go2) against the analytic Go2: positions apart by up to " << apart
                                                                                       << " m");
  CHECK(apart < 1e-9);  // measured 5.5e-16 m: the same legs
  Samples s = samplesOf(log.rows[0]);
  s.imu.t = log.rows.back().t + 1.0;
  s.joints.count = 13;
  CHECK_THROWS_WITH(generic.update(s.imu, s.joints, s.forces),
                    Catch::Contains("joints.count is 13, the robot has 12 joints"));
}

TEST_CASE("manager: construction refuses what it cannot run", "[57.11]") {
  Settings s = schmittSettings("no-such-filter");
  CHECK_THROWS_AS(StateEstimator(s), std::invalid_argument);
  s = schmittSettings("eskf");
  s.pipeline.contact = "no-such-detector";
  CHECK_THROWS_AS(StateEstimator(s), std::invalid_argument);
  s = schmittSettings("eskf");
  s.robot.model = "robot.urdf";
  CHECK_THROWS_WITH(StateEstimator(s), Catch::Contains("robot model 'robot.urdf'"));
  CHECK_THROWS_AS(StateEstimator(schmittSettings("eskf"), 0), std::invalid_argument);
  Settings any;  // no estimator named: the chapter's invariant EKF
  any.pipeline.contact = "schmitt";
  CHECK(StateEstimator(any).estimatorName() == "invariant-ekf");
}

TEST_CASE("manager: stateAt interpolates inside the buffer, ages after it, refuses before it",
          "[57.11][physics]") {
  const io::Log& log = trotLog();
  StateEstimator manager(schmittSettings("invariant-ekf"), 100);
  CHECK_THROWS_AS(manager.stateAt(0.0), std::out_of_range);
  eval::Trajectory states;
  for (std::size_t k = 0; k < 250; ++k) states.push_back(feed(manager, log.rows[k]).x);
  REQUIRE(manager.buffered() == 100);
  CHECK(manager.oldestTime() == states[150].t);

  // At a buffered state: that state.
  StateQuery at = manager.stateAt(states[200].t);
  CHECK(sameState(at.x, states[200], 0.0));
  CHECK(at.age == 0.0);
  CHECK_FALSE(at.interpolated);
  CHECK(sameState(manager.stateAt(states[150].t).x, states[150], 0.0));

  // Between two: p and v linear, the attitude by slerp, age 0.
  const EstimateSample& a = states[210];
  const EstimateSample& b = states[211];
  const double t = a.t + 0.25 * (b.t - a.t);
  const StateQuery mid = manager.stateAt(t);
  CHECK(mid.interpolated);
  CHECK(mid.age == 0.0);
  CHECK(mid.x.t == t);
  CHECK((mid.x.p - (0.75 * a.p + 0.25 * b.p)).norm() < 1e-12);
  CHECK((mid.x.v - (0.75 * a.v + 0.25 * b.v)).norm() < 1e-12);
  CHECK(mid.x.q.angularDistance(a.q) == Approx(0.25 * a.q.angularDistance(b.q)).margin(1e-12));
  CHECK(mid.x.q.angularDistance(b.q) == Approx(0.75 * a.q.angularDistance(b.q)).margin(1e-12));

  // Nearest: the closer of the two, with its signed age.
  const StateQuery near_a = manager.stateAt(t, true);
  CHECK(sameState(near_a.x, a, 0.0));
  CHECK(near_a.age == Approx(t - a.t));
  const double t_late = a.t + 0.8 * (b.t - a.t);
  const StateQuery near_b = manager.stateAt(t_late, true);
  CHECK(sameState(near_b.x, b, 0.0));
  CHECK(near_b.age < 0.0);

  // After the newest: the newest with its age, never extrapolated.
  const StateQuery late = manager.stateAt(states.back().t + 0.003);
  CHECK(sameState(late.x, states.back(), 0.0));
  CHECK(late.age == Approx(0.003));
  CHECK_FALSE(late.interpolated);

  // Before the oldest: refused, naming both times.
  CHECK_THROWS_WITH(manager.stateAt(states[149].t), Catch::Contains("before the oldest"));
  CHECK_THROWS_AS(manager.stateAt(std::nan("")), std::invalid_argument);

  manager.reset();
  CHECK(manager.buffered() == 0);
  CHECK_THROWS_AS(manager.stateAt(states.back().t), std::out_of_range);
}

TEST_CASE("manager: no heap allocation per update or query", "[57.11][physics]") {
  const io::Log& log = trotLog();
  for (const char* contact : {"schmitt", "fallback", "truth"}) {
    INFO(contact);
    Settings s = schmittSettings("invariant-ekf");
    s.pipeline.contact = contact;
    s.pipeline.settle_time = kRecommendedSettleTime;
    StateEstimator manager(s);
    std::vector<Samples> samples(1000);
    for (std::size_t k = 0; k < samples.size(); ++k) {
      samples[k] = samplesOf(log.rows[k]);
      for (int f = 0; f < io::kNumLegs; ++f) samples[k].forces.contact[f] = log.rows[k].contact[f];
    }
    feed(manager, log.rows.front());
    const long before = test::allocationCount();
    double sum = 0.0;
    for (std::size_t k = 1; k < samples.size(); ++k) {
      const EstimatorOutput& out =
          manager.update(samples[k].imu, samples[k].joints, samples[k].forces);
      sum += out.x.p.x();
      if (k >= 5) sum += manager.stateAt(samples[k].imu.t - 0.0025).x.p.x();  // an MPC 2.5 ms back
    }
    CHECK(test::allocationCount() == before);
    CHECK(std::isfinite(sum));
  }
}
