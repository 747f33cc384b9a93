// Section 57.6, methods 1 and 6 and the fallback chain: the gait clock against the simulator's
// gait rule, the kinematic detector on synthetic stance and swing feet (speed AND height, the
// ground height it tracks), the chain's order and its reports, and no allocation per update.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "estimation/contact/fallback_detector.hpp"
#include "estimation/contact/gait_clock.hpp"
#include "estimation/contact/grf_threshold.hpp"
#include "estimation/contact/kinematic_detector.hpp"
#include "estimation/contact/schmitt_trigger.hpp"
#include "sim/gait.hpp"

using namespace legkit;
using namespace legkit::contact;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

GaitSchedule scheduleOf(const sim::Gait& g) {
  GaitSchedule s;
  s.period = g.period;
  s.duty = g.duty;
  for (int i = 0; i < 4; ++i) s.offset[i] = g.offset[i];
  s.start = g.start;
  return s;
}

}  // namespace

TEST_CASE("gait clock: planned stance is the simulator's gait rule", "[57.6]") {
  for (sim::Gait g :
       {sim::Gait::trot(), sim::Gait::walk(1.5), sim::Gait::bound(), sim::Gait::stand()}) {
    g.start = 1.0;
    GaitClockDetector d(scheduleOf(g));
    CHECK(d.name() == "gait-clock");
    ContactSignals s;
    int stance = 0, samples = 0;
    for (int k = 0; k < 6000; ++k) {
      s.t = 0.00071 * k + 0.00013;  // off every phase boundary
      const ContactEstimate e = d.update(s);
      for (int leg = 0; leg < 4; ++leg) {
        INFO("period " << g.period << " duty " << g.duty << " leg " << leg << " t " << s.t);
        REQUIRE(e.feet[leg].usable());
        REQUIRE(e.feet[leg].contact == sim::gaitPhase(g, leg, s.t).stance);
        CHECK(e.feet[leg].probability == (e.feet[leg].contact ? 1.0 : 0.0));
        stance += e.feet[leg].contact;
        ++samples;
      }
    }
    // Over the 3.26 s after the start the stance fraction is the duty factor (the first second
    // stands): (1 + duty * 3.26) / 4.26 within a few samples' worth.
    const double expected = g.alwaysStance() ? 1.0 : (1.0 + g.duty * 3.26) / 4.26;
    CHECK(double(stance) / samples == Approx(expected).margin(0.03));
  }
}

TEST_CASE("gait clock: a foot the schedule does not know is a problem", "[57.6]") {
  GaitSchedule g;
  g.num_feet = 2;
  GaitClockDetector d(g);
  ContactSignals s;
  s.num_feet = 3;
  const ContactEstimate e = d.update(s);
  CHECK(e.feet[1].usable());
  CHECK(std::string(e.feet[2].problem) == "foot not in the gait schedule");
  GaitSchedule bad;
  bad.period = 0.0;
  CHECK_THROWS_AS(GaitClockDetector(bad), std::invalid_argument);
}

namespace {

// A robot standing at base height 0.3 m, four feet under the hips with their sphere centres
// 0.278 m below the base (contact point at z = 0 with the 0.022 m radius); the accelerometer reads
// gravity's reaction.
ContactSignals standing() {
  ContactSignals s;
  s.acc = Eigen::Vector3d(0.0, 0.0, 9.81);
  s.base.valid = true;
  s.base.p = Eigen::Vector3d(0, 0, 0.3);
  const double x[4] = {0.19, 0.19, -0.19, -0.19}, y[4] = {0.14, -0.14, 0.14, -0.14};
  for (int i = 0; i < 4; ++i) {
    s.feet[i].has_kinematics = true;
    s.feet[i].p_body = Eigen::Vector3d(x[i], y[i], -0.278);
  }
  return s;
}

std::array<bool, 4> contacts(const ContactEstimate& e) {
  return {e.feet[0].contact, e.feet[1].contact, e.feet[2].contact, e.feet[3].contact};
}

}  // namespace

TEST_CASE("kinematic detector: contact needs the foot both still and at ground height", "[57.6]") {
  KinematicParams p;
  p.v_thresh = 0.1;  // the raw criterion of the chapter: no low-pass
  p.speed_tau = 0.0;
  KinematicDetector d(p);  // 0.1 m/s, 0.03 m
  ContactSignals s = standing();
  s.dt = 0.001;
  CHECK(contacts(d.update(s)) == std::array<bool, 4>{true, true, true, true});
  CHECK(d.groundHeight() == Approx(0.0).margin(1e-12));  // the lowest foot's contact point

  s.feet[0].v_body = Eigen::Vector3d(0.5, 0, 0);       // FL swinging low: fast -> not down
  s.feet[1].p_body.z() += 0.08;                        // FR at the top of its arc: still, high
  s.feet[2].v_body = Eigen::Vector3d(0.0, 0.0, 0.09);  // RL: slow enough
  s.feet[3].p_body.z() += 0.029;                       // RR: low enough
  CHECK(contacts(d.update(s)) == std::array<bool, 4>{false, false, true, true});

  // Criterion 1 is the WORLD foot velocity: a base turning at 1 rad/s moves a still leg's foot
  // at |omega x r| = 0.24 m/s; the leg's joints cancelling it, v_b = -omega x p_b, keep it down.
  s = standing();
  s.gyro = Eigen::Vector3d(0, 0, 1.0);
  CHECK(contacts(d.update(s)) == std::array<bool, 4>{false, false, false, false});
  for (int i = 0; i < 4; ++i) s.feet[i].v_body = -s.gyro.cross(s.feet[i].p_body);
  CHECK(contacts(d.update(s)) == std::array<bool, 4>{true, true, true, true});
  // And the base velocity, in the world, through R: a base moving at 0.5 m/s with the feet
  // sweeping back at 0.5 m/s in a body frame yawed by 90 degrees.
  s = standing();
  s.base.R = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  s.base.v = Eigen::Vector3d(0, 0.5, 0);  // world +y = body +x
  for (int i = 0; i < 4; ++i) s.feet[i].v_body = Eigen::Vector3d(-0.5, 0, 0);
  CHECK(contacts(d.update(s)) == std::array<bool, 4>{true, true, true, true});
}

TEST_CASE("kinematic detector: the foot speed is low-passed with time constant speed_tau",
          "[57.6]") {
  KinematicDetector d;  // 0.2 m/s, 5 ms
  ContactSignals s = standing();
  s.dt = 0.001;
  CHECK(d.update(s).feet[0].contact);
  // FL starts moving at 0.5 m/s: the filtered speed is 0.5 (1 - (5/6)^n) after n samples
  // (alpha = 1 ms / 6 ms), above 0.2 m/s from n = 3 on ((5/6)^3 = 0.579 < 0.6).
  s.feet[0].v_body = Eigen::Vector3d(0.5, 0, 0);
  CHECK(d.update(s).feet[0].contact);
  CHECK(d.update(s).feet[0].contact);
  CHECK_FALSE(d.update(s).feet[0].contact);
  // A problem restarts the filter: the next usable sample is taken as it is.
  s.feet[0].has_kinematics = false;
  CHECK_FALSE(d.update(s).feet[0].usable());
  s.feet[0].has_kinematics = true;
  s.feet[0].v_body.setZero();
  CHECK(d.update(s).feet[0].contact);
  KinematicParams bad;
  bad.speed_tau = -1.0;
  CHECK_THROWS_AS(KinematicDetector(bad), std::invalid_argument);
}

TEST_CASE("kinematic detector: z_ground follows the judged-down feet, re-anchors after a step",
          "[57.6]") {
  KinematicParams p;
  p.ground_tau = 0.1;
  KinematicDetector d(p);
  ContactSignals s = standing();
  s.dt = 0.001;
  d.update(s);
  // The base estimate's height and velocity do not enter: a 1 m height error and a 0.5 m/s
  // velocity error change nothing.
  s.base.p.z() += 1.0;
  s.base.v = Eigen::Vector3d(0.5, 0.0, -0.3);
  CHECK(contacts(d.update(s)) == std::array<bool, 4>{true, true, true, true});
  CHECK(d.groundHeight() == Approx(0.0).margin(1e-12));
  // The feet read 2 cm higher under the base with no leg velocity (an offset, not a motion): the
  // feet (still judged down: 2 cm < 3 cm) pull z_ground along with time constant 0.1 s: after
  // 0.5 s within 1 - e^-5 of it.
  for (int i = 0; i < 4; ++i) s.feet[i].p_body.z() += 0.02;
  for (int k = 0; k < 500; ++k) CHECK(d.update(s).feet[0].contact);
  CHECK(d.groundHeight() == Approx(0.02 * (1.0 - std::pow(0.1 / 0.101, 500))).epsilon(1e-9));
  CHECK(d.groundHeight() > 0.0198);
  // The legs reach 5 cm lower at once (the whole robot stepped down): nothing is within 3 cm of
  // z_ground; the still feet re-anchor it and are down from the next sample on.
  for (int i = 0; i < 4; ++i) s.feet[i].p_body.z() -= 0.05;
  CHECK(contacts(d.update(s)) == std::array<bool, 4>{false, false, false, false});
  CHECK(d.groundHeight() == Approx(-0.03).margin(1e-12));
  CHECK(contacts(d.update(s)) == std::array<bool, 4>{true, true, true, true});
  d.reset();
  CHECK(std::isnan(d.groundHeight()));
}

TEST_CASE("kinematic detector: its problems", "[57.6]") {
  KinematicDetector d;
  ContactSignals s = standing();
  s.base.valid = false;
  ContactEstimate e = d.update(s);
  for (int i = 0; i < 4; ++i) CHECK(std::string(e.feet[i].problem) == "no base estimate");
  CHECK(std::isnan(d.groundHeight()));  // nothing usable yet
  s.base.valid = true;
  s.base.v.x() = kNaN;
  CHECK(std::string(d.update(s).feet[3].problem) == "base not finite");
  s.base.v.x() = 0.0;
  s.feet[1].has_kinematics = false;
  s.feet[2].v_body.y() = kNaN;
  e = d.update(s);
  CHECK(std::string(e.feet[1].problem) == "no leg kinematics");
  CHECK(std::string(e.feet[2].problem) == "kinematics not finite");
  CHECK(e.feet[0].contact);
  CHECK(e.feet[3].contact);
}

namespace {

std::vector<std::unique_ptr<ContactDetector>> chain() {
  std::vector<std::unique_ptr<ContactDetector>> c;
  c.push_back(std::make_unique<SchmittDetector>());
  c.push_back(std::make_unique<KinematicDetector>());
  GaitSchedule g;
  g.period = 1.0;
  g.duty = 0.5;
  g.offset = {0.0, 0.0, 0.0, 0.0};
  c.push_back(std::make_unique<GaitClockDetector>(g));
  return c;
}

}  // namespace

TEST_CASE("fallback: per foot the first usable detector, every hand-over counted", "[57.6]") {
  FallbackDetector d(chain());
  CHECK(d.name() == "schmitt>kinematic>gait-clock");
  ContactSignals s = standing();
  s.base.valid = false;  // the kinematic detector cannot decide
  s.feet[0].force = 100.0;
  s.feet[1].force = kNaN;   // -> kinematic (no base) -> gait clock
  s.feet[2].force = -50.0;  // "force negative"
  s.feet[3].force = 10.0;
  for (int k = 0; k < 10; ++k) {
    s.t = 0.001 * k;
    s.dt = k == 0 ? 0.0 : 0.001;
    const ContactEstimate e = d.update(s);
    CHECK(e.feet[1].contact);  // the gait clock: stance in the first half period
    CHECK(e.feet[1].usable());
  }
  CHECK(d.source() == std::array<int, kMaxFeet>{0, 2, 2, 0, -1, -1, -1, -1});
  const FallbackReports& r = d.reports();
  CHECK(r.answered[0][0] == 10);
  CHECK(r.failed[1][0] == 10);
  CHECK(r.failed[1][1] == 10);
  CHECK(r.answered[1][2] == 10);
  CHECK(r.failed[3][0] == 0);
  CHECK(r.first.foot == 1);
  CHECK(r.first.t == 0.0);
  CHECK(r.first.detector == 0);
  CHECK(std::string(r.first.problem) == "no force reading");
  CHECK(r.last.foot == 2);
  CHECK(r.last.t == Approx(0.009));
  CHECK(r.last.detector == 1);
  CHECK(std::string(r.last.problem) == "no base estimate");

  // The base estimate arrives: foot 1 goes to the kinematic detector (still at ground height).
  s.base.valid = true;
  s.t = 0.01;
  s.dt = 0.001;
  CHECK(d.update(s).feet[1].contact);
  CHECK(d.source()[1] == 1);
  // The sensor comes back: the foot returns to the Schmitt trigger (60 N: not yet on).
  s.feet[1].force = 60.0;
  s.t = 0.011;
  const ContactEstimate e = d.update(s);
  CHECK(d.source()[1] == 0);
  CHECK_FALSE(e.feet[1].contact);
  d.reset();
  CHECK(d.reports().first.problem == nullptr);
  CHECK(d.reports().failed[1][0] == 0);
}

TEST_CASE("fallback: when nothing can decide the foot carries the last problem", "[57.6]") {
  std::vector<std::unique_ptr<ContactDetector>> c;
  c.push_back(std::make_unique<GrfThresholdDetector>());
  c.push_back(std::make_unique<KinematicDetector>());
  FallbackDetector d(std::move(c));
  ContactSignals s;  // no force, no base
  s.num_feet = 1;
  const ContactEstimate e = d.update(s);
  CHECK_FALSE(e.feet[0].usable());
  CHECK(std::string(e.feet[0].problem) == "no base estimate");
  CHECK(d.source()[0] == -1);
  CHECK(d.reports().undecided[0] == 1);
  CHECK_THROWS_AS(FallbackDetector({}), std::invalid_argument);
}

TEST_CASE("no detector allocates in update()", "[57.6]") {
  ContactSignals s = standing();
  s.has_joints = s.has_torque = true;
  for (int l = 0; l < 4; ++l) s.q.segment<3>(3 * l) << 0.0, 0.8, -1.6;
  for (int i = 0; i < 4; ++i) s.feet[i].force = 60.0;
  s.dt = 0.001;
  std::vector<std::unique_ptr<ContactDetector>> all;
  all.push_back(std::make_unique<GaitClockDetector>(GaitSchedule{}));
  all.push_back(std::make_unique<GrfThresholdDetector>());
  all.push_back(
      std::make_unique<GrfThresholdDetector>(GrfThresholdParams{}, ForceSource::kJointTorque));
  all.push_back(std::make_unique<SchmittDetector>());
  all.push_back(std::make_unique<SchmittDetector>(SchmittParams{}, ForceSource::kJointTorque));
  all.push_back(std::make_unique<KinematicDetector>());
  all.push_back(std::make_unique<FallbackDetector>(chain()));
  for (const auto& d : all) {
    INFO(d->name());
    d->update(s);  // first sample
    const long before = test::allocationCount();
    for (int k = 0; k < 10; ++k) {
      s.t += 0.001;
      d->update(s);
    }
    CHECK(test::allocationCount() == before);
  }
}
