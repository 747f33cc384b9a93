// The estimators on detected contacts (57.6): the pipeline row -> signals -> detector -> input,
// against the old path on the log's flags, on a log without flags, and its silence watch.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <memory>

#include "estimation/contact/schmitt_trigger.hpp"
#include "estimation/contact_pipeline.hpp"
#include "estimation/estimators.hpp"
#include "eval/consistency.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "sim/physics_simulator.hpp"

// This program counts its heap allocations (the header defines operator new: this file only).
#include "allocation_counter.hpp"

using namespace legkit;

namespace {

sim::PhysicsOptions trotOptions(double duration) {
  sim::PhysicsOptions o = sim::PhysicsOptions::forScenario("physics-trot");
  o.duration = duration;
  o.seed = 7;
  return o;
}

// A short physics trot (MuJoCo), the same for the tests of this file that need one.
const io::Log& trotLog() {
  static const io::Log log = sim::simulatePhysics(trotOptions(3.0)).log;
  return log;
}

// The scenario's gait as a robot's planner would publish it (the simulator starts the clock at
// stand_time).
contact::GaitSchedule plannedGait(const sim::PhysicsScenario& s) {
  contact::GaitSchedule g;
  g.period = s.gait.period;
  g.duty = s.gait.duty;
  for (int foot = 0; foot < 4; ++foot) g.offset[foot] = s.gait.offset[foot];
  g.start = s.stand_time;
  return g;
}

}  // namespace

TEST_CASE("pipeline: contact 'truth' gives every estimator exactly the old path's estimates",
          "[57.6][physics]") {
  const io::Log& log = trotLog();
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics());
  PipelineOptions options;  // the log's flags, slip check without reaction
  options.rolling_foot = false;
  ContactPipeline pipeline(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, options);
  CHECK(pipeline.source() == "truth");
  const EstimateSample x0 = eval::initialState(log);
  for (const std::string& name : estimatorNames()) {
    INFO(name);
    const std::unique_ptr<Estimator> e = makeEstimator(name);
    const eval::RunResult old_path = eval::runOnLog(*e, log, frontend, x0);
    const eval::RunResult piped = eval::runOnLog(*e, log, pipeline, x0);
    REQUIRE_FALSE(piped.failed());
    REQUIRE(piped.trajectory.size() == old_path.trajectory.size());
    bool identical = true;
    for (std::size_t k = 0; k < log.rows.size(); ++k) {
      const EstimateSample& a = old_path.trajectory[k];
      const EstimateSample& b = piped.trajectory[k];
      identical = identical && a.p == b.p && a.v == b.v && a.q.coeffs() == b.q.coeffs();
    }
    CHECK(identical);
    CHECK(piped.contact_source == "truth");
    REQUIRE(piped.detected_contact.size() == log.rows.size());
    bool flags = true;
    for (std::size_t k = 0; k < log.rows.size(); ++k) {
      for (int foot = 0; foot < 4; ++foot) {
        flags = flags && piped.detected_contact[k][foot] == log.rows[k].contact[foot];
      }
    }
    CHECK(flags);
    CHECK(piped.health[Fault::kNoContact] == 0);
  }
}

TEST_CASE("pipeline: on the Schmitt trigger (foot sensor) every filter finishes near the truth",
          "[57.6][physics]") {
  const io::Log& log = trotLog();
  const EstimateSample x0 = eval::initialState(log);
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics());
  PipelineOptions options;
  options.contact = "schmitt";
  for (const slip::SlipReaction reaction :
       {slip::SlipReaction::kNone, slip::SlipReaction::kInflate}) {
    options.slip = reaction;
    ContactPipeline pipeline(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, options,
                             std::make_unique<contact::SchmittDetector>());
    for (const char* name : {"leg-odometry", "linear-kf", "eskf", "invariant-ekf", "tsif"}) {
      INFO(name << ", slip reaction " << slip::slipReactionName(reaction));
      const std::unique_ptr<Estimator> e = makeEstimator(name);
      const eval::RunResult run = eval::runOnLog(*e, log, pipeline, x0);
      REQUIRE_FALSE(run.failed());
      CHECK(run.contact_source == "schmitt");
      CHECK(run.slip.size() == log.rows.size());
      // Detected: while trotting (from 0.5 s after the stand, whose four-foot load of about 37 N
      // a foot stays below F_high = 50 N) the sensor's flags agree with the truth on most rows;
      // the trigger is late by its hold time and the sensor's noise.
      int agree = 0, trotting = 0;
      for (std::size_t k = 0; k < log.rows.size(); ++k) {
        if (log.rows[k].t < trotOptions(3.0).scenario.stand_time + 0.5) continue;
        for (int foot = 0; foot < 4; ++foot) {
          agree += run.detected_contact[k][foot] == log.rows[k].gt_feet[foot].contact;
          ++trotting;
        }
      }
      CHECK(agree > 0.9 * trotting);
      // And the estimate is as good as on the truth, within a few centimetres over 3 s.
      const std::unique_ptr<Estimator> t = makeEstimator(name);
      const eval::Metrics on_truth =
          eval::compare(log, eval::runOnLog(*t, log, frontend, x0).trajectory);
      const eval::Metrics on_schmitt = eval::compare(log, run.trajectory);
      INFO("position RMSE " << on_schmitt.position_rmse << " m (truth flags "
                            << on_truth.position_rmse << " m)");
      CHECK(on_schmitt.position_rmse < on_truth.position_rmse + 0.03);
      CHECK(on_schmitt.velocity_rmse < on_truth.velocity_rmse + 0.05);
    }
  }
}

TEST_CASE("pipeline: one gyro glitch is not rolled into the feet (the admitted sample is)",
          "[57.6][physics]") {
  // A stand: the feet never lift, so a foot rolled away stays away (the 10 s stand lost
  // 38000 contacts and 0.8 m to one sample).
  sim::PhysicsOptions stand = sim::PhysicsOptions::forScenario("physics-stand");
  stand.duration = 3.0;
  stand.seed = 7;
  const io::Log clean = sim::simulatePhysics(stand).log;
  io::Log glitched = clean;
  glitched.rows[glitched.rows.size() / 2].gyro = Eigen::Vector3d(1e6, 0.0, 0.0);  // out of range
  PipelineOptions options;  // the log's flags, the rolling foot on
  options.rolling_foot = true;
  const auto run = [&](const io::Log& log) {
    ContactPipeline pipeline(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, options);
    const std::unique_ptr<Estimator> e = makeEstimator("eskf");
    return eval::runOnLog(*e, log, pipeline, eval::initialState(log));
  };
  const eval::RunResult a = run(clean);
  const eval::RunResult b = run(glitched);
  REQUIRE_FALSE(b.failed());
  // The filter holds the previous sample over the glitch's interval, and so does the rolling
  // foot: the estimates differ by far less than a millimetre.
  CHECK((a.trajectory.back().p - b.trajectory.back().p).norm() < 1e-4);
}

TEST_CASE("pipeline: a log without contact columns runs on a detector, not on dead reckoning",
          "[57.6][physics]") {
  // Long enough for the IMU alone to drift visibly.
  io::Log log = sim::simulatePhysics(trotOptions(15.0)).log;
  log.layout.contact = false;
  for (io::LogRow& row : log.rows) row.contact.fill(false);
  const EstimateSample x0 = eval::initialState(log);

  // The log's flags are asked for, and there are none: an error, never silence.
  CHECK_THROWS_WITH(ContactPipeline(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, {}),
                    Catch::Matchers::Contains("no contact columns"));

  // The recommended chain by name; with the force columns gone too, it falls back to the
  // momentum observer (joint torques) for every foot and sample.
  contact::DetectorContext context;
  context.gait = plannedGait(trotOptions(15.0).scenario);
  PipelineOptions options;
  options.contact = "fallback";
  ContactPipeline pipeline(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, options,
                           context);
  CHECK(pipeline.source() == "schmitt>momentum-observer>kinematic>gait-clock");
  io::Log no_force = log;
  no_force.layout.force = false;
  ContactPipeline torque_only(no_force.layout, model::QuadrupedKinematics(), FrontendNoise{},
                              options, context);
  const std::unique_ptr<Estimator> eskf = makeEstimator("eskf");
  const eval::RunResult detected = eval::runOnLog(*eskf, log, pipeline, x0);
  const eval::RunResult from_torques = eval::runOnLog(*eskf, no_force, torque_only, x0);
  REQUIRE_FALSE(detected.failed());
  REQUIRE_FALSE(from_torques.failed());
  CHECK(detected.health[Fault::kNoContact] == 0);
  // The momentum observer's 30 N threshold is below a standing foot's load (about 37 N): the
  // stand before the trot is in contact on the torques alone, no silence.
  CHECK(from_torques.health[Fault::kNoContact] == 0);
  // The old path on this log: no feet at all, the filter integrates the IMU alone.
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics());
  const eval::RunResult blind = eval::runOnLog(*eskf, log, frontend, x0);
  const eval::Metrics without = eval::compare(log, blind.trajectory);
  for (const eval::RunResult* run : {&detected, &from_torques}) {
    const eval::Metrics with = eval::compare(log, run->trajectory);
    INFO("position RMSE on detected contacts " << with.position_rmse << " m, without feet "
                                               << without.position_rmse << " m");
    CHECK(with.position_rmse < 0.1 * without.position_rmse);
    CHECK(with.velocity_rmse < 0.25 * without.velocity_rmse);
  }
}

TEST_CASE("pipeline: no stance foot for longer than the bound is counted once per stretch",
          "[57.6][physics]") {
  io::Log log = trotLog();
  // Silence the flags over [1.0, 1.7) s (0.7 s: beyond the 0.5 s bound) and [2.0, 2.4) s (0.4 s:
  // within it).
  for (io::LogRow& row : log.rows) {
    if ((row.t >= 1.0 && row.t < 1.7) || (row.t >= 2.0 && row.t < 2.4)) row.contact.fill(false);
  }
  ContactPipeline pipeline(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, {});
  const std::unique_ptr<Estimator> eskf = makeEstimator("eskf");
  const eval::RunResult run = eval::runOnLog(*eskf, log, pipeline, eval::initialState(log));
  REQUIRE_FALSE(run.failed());
  CHECK(run.health[Fault::kNoContact] == 1);
  CHECK(run.health.last_fault == Fault::kNoContact);
  // Counted at the first row beyond the bound: the last stance row is t = 0.999 s.
  CHECK(run.health.last_fault_t == Approx(1.5).margin(2e-3));
  CHECK(run.ok());  // a warning, not a recovery
  CHECK_THAT(eval::describe(run.health),
             Catch::Matchers::Contains("1 no contact for longer than the bound"));

  PipelineOptions tight;
  tight.no_contact_bound = 0.3;
  ContactPipeline strict(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, tight);
  CHECK(eval::runOnLog(*eskf, log, strict, eval::initialState(log)).health[Fault::kNoContact] == 2);
  tight.no_contact_bound = 0.0;
  CHECK_THROWS_WITH(
      ContactPipeline(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, tight),
      Catch::Matchers::Contains("no_contact_bound"));
}

TEST_CASE("frontend: a detector sees what the robot measured, never the contact or truth columns",
          "[57.6][physics]") {
  const io::Log& log = trotLog();
  const model::QuadrupedKinematics kinematics;
  const LogFrontend frontend(log.layout, kinematics);
  io::LogRow row = log.rows[1500];
  contact::BaseFeedback base;
  base.valid = true;
  base.v = Eigen::Vector3d(0.5, 0, 0);
  const contact::ContactSignals s = frontend.signals(row, 1e-3, base);
  CHECK(s.num_feet == 4);
  CHECK(s.has_joints);
  CHECK(s.has_torque == log.layout.torque);
  CHECK(s.base.v == base.v);
  CHECK(s.q == row.q);
  for (int foot = 0; foot < 4; ++foot) {
    CHECK(s.feet[foot].force == row.force[foot]);
    CHECK(s.feet[foot].has_kinematics);
    const Eigen::Vector3d q = row.q.segment<3>(3 * foot);
    CHECK(s.feet[foot].p_body == kinematics.footPosition(foot, q));
    CHECK(s.feet[foot].v_body == kinematics.footJacobian(foot, q) * row.dq.segment<3>(3 * foot));
  }
  // Flipping the flags and the truth changes nothing a detector sees.
  row.contact = {!row.contact[0], !row.contact[1], !row.contact[2], !row.contact[3]};
  row.gt_p += Eigen::Vector3d(1, 2, 3);
  row.gt_feet[0].contact = !row.gt_feet[0].contact;
  row.gt_feet[0].normal_force += 100.0;
  const contact::ContactSignals flipped = frontend.signals(row, 1e-3, base);
  for (int foot = 0; foot < 4; ++foot) {
    CHECK(flipped.feet[foot].force == s.feet[foot].force);
    CHECK(flipped.feet[foot].p_body == s.feet[foot].p_body);
  }
  // Without a force column the force is NaN (no sensor), not 0 (a foot in the air).
  io::LogLayout no_force = log.layout;
  no_force.force = false;
  const LogFrontend blind(no_force, kinematics);
  CHECK(std::isnan(blind.signals(row, 1e-3, base).feet[2].force));
}

TEST_CASE("frontend: the detector's answer weights each foot by p_c; unsure feet are left out",
          "[57.6][physics]") {
  const io::Log& log = trotLog();
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics());
  const io::LogRow& row = log.rows[1500];
  contact::ContactEstimate answer;
  answer.num_feet = 4;
  answer.feet[0] = {true, 1.0};
  answer.feet[1] = {true, 0.6};
  answer.feet[2] = {true, 0.04};  // below min_probability 0.05
  answer.feet[3] = {true, 1.0, 0.0, "force is NaN"};
  const contact::SoftContactParams soft;
  const StepInput in = frontend.input(row, 1e-3, answer, soft);
  REQUIRE(in.num_contacts == 2);
  CHECK(in.contacts[0].foot == 0);
  CHECK(in.contacts[1].foot == 1);
  // The hard-flag measurement of foot 1, then R / (p_c + eps) + R_swing (1 - p_c).
  io::LogRow flagged = row;
  flagged.contact = {false, true, false, false};
  io::LogLayout with_flags = log.layout;
  with_flags.contact = true;
  const StepInput hard = LogFrontend(with_flags, model::QuadrupedKinematics()).input(flagged, 1e-3);
  REQUIRE(hard.num_contacts == 1);
  const Eigen::Matrix3d expected =
      hard.contacts[0].cov / 0.61 + 0.05 * 0.05 * 0.4 * Eigen::Matrix3d::Identity();
  CHECK((in.contacts[1].cov - expected).norm() < 1e-15);
  CHECK(in.contacts[1].p_body == hard.contacts[0].p_body);
  CHECK(in.contacts[0].probability == 1.0);
  CHECK(in.contacts[1].probability == 0.6);
  CHECK(in.t == row.t);
  CHECK(in.imu.w_m == row.gyro);
}

TEST_CASE("pipeline: a step never allocates, whatever the detector and the slip reaction",
          "[57.6][physics]") {
  const io::Log& log = trotLog();
  contact::DetectorContext context;
  context.gait = plannedGait(trotOptions(3.0).scenario);
  for (const char* contact : {"truth", "schmitt", "fallback", "kinematic", "momentum-observer"}) {
    for (const slip::SlipReaction reaction :
         {slip::SlipReaction::kNone, slip::SlipReaction::kInflate, slip::SlipReaction::kImuOnly}) {
      INFO(contact << ", " << slip::slipReactionName(reaction));
      PipelineOptions options;
      options.contact = contact;
      options.slip = reaction;
      options.settle_time = kRecommendedSettleTime;
      ContactPipeline pipeline(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, options,
                               context);
      const std::unique_ptr<Estimator> eskf = makeEstimator("eskf");
      eskf->reset(eval::initialState(log));
      pipeline.reset();
      const long before = test::allocationCount();
      for (std::size_t k = 0; k < log.rows.size(); ++k) {
        const double dt = k == 0 ? 0.0 : log.rows[k].t - log.rows[k - 1].t;
        eskf->step(pipeline.step(log.rows[k], dt, eskf->estimate(), eskf->covariance()));
      }
      CHECK(test::allocationCount() == before);
    }
  }
}

TEST_CASE("settling: the factor on p_c is 0 until the settling time after touchdown, then 1",
          "[57.6]") {
  CHECK(settleWeight(0.0, 0.08) == 0.0);  // the touchdown row
  CHECK(settleWeight(0.079, 0.08) == 0.0);
  CHECK(settleWeight(0.08, 0.08) == 1.0);
  CHECK(settleWeight(0.5, 0.08) == 1.0);
  CHECK(settleWeight(std::numeric_limits<double>::infinity(), 0.08) == 1.0);  // down at the start
  CHECK(settleWeight(0.0, 0.0) == 1.0);                                       // off
  CHECK(settleWeight(0.001, 0.0) == 1.0);
  CHECK(PipelineOptions{}.settle_time == 0.0);  // off unless asked for
  CHECK(kRecommendedSettleTime == 0.08);
}

TEST_CASE(
    "settling: a foot put down by the flags reaches the filters 80 ms later, a foot down "
    "at the first row at once",
    "[57.6][physics]") {
  const io::Log& log = trotLog();
  PipelineOptions options;  // the log's flags
  options.settle_time = kRecommendedSettleTime;
  ContactPipeline pipeline(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, options);
  const EstimateSample x0 = eval::initialState(log);
  std::array<double, 4> touchdown{};
  touchdown.fill(-1.0);  // down at the first row
  int touchdowns = 0, checked = 0;
  bool right = true;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const io::LogRow& row = log.rows[k];
    const double dt = k == 0 ? 0.0 : row.t - log.rows[k - 1].t;
    const StepInput& in = pipeline.step(row, dt, x0, std::nullopt);
    for (int foot = 0; foot < 4; ++foot) {
      if (k > 0 && row.contact[foot] && !log.rows[k - 1].contact[foot]) {
        touchdown[foot] = row.t;
        ++touchdowns;
      }
      // Every foot down is in the input (leg odometry takes it whole); a settling one at p_c = 0
      // with the measurement covariance of p_c = 0, which the p_c-weighted filters ignore.
      const ContactMeasurement* c = nullptr;
      for (const ContactMeasurement& m : in.stance()) c = m.foot == foot ? &m : c;
      const bool settled = touchdown[foot] < 0.0 || row.t - touchdown[foot] >= 0.08;
      right = right && (c != nullptr) == row.contact[foot];
      if (c) {
        right = right && c->probability == (settled ? 1.0 : 0.0);
        right = right && (settled || c->cov(0, 0) > 1e-4);  // swing_sigma^2 and more
      }
      checked += row.contact[foot] && !settled;
      // The source's answer itself is not delayed (the detector scores read it).
      right = right && pipeline.contacts().feet[foot].contact == row.contact[foot];
    }
  }
  CHECK(touchdowns > 10);
  CHECK(checked > 10 * 79);
  CHECK(right);

  options.settle_time = -0.01;
  CHECK_THROWS_WITH(
      ContactPipeline(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, options),
      Catch::Matchers::Contains("settle_time"));
}

TEST_CASE("settling: on a 10 s physics trot the ESKF's ANEES is at least halved, its error lower",
          "[57.6][physics][study]") {
  const io::Log log = sim::simulatePhysics(trotOptions(10.0)).log;
  const EstimateSample x0 = eval::initialState(log);
  contact::DetectorContext context;
  context.gait = plannedGait(trotOptions(10.0).scenario);
  for (const char* contact : {"truth", "fallback"}) {
    INFO(contact);
    PipelineOptions options;
    options.contact = contact;
    options.settle_time = kRecommendedSettleTime;
    ContactPipeline settled(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, options,
                            context);
    options.settle_time = 0.0;
    ContactPipeline unsettled(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, options,
                              context);
    const std::unique_ptr<Estimator> eskf = makeEstimator("eskf");
    const eval::RunResult with = eval::runOnLog(*eskf, log, settled, x0);
    const eval::RunResult without = eval::runOnLog(*eskf, log, unsettled, x0);
    REQUIRE_FALSE(with.failed());
    REQUIRE_FALSE(without.failed());
    const double anees_with = eval::normalisedAnees(with);
    const double anees_without = eval::normalisedAnees(without);
    const double rmse_with = eval::compare(log, with.trajectory).position_rmse;
    const double rmse_without = eval::compare(log, without.trajectory).position_rmse;
    INFO(contact << ": ANEES " << anees_without << " -> " << anees_with << ", position RMSE "
                 << rmse_without << " -> " << rmse_with << " m");
    CHECK(anees_with < 0.5 * anees_without);
    CHECK(rmse_with < rmse_without);
  }
}

TEST_CASE(
    "settling: the slip check sees a foot from its touchdown; only the filter's input holds its "
    "p_c at 0",
    "[57.6][57.7][physics]") {
  const io::Log& log = trotLog();
  contact::DetectorContext context;
  context.gait = plannedGait(trotOptions(3.0).scenario);
  for (const char* contact : {"truth", "fallback"}) {
    INFO(contact);
    PipelineOptions options;
    options.contact = contact;
    options.slip = slip::SlipReaction::kDrop;
    options.settle_time = kRecommendedSettleTime;
    ContactPipeline settled(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, options,
                            context);
    options.settle_time = 0.0;
    ContactPipeline unsettled(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, options,
                              context);
    std::array<double, 4> touchdown{};
    touchdown.fill(-1.0);  // down at the first row
    std::array<bool, 4> down{};
    int settling_rows = 0, slides_while_settling = 0;
    bool same_report = true, same_feet = true;
    for (std::size_t k = 0; k < log.rows.size(); ++k) {
      const io::LogRow& row = log.rows[k];
      const double dt = k == 0 ? 0.0 : row.t - log.rows[k - 1].t;
      // Both judged against the same estimate: the truth of the previous row.
      const io::LogRow& prev = log.rows[k == 0 ? 0 : k - 1];
      EstimateSample x;
      x.t = prev.t;
      x.q = prev.gt_q;
      x.v = prev.gt_v;
      x.p = prev.gt_p;
      const StepInput with = settled.step(row, dt, x, std::nullopt);
      const StepInput& without = unsettled.step(row, dt, x, std::nullopt);
      const slip::SlipReport& a = settled.slipReport();
      const slip::SlipReport& b = unsettled.slipReport();
      same_report = same_report && a.num_feet == b.num_feet && a.all_slipping == b.all_slipping;
      for (int i = 0; i < std::min(a.num_feet, b.num_feet); ++i) {
        same_report = same_report && a.feet[i].foot == b.feet[i].foot &&
                      a.feet[i].d2 == b.feet[i].d2 && a.feet[i].slipping == b.feet[i].slipping;
      }
      // The filter's input: the unsettled one, the feet put down less than 80 ms ago at p_c = 0.
      for (int foot = 0; foot < 4; ++foot) {
        const contact::FootContact& c = settled.contacts().feet[foot];
        const bool is_down = c.usable() && c.contact;
        if (k > 0 && is_down && !down[foot]) touchdown[foot] = row.t;
        down[foot] = is_down;
        const bool settling = is_down && touchdown[foot] >= 0.0 && row.t - touchdown[foot] < 0.08;
        settling_rows += settling;
        slides_while_settling += settling && a.slipping(foot);
      }
      same_feet = same_feet && with.num_contacts == without.num_contacts;
      for (int i = 0; i < std::min(with.num_contacts, without.num_contacts); ++i) {
        const ContactMeasurement& c = without.contacts[i];
        const ContactMeasurement& w = with.contacts[i];
        const bool settling = touchdown[c.foot] >= 0.0 && row.t - touchdown[c.foot] < 0.08;
        same_feet =
            same_feet && w.foot == c.foot && w.p_body == c.p_body &&
            w.probability == (settling ? 0.0 : c.probability) &&
            w.cov == (settling ? contact::softMeasurementCov(c.cov, 0.0, options.soft) : c.cov);
      }
    }
    INFO("rows with a settling foot " << settling_rows << ", of them found slipping "
                                      << slides_while_settling);
    CHECK(settling_rows > 10 * 79);
    CHECK(slides_while_settling > 0);  // touchdown skids, seen although the filter waits
    CHECK(same_report);
    CHECK(same_feet);
  }
}
