// Section 57.6, methods 2 and 3: the GRF threshold and the Schmitt trigger on hand-made force
// traces (switch times, hold times, chatter), every problem a force reading can have, and the
// force from joint torques against the equation of motion it inverts.
#include <rapidcheck.h>
#include <rapidcheck/catch.h>
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "estimation/contact/foot_force.hpp"
#include "estimation/contact/grf_threshold.hpp"
#include "estimation/contact/schmitt_trigger.hpp"
#include "model/floating_base_dynamics.hpp"

using namespace legkit;
using namespace legkit::contact;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The samples (index into `force`, dt = 1 ms) at which the trigger's state changes.
std::vector<int> switchSamples(SchmittTrigger& s, const std::vector<double>& force) {
  std::vector<int> at;
  bool state = s.state();
  for (std::size_t k = 0; k < force.size(); ++k) {
    if (s.update(force[k], 0.001) != state) at.push_back(static_cast<int>(k));
    state = s.state();
  }
  return at;
}

std::vector<double> concat(std::initializer_list<std::pair<int, double>> pieces) {
  std::vector<double> f;
  for (const auto& [n, value] : pieces) f.insert(f.end(), n, value);
  return f;
}

ContactSignals oneFoot(double force, double t, double dt) {
  ContactSignals s;
  s.t = t;
  s.dt = dt;
  s.num_feet = 1;
  s.feet[0].force = force;
  return s;
}

}  // namespace

TEST_CASE("Schmitt trigger: F_high held for more than T_on switches on, F_low for T_off off",
          "[57.6]") {
  SchmittTrigger s;  // 50 / 20 N, 5 / 5 ms
  // 0 N for 10 samples, 60 N from sample 10: held 1 ms at sample 10, 6 ms > 5 ms at sample 15.
  // 40 N (inside the band) changes nothing; 10 N from sample 30: off at sample 35.
  const std::vector<double> f = concat({{10, 0.0}, {15, 60.0}, {5, 40.0}, {10, 10.0}});
  CHECK(switchSamples(s, f) == std::vector<int>{15, 35});
}

TEST_CASE("Schmitt trigger: a hold of exactly T_on is not enough, an interruption restarts it",
          "[57.6]") {
  SchmittTrigger s;
  // 5 samples above F_high hold 5 ms (not > 5 ms): no switch. A dip to 45 N restarts the hold.
  const std::vector<double> f =
      concat({{5, 60.0}, {1, 0.0}, {4, 60.0}, {1, 45.0}, {5, 60.0}, {1, 30.0}, {6, 60.0}});
  // The last run of 6 samples is 17..22: switches at 22.
  CHECK(switchSamples(s, f) == std::vector<int>{22});
  // The other direction: on, then 5 samples below F_low and back: stays on.
  const std::vector<double> g = concat({{5, 10.0}, {1, 25.0}, {6, 10.0}});
  CHECK(switchSamples(s, g) == std::vector<int>{11});
  s.reset();
  CHECK_FALSE(s.state());
}

TEST_CASE("Schmitt trigger: other thresholds and hold times, zero hold", "[57.6]") {
  SchmittParams p;
  p.f_high = 80.0;
  p.f_low = 60.0;
  p.t_on = 0.0;    // on at the first sample above
  p.t_off = 0.01;  // off after 11 samples below
  SchmittTrigger s(p);
  const std::vector<double> f = concat({{3, 70.0}, {3, 81.0}, {20, 59.0}});
  CHECK(switchSamples(s, f) == std::vector<int>{3, 16});
  SchmittParams bad;
  bad.f_low = 60.0;  // above f_high = 50
  CHECK_THROWS_AS(SchmittTrigger(bad), std::invalid_argument);
  bad = SchmittParams{};
  bad.t_on = -0.001;
  CHECK_THROWS_AS(SchmittTrigger(bad), std::invalid_argument);
}

TEST_CASE("Both force detectors refuse force checks that cannot hold, naming themselves",
          "[57.6]") {
  using Catch::Matchers::Equals;
  // The reader's checks (ForceChecks, shared by both detectors' params): each spoiled, and why.
  const std::vector<std::pair<void (*)(ForceChecks&), std::string>> spoiled = {
      {+[](ForceChecks& c) { c.stuck_time = 0.0; }, "stuck_time must be positive"},
      {+[](ForceChecks& c) { c.negative_limit = 1.0; }, "negative_limit must be <= 0"}};
  for (const auto& [spoil, why] : spoiled) {
    GrfThresholdParams grf;
    SchmittParams schmitt;
    spoil(grf);
    spoil(schmitt);
    CHECK_THROWS_WITH(GrfThresholdDetector(grf), Equals("grf-threshold: " + why));
    CHECK_THROWS_WITH(SchmittDetector(schmitt), Equals("schmitt: " + why));
  }
  // The full scale, above each detector's own threshold.
  GrfThresholdParams grf;
  grf.saturation = grf.threshold;
  CHECK_THROWS_WITH(GrfThresholdDetector(grf),
                    Equals("grf-threshold: saturation must be above the threshold"));
  SchmittParams schmitt;
  schmitt.saturation = schmitt.f_high;
  CHECK_THROWS_WITH(SchmittDetector(schmitt), Equals("schmitt: saturation must be above f_high"));
}

TEST_CASE("Schmitt suppresses the chatter a plain threshold shows on a noisy force", "[57.6]") {
  // A stance's force: 0 N, a 50 ms ramp to 120 N, 200 ms flat, a 50 ms ramp down, 0 N; plus
  // N(0, 5 N) noise. The plain 30 N threshold toggles several times on each ramp where the noise
  // crosses it; the Schmitt trigger (band 20..50 N, 5 ms holds) toggles exactly twice.
  std::mt19937 rng(57);
  std::normal_distribution<double> noise(0.0, 5.0);
  std::vector<double> f;
  for (int k = 0; k < 100; ++k) f.push_back(0.0);
  for (int k = 0; k < 50; ++k) f.push_back(120.0 * k / 50.0);
  for (int k = 0; k < 200; ++k) f.push_back(120.0);
  for (int k = 0; k < 50; ++k) f.push_back(120.0 * (50 - k) / 50.0);
  for (int k = 0; k < 100; ++k) f.push_back(0.0);
  for (double& x : f) x += noise(rng);

  GrfThresholdDetector plain;
  SchmittDetector schmitt;
  int plain_toggles = 0, schmitt_toggles = 0;
  bool plain_state = false, schmitt_state = false;
  int touchdown = -1;
  for (std::size_t k = 0; k < f.size(); ++k) {
    const ContactSignals s = oneFoot(f[k], 0.001 * k, k == 0 ? 0.0 : 0.001);
    const bool a = plain.update(s).feet[0].contact, b = schmitt.update(s).feet[0].contact;
    plain_toggles += a != plain_state;
    schmitt_toggles += b != schmitt_state;
    if (b && !schmitt_state) touchdown = static_cast<int>(k);
    plain_state = a;
    schmitt_state = b;
  }
  CHECK(schmitt_toggles == 2);
  CHECK(plain_toggles > 2);
  // The force passes 50 N near sample 121 (20.8 of the 50 ramp samples); +5 ms hold, +-noise.
  CHECK(touchdown > 121);
  CHECK(touchdown < 135);
}

TEST_CASE("Schmitt trigger on random force traces", "[57.6]") {
  // A random trace of readings in [0, 100] N, runs of 1..15 samples at one level, dt = 1 ms.
  // Every switch on is preceded by more than T_on of readings above F_high, every switch off by
  // more than T_off below F_low; and the trigger never toggles more often than a plain threshold
  // inside its band (between two of its toggles the force crosses the whole band, so the plain
  // threshold toggles too).
  rc::prop("holds before every switch, fewer toggles than the plain threshold", [](unsigned seed) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> level(0.0, 100.0);
    std::uniform_int_distribution<int> run(1, 15);
    std::vector<double> f;
    while (f.size() < 2000) f.insert(f.end(), run(gen), level(gen));
    SchmittParams p;  // 50 / 20 N, 5 / 5 ms
    SchmittTrigger s(p);
    int toggles = 0, plain_toggles = 0;
    bool plain = false;
    for (std::size_t k = 0; k < f.size(); ++k) {
      const bool before = s.state();
      const bool after = s.update(f[k], 0.001);
      const bool now_plain = f[k] > 35.0;
      plain_toggles += now_plain != plain;
      plain = now_plain;
      if (after == before) continue;
      ++toggles;
      // Held for more than 5 ms: this sample and the five before it.
      RC_ASSERT(k >= 5);
      for (std::size_t j = k - 5; j <= k; ++j) {
        const bool held = after ? f[j] > 50.0 : f[j] < 20.0;
        RC_ASSERT(held);
      }
    }
    RC_ASSERT(toggles <= plain_toggles);
  });
}

TEST_CASE("GRF threshold: c = F > F_threshold, strictly", "[57.6]") {
  GrfThresholdDetector d;  // 30 N
  CHECK(d.name() == "grf-threshold");
  CHECK_FALSE(d.update(oneFoot(30.0, 0.0, 0.0)).feet[0].contact);
  const FootContact c = d.update(oneFoot(30.001, 0.001, 0.001)).feet[0];
  CHECK(c.contact);
  CHECK(c.probability == 1.0);
  CHECK(c.force == 30.001);
  CHECK(c.usable());
  CHECK(GrfThresholdDetector({}, ForceSource::kJointTorque).name() == "grf-threshold-torque");
  CHECK(SchmittDetector({}, ForceSource::kJointTorque).name() == "schmitt-torque");
  GrfThresholdParams bad;
  bad.saturation = 20.0;
  CHECK_THROWS_AS(GrfThresholdDetector(bad), std::invalid_argument);
}

TEST_CASE("force detectors: every problem of a sensor reading, never a silent no-contact",
          "[57.6]") {
  GrfThresholdDetector grf;
  SchmittDetector schmitt;
  for (ContactDetector* d :
       {static_cast<ContactDetector*>(&grf), static_cast<ContactDetector*>(&schmitt)}) {
    INFO(d->name());
    auto problem = [&](double f) {
      const char* p = d->update(oneFoot(f, 0.0, 0.0)).feet[0].problem;
      return std::string(p == nullptr ? "" : p);
    };
    CHECK(problem(kNaN) == "no force reading");
    CHECK(problem(std::numeric_limits<double>::infinity()) == "force is not finite");
    CHECK(problem(-std::numeric_limits<double>::infinity()) == "force is not finite");
    CHECK(problem(-10.5) == "force negative");
    CHECK(problem(-9.5).empty());  // within the sensor's noise: a reading, no contact
    d->reset();
    // Saturated (150 N) for longer than stuck_time (1 s): a valid reading up to 1 s, then a
    // problem. dt = 0.25 s is exact in binary: the 5th sample (k = 4) has been saturated for
    // 1.0 s (not > 1 s), the 6th for 1.25 s. (The Schmitt trigger is on from k = 1: 0.25 s held.)
    for (int k = 0; k <= 4; ++k) {
      const FootContact c = d->update(oneFoot(150.0, 0.25 * k, k == 0 ? 0.0 : 0.25)).feet[0];
      INFO("sample " << k);
      CHECK(c.usable());
      if (k >= 1) CHECK(c.contact);
    }
    const FootContact stuck = d->update(oneFoot(150.0, 1.25, 0.25)).feet[0];
    REQUIRE_FALSE(stuck.usable());
    CHECK(std::string(stuck.problem) == "force stuck at saturation");
    // One reading below full scale ends it.
    CHECK(d->update(oneFoot(149.0, 1.5, 0.25)).feet[0].usable());
    CHECK(d->update(oneFoot(150.0, 1.75, 0.25)).feet[0].usable());
  }
}

TEST_CASE("Schmitt: a sample without a reading holds the state and restarts the hold", "[57.6]") {
  SchmittDetector d;
  double t = 0.0;
  auto feed = [&](double f) { return d.update(oneFoot(f, t += 0.001, 0.001)).feet[0]; };
  for (int k = 0; k < 4; ++k) feed(60.0);  // held 4 ms
  CHECK_FALSE(feed(kNaN).usable());
  CHECK_FALSE(feed(60.0).contact);  // the hold starts again: 1 ms
  for (int k = 0; k < 4; ++k) CHECK_FALSE(feed(60.0).contact);
  CHECK(feed(60.0).contact);  // 6 ms
  CHECK_FALSE(feed(kNaN).usable());
  CHECK(feed(30.0).contact);  // still on after the dropout
}

TEST_CASE("input no caller can mean throws", "[57.6]") {
  SchmittDetector d;
  ContactSignals s = oneFoot(10.0, 0.0, 0.0);
  s.num_feet = 0;
  CHECK_THROWS_AS(d.update(s), std::invalid_argument);
  s.num_feet = kMaxFeet + 1;
  CHECK_THROWS_AS(d.update(s), std::invalid_argument);
  s.num_feet = 1;
  s.dt = -0.001;
  CHECK_THROWS_AS(d.update(s), std::invalid_argument);
  s.dt = kNaN;
  CHECK_THROWS_AS(d.update(s), std::invalid_argument);
}

namespace {

// A standing-like configuration of the four legs (knees bent).
JointVector bentLegs() {
  JointVector q;
  for (int l = 0; l < 4; ++l) q.segment<3>(3 * l) << 0.05 * (l % 2 ? -1 : 1), 0.8, -1.6;
  return q;
}

}  // namespace

TEST_CASE("force from joint torques inverts the leg rows of the equation of motion", "[57.6]") {
  // Build the motor torques from chosen world forces lambda_l with the dynamics themselves:
  //   tau_l = h_l - J_l^T lambda_l + D dq_l   (nudot = 0; D the joint damping),
  // then the estimate must return lambda_l.
  const model::QuadrupedGeometry geo = model::QuadrupedGeometry::go2();
  const model::QuadrupedInertia inertia = model::QuadrupedInertia::go2();
  const model::QuadrupedDynamics dyn(geo, inertia);
  const FootForceFromTorque ff(geo, inertia);

  model::FloatingBaseState x;
  x.R = (Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(-0.15, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
  x.v = Eigen::Vector3d(0.4, -0.1, 0.05);
  x.omega = Eigen::Vector3d(0.2, -0.3, 0.5);
  x.q = bentLegs();
  x.dq << 1, -2, 3, 0.5, 0.2, -0.1, -1, 1, 2, 0, 0.3, -0.4;
  const std::array<Eigen::Vector3d, 4> lambda = {
      Eigen::Vector3d(5, -3, 40), Eigen::Vector3d(-2, 1, 35), Eigen::Vector3d(0, 0, 0),
      Eigen::Vector3d(10, 4, 60)};
  const model::GeneralizedVector h = dyn.biasForces(x);
  ContactSignals s;
  s.has_joints = s.has_torque = true;
  s.q = x.q;
  s.dq = x.dq;
  s.gyro = x.omega;
  s.base.valid = true;
  s.base.R = x.R;
  s.base.v = x.v;
  for (int l = 0; l < 4; ++l) {
    const model::ContactJacobian J = dyn.footJacobian(l, x);
    s.tau.segment<3>(3 * l) = h.segment<3>(6 + 3 * l) -
                              J.middleCols<3>(6 + 3 * l).transpose() * lambda[l] +
                              inertia.damping.cwiseProduct(x.dq.segment<3>(3 * l));
  }
  std::array<const char*, 4> why{};
  const auto f = ff.estimate(s, &why);
  for (int l = 0; l < 4; ++l) {
    INFO("leg " << l);
    CHECK(why[l] == nullptr);
    CHECK((f[l] - lambda[l]).norm() < 1e-9);
  }

  // Without a base estimate the accelerometer's tilt (a robot at rest, yaw 0) gives the same
  // attitude and v = 0: with v = 0 in the reference too, the same forces.
  x.v.setZero();
  const model::GeneralizedVector h0 = dyn.biasForces(x);
  for (int l = 0; l < 4; ++l)
    s.tau.segment<3>(3 * l) =
        h0.segment<3>(6 + 3 * l) -
        dyn.footJacobian(l, x).middleCols<3>(6 + 3 * l).transpose() * lambda[l] +
        inertia.damping.cwiseProduct(x.dq.segment<3>(3 * l));
  s.base.valid = false;
  s.acc = x.R.transpose() * Eigen::Vector3d(0, 0, 9.81);
  const auto g = ff.estimate(s, &why);
  for (int l = 0; l < 4; ++l) {
    INFO("leg " << l);
    CHECK(why[l] == nullptr);
    CHECK((g[l] - lambda[l]).norm() < 1e-9);
  }
}

TEST_CASE("force from joint torques: a leg that cannot be solved says why", "[57.6]") {
  const FootForceFromTorque ff(model::QuadrupedGeometry::go2(), model::QuadrupedInertia::go2());
  ContactSignals s;
  s.has_joints = s.has_torque = true;
  s.q = bentLegs();
  s.base.valid = true;
  std::array<const char*, 4> why{};
  auto reason = [&](int leg) {
    const auto f = ff.estimate(s, &why);
    if (why[leg] == nullptr) {
      CHECK(f[leg].allFinite());
      return std::string();
    }
    CHECK(f[leg].hasNaN());
    return std::string(why[leg]);
  };
  CHECK(reason(0).empty());
  s.q.segment<3>(3) << 0.0, 0.3, 0.0;  // FR straight knee
  CHECK(reason(1) == "leg singular");
  CHECK(reason(0).empty());              // the other legs are not affected
  s.q.segment<3>(3) << 0.0, 0.3, -0.02;  // 1 degree from straight: still singular by the ratio
  CHECK(jacobianRatio(Eigen::Matrix3d::Identity()) == Approx(1.0));
  CHECK(reason(1) == "leg singular");
  s.q = bentLegs();
  s.tau(7) = kNaN;
  CHECK(reason(2) == "joint torque not finite");
  CHECK(reason(0).empty());
  s.tau(7) = 0.0;
  s.dq(0) = std::numeric_limits<double>::infinity();
  CHECK(reason(0) == "joint state not finite");
  CHECK(reason(3).empty());
  s.dq(0) = 0.0;
  s.gyro.y() = kNaN;
  CHECK(reason(3) == "base state not finite");
  s.gyro.y() = 0.0;
  s.has_torque = false;
  CHECK(reason(3) == "no joint torques");
  s.has_torque = true;
  s.has_joints = false;
  CHECK(reason(3) == "no joint angles");
  s.has_joints = true;
  s.base.valid = false;
  s.acc.setConstant(kNaN);
  CHECK(reason(0) == "no attitude");
  s.acc = Eigen::Vector3d(0, 0, 9.81);
  CHECK(reason(0).empty());
  s.num_feet = 2;
  CHECK(reason(0) == "joints not the quadruped's");

  // Through a detector: the torque source's reasons are the feet's problems.
  SchmittDetector d({}, ForceSource::kJointTorque);
  s.num_feet = 4;
  s.has_torque = false;
  const ContactEstimate e = d.update(s);
  for (int l = 0; l < 4; ++l) CHECK(std::string(e.feet[l].problem) == "no joint torques");
}
