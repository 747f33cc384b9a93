// Section 57.6 against physics (sim/physics_simulator.hpp, MuJoCo): the force estimated from the
// joint torques on a standing robot against the true normal forces, and the detectors scored
// against the true contact (gt_feet[].contact, a normal force above 1 N) on a 10 s trot, with
// eval/contact_scores.hpp's definitions (those of `legkit study contact`). The detectors that need
// a base estimate get the true pose and velocity in its place. Every score is printed; run
//   build/tests/contact/test_contact_detectors_physics
// to see them.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "estimation/contact/detectors.hpp"
#include "estimation/contact/fallback_detector.hpp"
#include "estimation/contact/foot_force.hpp"
#include "estimation/contact/grf_threshold.hpp"
#include "estimation/contact/kinematic_detector.hpp"
#include "estimation/contact/schmitt_trigger.hpp"
#include "eval/contact_scores.hpp"
#include "model/quadruped.hpp"
#include "sim/physics_simulator.hpp"

using namespace legkit;
using namespace legkit::contact;

namespace {

constexpr unsigned kSeed = 13;

// What a robot measures at log row k, and (when with_base) the true base as the estimate.
ContactSignals signalsOf(const io::Log& log, std::size_t k, const model::QuadrupedKinematics& kin,
                         bool with_base) {
  const io::LogRow& row = log.rows[k];
  ContactSignals s;
  s.t = row.t;
  s.dt = k == 0 ? 0.0 : row.t - log.rows[k - 1].t;
  s.num_feet = 4;
  s.gyro = row.gyro;
  s.acc = row.acc;
  s.has_joints = log.layout.joints;
  s.q = row.q;
  s.dq = row.dq;
  s.has_torque = log.layout.torque;
  s.tau = row.tau;
  for (int i = 0; i < 4; ++i) {
    FootSignals& f = s.feet[i];
    if (log.layout.force) f.force = row.force[i];
    const Eigen::Vector3d q = row.q.segment<3>(3 * i), dq = row.dq.segment<3>(3 * i);
    f.has_kinematics = true;
    f.p_body = kin.footPosition(i, q);
    f.v_body = kin.footJacobian(i, q) * dq;
  }
  if (with_base) {
    s.base.valid = true;
    s.base.R = row.gt_q.toRotationMatrix();
    s.base.v = row.gt_v;
    s.base.p = row.gt_p;
  }
  return s;
}

// The detector's scores on the log; every answer must be usable (these logs have every column).
eval::ContactScores score(ContactDetector& d, const io::Log& log) {
  const model::QuadrupedKinematics kin;
  std::vector<double> t;
  std::vector<eval::FootFlags> detected, truth;
  int problems = 0;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const ContactEstimate e = d.update(signalsOf(log, k, kin, true));
    eval::FootFlags a{}, b{};
    for (int i = 0; i < 4; ++i) {
      problems += !e.feet[i].usable();
      a[i] = e.feet[i].contact;
      b[i] = log.rows[k].gt_feet[i].contact;
    }
    t.push_back(log.rows[k].t);
    detected.push_back(a);
    truth.push_back(b);
  }
  CHECK(problems == 0);
  const eval::ContactScores s = eval::scoreContacts(t, detected, truth, 4);
  std::cout << d.name() << ": F1 " << s.f1 << " (precision " << s.precision << ", recall "
            << s.recall << "), touchdown delay " << s.touchdown_delay_mean << " ms (p95 "
            << s.touchdown_delay_p95 << "), lift-off delay " << s.liftoff_delay_mean << " ms (p95 "
            << s.liftoff_delay_p95 << "), chatter " << s.chatter_per_min << " /min, missed "
            << s.missed_touchdowns << " + " << s.missed_liftoffs << " of " << s.touchdowns << " + "
            << s.liftoffs << " events\n";
  return s;
}

const sim::PhysicsResult& trot() {
  static const sim::PhysicsResult run = [] {
    sim::PhysicsOptions o = sim::PhysicsOptions::forScenario("physics-trot");
    o.duration = 10.0;
    o.seed = kSeed;
    return sim::simulatePhysics(o);
  }();
  return run;
}

}  // namespace

TEST_CASE("force from joint torques on a standing robot: the true normal forces, m g in all",
          "[57.6][physics]") {
  sim::PhysicsOptions o = sim::PhysicsOptions::forScenario("physics-stand");
  o.duration = 2.0;
  o.seed = kSeed;
  const sim::PhysicsResult run = sim::simulatePhysics(o);
  REQUIRE_FALSE(run.status.fell);
  const model::QuadrupedGeometry geo = model::QuadrupedGeometry::go2();
  const model::QuadrupedInertia inertia = model::QuadrupedInertia::go2();
  const FootForceFromTorque ff(geo, inertia);
  const model::QuadrupedKinematics kin(geo);
  const double mg = inertia.totalMass() * 9.81;  // 149.2 N
  const double n = static_cast<double>(run.log.rows.size());

  // The torques carry N(0, 0.1 N m) noise, mapped through J^-T (|J| ~ 0.2 m: ~0.5 N per foot),
  // and the model neglects the legs' small accelerations. With the accelerometer's tilt (noise
  // 0.04 m/s^2/sqrt(Hz): 1.3 m/s^2 per 1 kHz sample, a few degrees of tilt) the forces rotate a
  // little into and out of z, and its bias tilts the mean (the sum reads ~2.4 N low). Bounds
  // about twice what seeds 13-16 measure (printed).
  struct Bound {
    bool with_base;
    double mean_foot, worst_foot, mean_total, worst_total;  // [N]
  };
  for (const Bound b : {Bound{true, 1.2, 6.0, 1.5, 11.0}, Bound{false, 2.0, 12.0, 4.0, 40.0}}) {
    double foot_err = 0.0, worst_foot = 0.0, total = 0.0, worst_total = 0.0;
    for (std::size_t k = 0; k < run.log.rows.size(); ++k) {
      std::array<const char*, 4> why{};
      const auto f = ff.estimate(signalsOf(run.log, k, kin, b.with_base), &why);
      double sum = 0.0;
      for (int i = 0; i < 4; ++i) {
        REQUIRE(why[i] == nullptr);
        const double err = std::abs(f[i].z() - run.log.rows[k].gt_feet[i].normal_force);
        foot_err += err;
        worst_foot = std::max(worst_foot, err);
        sum += f[i].z();
      }
      total += sum;
      worst_total = std::max(worst_total, std::abs(sum - mg));
    }
    std::cout << "stand, attitude from "
              << (b.with_base ? "the base estimate" : "the accelerometer") << ": |f_z - f_n| mean "
              << foot_err / (4 * n) << " N, worst " << worst_foot << " N; sum of f_z mean "
              << total / n << " N, worst |sum - m g| " << worst_total << " N (m g = " << mg
              << " N)\n";
    CHECK(foot_err / (4 * n) < b.mean_foot);
    CHECK(worst_foot < b.worst_foot);
    CHECK(std::abs(total / n - mg) < b.mean_total);
    CHECK(worst_total < b.worst_total);
  }
}

TEST_CASE("Schmitt on the foot sensor: F1 against the physics trot, and no chatter",
          "[57.6][physics]") {
  const sim::PhysicsResult& run = trot();
  REQUIRE_FALSE(run.status.fell);
  // The kit's Go2 design (go2SchmittParams: 25 / 10 N, 5 / 5 ms; exercise 57.6.1 asks for one):
  // the chapter's F_high = 50 N is above what one foot of the 15.2 kg robot carries while it
  // stands on four (m g / 4 = 37 N), so the chapter's thresholds never see the first second's
  // stand.
  SchmittDetector schmitt(go2SchmittParams());
  GrfThresholdDetector plain;  // 30 N
  const eval::ContactScores s = score(schmitt, run.log);
  const eval::ContactScores p = score(plain, run.log);
  // Seed 13 measures F1 0.991 (the misses: the 5 ms hold after each touchdown and the ramp below
  // 25 N); 0.98 leaves room for another seed's noise, and is well above what a detector that
  // lost a touchdown's worth of samples per step would score (~0.97).
  CHECK(s.f1 > 0.98);
  CHECK(s.missed_touchdowns == 0);
  CHECK(s.missed_liftoffs == 0);
  // Touchdown: T_on after the force passes 25 N, which it does within 1-2 ms of the 1 N contact.
  CHECK(s.touchdown_delay_mean > 4.5);
  CHECK(s.touchdown_delay_p95 <= 8.0);
  // Chatter: the plain threshold toggles on the sensor's noise each time the force ramps through
  // 30 N (hundreds a minute); the trigger's 15 N band with 5 ms holds leaves none: the 4 toggles
  // it has in 10 s (24 a minute) are the four feet switching on T_on after the log's first sample,
  // where the truth has no event.
  CHECK(p.chatter_per_min > 200.0);
  CHECK(s.chatter_per_min < p.chatter_per_min / 10.0);
  CHECK(s.chatter_per_min < 60.0);

  // The chapter's defaults (50 / 20 N): precise, but blind to the stand (recall ~0.82).
  SchmittDetector chapter;
  const eval::ContactScores c = score(chapter, run.log);
  CHECK(c.precision > 0.99);
  CHECK(c.recall < 0.9);
}

TEST_CASE("detectors without a foot sensor on the physics trot", "[57.6][physics]") {
  const sim::PhysicsResult& run = trot();
  REQUIRE_FALSE(run.status.fell);
  // The force from joint torques against the true normal force: close in stance (the leg hardly
  // accelerates), except around touchdown; in swing the leg's acceleration, which the model
  // leaves out, reads as force.
  {
    const FootForceFromTorque ff(model::QuadrupedGeometry::go2(), model::QuadrupedInertia::go2());
    const model::QuadrupedKinematics kin;
    std::vector<double> stance, swing;
    for (std::size_t k = 0; k < run.log.rows.size(); ++k) {
      const auto f = ff.estimate(signalsOf(run.log, k, kin, true));
      for (int i = 0; i < 4; ++i) {
        const io::FootTruth& truth = run.log.rows[k].gt_feet[i];
        (truth.contact ? stance : swing).push_back(std::abs(f[i].z() - truth.normal_force));
      }
    }
    std::sort(stance.begin(), stance.end());
    std::sort(swing.begin(), swing.end());
    auto at = [](const std::vector<double>& v, double q) {
      return v[static_cast<std::size_t>(q * (v.size() - 1))];
    };
    std::cout << "force from joint torques, |f_z - f_n| in stance: median " << at(stance, 0.5)
              << " N, p95 " << at(stance, 0.95) << " N; in swing: median " << at(swing, 0.5)
              << " N, p95 " << at(swing, 0.95) << " N, worst " << swing.back() << " N\n";
    // Seed 13: stance median 1.0 N, p95 17 N.
    CHECK(at(stance, 0.5) < 2.0);
    CHECK(at(stance, 0.95) < 30.0);
  }
  // Forces from joint torques: the model leaves out the legs' accelerations, so a swing leg that
  // brakes reads tens of newtons, and an early touchdown loads the leg only as fast as the swing
  // controller's error grows. The chapter's 50 / 20 N band keeps the swing out (precision) at the
  // price of late touchdowns and the stand.
  SchmittDetector schmitt_torque({}, ForceSource::kJointTorque);
  const eval::ContactScores st = score(schmitt_torque, run.log);
  CHECK(st.f1 > 0.8);
  CHECK(st.precision > 0.99);
  GrfThresholdDetector plain_torque({}, ForceSource::kJointTorque);
  const eval::ContactScores pt = score(plain_torque, run.log);
  CHECK(pt.f1 > 0.85);
  CHECK(st.chatter_per_min < pt.chatter_per_min / 10.0);

  // Kinematic (speed AND height): F1 0.941 on seed 13, no chatter, ~21 ms late at touchdown
  // (the foot centre settles below 0.2 m/s) and ~22 ms late at lift-off (0.943, 22 and 19 ms when
  // it judged speed against the base velocity given, here the true one).
  KinematicDetector kinematic;
  const eval::ContactScores k = score(kinematic, run.log);
  CHECK(k.f1 > 0.92);
  CHECK(k.chatter_per_min < 30.0);
  CHECK(k.touchdown_delay_mean < 35.0);
}

namespace {

// The chicken-and-egg loop of 57.6 closed by the smallest filter that has it: the base velocity
// estimate integrates the accelerometer (R a_m + g, R the true attitude: gravity keeps roll and
// pitch observable) and is pulled toward the legs' velocity, -R (omega x B_p_f + B_v_f) averaged
// over the feet the detector judges down, with time constant 50 ms; its position integrates it.
// The detector sees that estimate as the previous step's base. Returns the scores and the mean
// |v_hat - v_true| over the last 5 s.
struct LoopResult {
  eval::ContactScores scores;
  double late_velocity_error = 0.0;  // [m/s]
};

LoopResult closedLoop(ContactDetector& d, const io::Log& log, const Eigen::Vector3d& v0_error) {
  const model::QuadrupedKinematics kin;
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  Eigen::Vector3d v_hat = log.rows[0].gt_v + v0_error, p_hat = log.rows[0].gt_p;
  std::vector<double> t;
  std::vector<eval::FootFlags> detected, truth;
  double late = 0.0;
  int n_late = 0;
  const double t_end = log.rows.back().t;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    ContactSignals s = signalsOf(log, k, kin, true);
    s.base.v = v_hat;
    s.base.p = p_hat;
    const ContactEstimate e = d.update(s);
    Eigen::Vector3d v_leg = Eigen::Vector3d::Zero();
    int n = 0;
    eval::FootFlags a{}, b{};
    for (int i = 0; i < 4; ++i) {
      a[i] = e.feet[i].usable() && e.feet[i].contact;
      b[i] = log.rows[k].gt_feet[i].contact;
      if (!a[i]) continue;
      v_leg -= s.base.R * (s.gyro.cross(s.feet[i].p_body) + s.feet[i].v_body);
      ++n;
    }
    v_hat += (s.base.R * s.acc + g) * s.dt;
    if (n > 0) v_hat += s.dt / (0.05 + s.dt) * (v_leg / n - v_hat);
    p_hat += v_hat * s.dt;
    if (s.t > t_end - 5.0) {
      late += (v_hat - log.rows[k].gt_v).norm();
      ++n_late;
    }
    t.push_back(s.t);
    detected.push_back(a);
    truth.push_back(b);
  }
  return {eval::scoreContacts(t, detected, truth, 4), late / n_late};
}

}  // namespace

TEST_CASE("kinematic detector in the loop: a base velocity 0.5 m/s off at the start",
          "[57.6][physics]") {
  // Issue 22 item 2: on a real Go1 trot `--contact kinematic` drifted 15 m over 13 m. The
  // detector judged speed against the estimate's velocity: once that is 0.2 m/s off, no foot looks
  // still, no foot corrects it, and it never comes back.
  const sim::PhysicsResult& run = trot();
  REQUIRE_FALSE(run.status.fell);
  for (const double error : {0.0, 0.5}) {
    KinematicDetector d;
    const LoopResult r = closedLoop(d, run.log, Eigen::Vector3d(error, 0.0, 0.0));
    std::cout << "kinematic in the loop, started " << error << " m/s off: F1 " << r.scores.f1
              << " (precision " << r.scores.precision << ", recall " << r.scores.recall
              << "), mean |v error| over the last 5 s " << r.late_velocity_error << " m/s\n";
    CHECK(r.scores.f1 > 0.9);
    CHECK(r.late_velocity_error < 0.1);
  }
}

TEST_CASE("the recommended fallback chain on a trot whose foot sensors fail", "[57.6][physics]") {
  // FR's sensor is lost (NaN) over [3, 5) s; RL's sticks at full scale (150 N) over [6, 8.5) s.
  io::Log log = trot().log;
  REQUIRE_FALSE(trot().status.fell);
  int lost = 0;
  for (io::LogRow& row : log.rows) {
    if (row.t >= 3.0 && row.t < 5.0) {
      row.force[1] = std::numeric_limits<double>::quiet_NaN();
      ++lost;
    }
    if (row.t >= 6.0 && row.t < 8.5) row.force[2] = 150.0;
  }
  DetectorContext context;
  const sim::PhysicsScenario scenario = sim::physicsScenarioByName("physics-trot");
  GaitSchedule gait;
  gait.period = scenario.gait.period;
  gait.duty = scenario.gait.duty;
  for (int i = 0; i < 4; ++i) gait.offset[i] = scenario.gait.offset[i];
  gait.start = scenario.stand_time;
  context.gait = gait;
  const std::unique_ptr<ContactDetector> d = makeDetector("fallback", context);
  REQUIRE(d->name() == "schmitt>momentum-observer>kinematic>gait-clock");
  const auto& chain = dynamic_cast<const FallbackDetector&>(*d);
  const eval::ContactScores s = score(*d, log);  // and every answer usable: decided every sample

  const FallbackReports& r = chain.reports();
  // The first hand-over: FR at the first row of the loss, from the Schmitt trigger (0).
  CHECK(r.first.foot == 1);
  CHECK(r.first.t == Approx(3.0));
  CHECK(r.first.detector == 0);
  CHECK(std::string(r.first.problem) == "no force reading");
  CHECK(r.failed[1][0] == lost);
  // The momentum observer, idle until then, restarts at the loss: "converging" for its 60 ms
  // settle time, when the kinematic detector answers; then it takes every sample.
  const long settle = std::lround(context.momentum.settle_time / 0.001);
  CHECK(r.answered[1][1] + r.answered[1][2] == lost);
  CHECK(r.answered[1][2] == Approx(settle).margin(1));
  CHECK(r.answered[1][3] == 0);
  // RL: a saturated reading is a valid one for stuck_time = 1 s, then the sensor is stuck until
  // the fault ends: the last hand-over is RL's, at the fault's last row.
  CHECK(r.last.foot == 2);
  CHECK(r.last.t == Approx(8.499));
  CHECK(std::string(r.last.problem) == "force stuck at saturation");
  CHECK(r.failed[2][0] == Approx(1500).margin(2));
  CHECK(r.answered[2][2] == Approx(settle).margin(1));
  for (int i = 0; i < 4; ++i) CHECK(r.undecided[i] == 0);
  // Lazy: the Schmitt trigger ran on every row, the momentum observer and the kinematic detector
  // only on the faults' rows (each restarted once per fault), the gait clock never.
  const long rows = static_cast<long>(log.rows.size());
  CHECK(r.ran[0] == rows);
  CHECK(r.ran[1] == r.failed[1][0] + r.failed[2][0]);
  CHECK(r.restarts[1] == 2);
  CHECK(r.ran[2] == Approx(2 * settle).margin(2));
  CHECK(r.restarts[2] == 2);
  CHECK(r.ran[3] == 0);
  std::cout << d->name() << " on the faulted trot: F1 " << s.f1 << "; runs per detector "
            << r.ran[0] << ", " << r.ran[1] << ", " << r.ran[2] << ", " << r.ran[3] << " of "
            << rows << " rows\n";
  // The chain keeps answering: F1 stays near the sensor's 0.991 (the momentum observer is ~10 ms
  // late at touchdown during the 2 s loss; the stuck sensor says "contact" through RL's swings of
  // its first second).
  CHECK(s.f1 > 0.96);

  // The former order, schmitt-torque second, for comparison (printed): at the chapter's 50 N it is
  // late at every touchdown.
  std::vector<std::unique_ptr<ContactDetector>> old;
  for (const char* n : {"schmitt", "schmitt-torque", "momentum-observer", "kinematic"})
    old.push_back(makeDetector(n, context));
  FallbackDetector former(std::move(old));
  const eval::ContactScores f = score(former, log);
  CHECK(f.f1 < s.f1);
}
