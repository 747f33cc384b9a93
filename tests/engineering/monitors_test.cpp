// Section 57.9's monitors on hand-made inputs: each alarm raised when its condition holds, not
// before, cleared when it stops; the answers (forceNoiseScale, legTrusted, applyTo); no
// allocation per update.
#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>

#include "estimation/engineering/monitors.hpp"

// This program counts its heap allocations (the header defines operator new: this file only).
#include "allocation_counter.hpp"

using namespace legkit;
using namespace legkit::engineering;

namespace {

constexpr double kDt = 0.001;  // 1 kHz

// A quadruped walking healthily: every joint moves, the force sensor agrees with the model.
MonitorInput healthy(int k) {
  MonitorInput in;
  in.t = k * kDt;
  in.gyro = Eigen::Vector3d(0.0, 0.0, 0.8);
  in.v_hat = Eigen::Vector3d(0.5, 0.0, 0.0);
  in.num_joints = 12;
  for (int j = 0; j < 12; ++j) {
    in.q[j] = 0.3 * std::sin(10.0 * in.t + j);
    in.dq[j] = 3.0 * std::cos(10.0 * in.t + j);
  }
  in.has_force = true;
  for (int i = 0; i < 4; ++i) {
    in.force_model[i] = 40.0 + 20.0 * std::sin(7.0 * in.t + i);
    in.force[i] = in.force_model[i] + 4.0 * std::sin(400.0 * in.t + 3 * i);  // noise ~ force_sigma
  }
  return in;
}

}  // namespace

TEST_CASE("monitors: a healthy robot raises nothing", "[57.9]") {
  HealthMonitor m(MonitorParams{}, 4, kDt);
  BaseCovariance P;
  P.P *= 0.01;
  for (int k = 0; k < 5000; ++k) {
    MonitorInput in = healthy(k);
    in.P = &P;
    const MonitorReport& r = m.update(in);
    REQUIRE_FALSE(r.uncertain);
  }
  for (int a = 0; a < kNumAlarms; ++a) {
    CHECK(m.report().count[a] == 0);
    CHECK(std::isnan(m.report().first[a]));
  }
  for (int i = 0; i < 4; ++i) {
    CHECK(m.forceNoiseScale(i) == 1.0);
    CHECK(m.legTrusted(i));
  }
}

TEST_CASE("monitors: IMU dropout over two nominal periods, flagged for the gap", "[57.9]") {
  HealthMonitor m(MonitorParams{}, 4, kDt);
  // Rows 1000..1001 present, then 2 periods late exactly (not a dropout), then 3 periods.
  int k = 0;
  for (; k <= 1000; ++k) REQUIRE_FALSE(m.update(healthy(k)).uncertain);
  k += 1;  // interval 2 dt: the bound itself is no dropout
  CHECK_FALSE(m.update(healthy(k))[Alarm::kImuDropout]);
  const double before_gap = healthy(k).t;
  k += 3;  // interval 3 dt: dropout
  const MonitorReport& r = m.update(healthy(k));
  CHECK(r[Alarm::kImuDropout]);
  CHECK(r.uncertain);
  CHECK(r.imu_gap == Approx(3 * kDt));
  CHECK(r.since[static_cast<int>(Alarm::kImuDropout)] == before_gap);
  CHECK(r.last[static_cast<int>(Alarm::kImuDropout)] == healthy(k).t);
  ++k;
  CHECK_FALSE(m.update(healthy(k))[Alarm::kImuDropout]);  // on time again
  CHECK_FALSE(m.report().uncertain);
  k += 50;
  m.update(healthy(k));
  CHECK(m.report().count[static_cast<int>(Alarm::kImuDropout)] == 2);
  CHECK(m.report().first[static_cast<int>(Alarm::kImuDropout)] == before_gap);
}

TEST_CASE("monitors: stuck encoder while the body moves; the leg's contacts are dropped",
          "[57.9]") {
  HealthMonitor m(MonitorParams{}, 4, kDt);
  const int stuck_joint = 7;  // leg 2 (RL), joint j = 1
  int k = 0;
  for (; k < 500; ++k) m.update(healthy(k));
  const MonitorInput frozen_at = healthy(k);
  int raised_at = -1;
  for (; k < 1000; ++k) {
    MonitorInput in = healthy(k);
    in.q[stuck_joint] = frozen_at.q[stuck_joint];
    in.dq[stuck_joint] = 0.0;
    if (m.update(in)[Alarm::kStuckEncoder] && raised_at < 0) raised_at = k;
  }
  // Raised stuck_encoder_time (0.1 s) after the first repeated reading (row 501).
  CHECK(raised_at == 501 + 100);
  CHECK_FALSE(m.legTrusted(2));
  CHECK(m.legTrusted(0));
  CHECK(m.legTrusted(1));
  CHECK(m.legTrusted(3));
  StepInput step;
  step.num_contacts = 3;
  for (int j = 0; j < 3; ++j) step.contacts[j].foot = j + 1;  // feet 1, 2, 3
  step.normal_force = {11.0, 22.0, 33.0};
  CHECK(m.applyTo(step) == 1);
  REQUIRE(step.num_contacts == 2);
  CHECK(step.contacts[0].foot == 1);
  CHECK(step.contacts[1].foot == 3);
  CHECK(step.normal_force[1] == 33.0);
  // The encoder comes back: trusted at once.
  m.update(healthy(k));
  CHECK(m.legTrusted(2));
  CHECK_FALSE(m.report()[Alarm::kStuckEncoder]);
}

TEST_CASE("monitors: a robot standing still with frozen encoders is not a fault", "[57.9]") {
  HealthMonitor m(MonitorParams{}, 4, kDt);
  for (int k = 0; k < 2000; ++k) {
    MonitorInput in = healthy(0);
    in.t = k * kDt;
    in.gyro = Eigen::Vector3d(0.01, -0.02, 0.0);  // gyro noise only
    in.v_hat.setZero();
    in.dq.setZero();
    REQUIRE_FALSE(m.update(in)[Alarm::kStuckEncoder]);
  }
}

TEST_CASE("monitors: force-sensor drift against the model inflates that foot's variance",
          "[57.9]") {
  const MonitorParams p;
  HealthMonitor m(p, 4, kDt);
  int k = 0;
  for (; k < 1000; ++k) m.update(healthy(k));
  CHECK(m.forceNoiseScale(1) == 1.0);
  // Foot 1 drifts +30 N over 2 s (15 N/s). The threshold is 3 x 3 N = 9 N of mean bias; the
  // exponential mean (0.25 s) lags a ramp by its time constant: raised near 0.6 + 0.25 s.
  int raised_at = -1;
  for (int n = 0; n < 2000; ++n, ++k) {
    MonitorInput in = healthy(k);
    in.force[1] += 15.0 * n * kDt;
    if (m.update(in)[Alarm::kForceDrift] && raised_at < 0) raised_at = n;
  }
  REQUIRE(raised_at > 0);
  CHECK(raised_at * kDt > 0.75);
  CHECK(raised_at * kDt < 0.95);
  CHECK(m.forceNoiseScale(1) > 1.0 + 4.0);  // bias well over 2 sigma by now
  CHECK(m.forceNoiseScale(1) == Approx(1.0 + std::pow(m.forceBias(1) / p.force_sigma, 2)));
  CHECK(m.forceNoiseScale(0) == 1.0);
  // Repaired: cleared once the mean falls below half the threshold.
  for (int n = 0; n < 3000; ++n, ++k) m.update(healthy(k));
  CHECK_FALSE(m.report()[Alarm::kForceDrift]);
  CHECK(m.forceNoiseScale(1) == 1.0);
  // A foot whose model has nothing (NaN) holds its mean, never raises on it.
  for (int n = 0; n < 1000; ++n, ++k) {
    MonitorInput in = healthy(k);
    in.force[3] += 100.0;
    in.force_model[3] = std::numeric_limits<double>::quiet_NaN();
    REQUIRE_FALSE(m.update(in)[Alarm::kForceDrift]);
  }
}

TEST_CASE("monitors: exteroception lost for the timeout (synthetic update times)", "[57.9]") {
  HealthMonitor m(MonitorParams{}, 4, kDt);
  // A 10 Hz exteroceptive source that stops at t = 2 s: alarm at 7 s, dated 7 s.
  int raised_at = -1;
  double last = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < 8000; ++k) {
    MonitorInput in = healthy(k);
    in.has_exteroception = true;
    if (k % 100 == 0 && k <= 2000) last = in.t;
    in.exteroception_t = last;
    if (m.update(in)[Alarm::kExteroceptionLost] && raised_at < 0) raised_at = k;
  }
  CHECK(raised_at == 7001);  // more than 5 s after the update at 2.000 s
  CHECK(m.report().since[static_cast<int>(Alarm::kExteroceptionLost)] == Approx(7.0));
  // Never any update: counted from the first step.
  HealthMonitor n(MonitorParams{}, 4, kDt);
  MonitorInput in = healthy(0);
  in.has_exteroception = true;
  in.t = 100.0;
  n.update(in);
  in.t = 104.9;
  CHECK_FALSE(n.update(in)[Alarm::kExteroceptionLost]);
  in.t = 105.1;
  CHECK(n.update(in)[Alarm::kExteroceptionLost]);
  // A robot without exteroception: never.
  HealthMonitor none(MonitorParams{}, 4, kDt);
  in.has_exteroception = false;
  in.t = 0.0;
  none.update(in);
  in.t = 60.0;
  CHECK_FALSE(none.update(in)[Alarm::kExteroceptionLost]);
}

TEST_CASE("monitors: covariance growth and loss of positive definiteness", "[57.9]") {
  MonitorParams p;
  p.position_sigma_max = 1.0;
  p.velocity_sigma_max = 0.5;
  HealthMonitor m(p, 4, kDt);
  BaseCovariance P;
  P.P = 0.01 * Eigen::Matrix<double, 9, 9>::Identity();
  MonitorInput in = healthy(0);
  in.P = &P;
  CHECK_FALSE(m.update(in).uncertain);
  P.P(7, 7) = 1.1 * 1.1;  // position y sigma 1.1 m
  in = healthy(1);
  in.P = &P;
  CHECK(m.update(in)[Alarm::kCovarianceGrowth]);
  CHECK(m.report().position_sigma == Approx(1.1));
  P.P(7, 7) = 0.01;
  P.P(4, 4) = 0.6 * 0.6;
  in = healthy(2);
  in.P = &P;
  CHECK(m.update(in)[Alarm::kCovarianceGrowth]);
  P.P(4, 4) = 0.01;
  // Indefinite: a correlation of 2 between v_x and p_x.
  P.P(3, 6) = P.P(6, 3) = 0.02;
  in = healthy(3);
  in.P = &P;
  const MonitorReport& r = m.update(in);
  CHECK_FALSE(r[Alarm::kCovarianceGrowth]);
  CHECK(r[Alarm::kNotPositiveDefinite]);
  // A filter without attitude: only the (v, p) block is judged.
  P.P(3, 6) = P.P(6, 3) = 0.0;
  P.P(0, 1) = P.P(1, 0) = 1.0;  // nonsense in the attitude block
  P.has_attitude = false;
  in = healthy(4);
  in.P = &P;
  CHECK_FALSE(m.update(in)[Alarm::kNotPositiveDefinite]);
  P.has_attitude = true;
  in = healthy(5);
  in.P = &P;
  CHECK(m.update(in)[Alarm::kNotPositiveDefinite]);
  // A NaN.
  P.P(0, 1) = P.P(1, 0) = 0.0;
  P.P(8, 8) = std::numeric_limits<double>::quiet_NaN();
  in = healthy(6);
  in.P = &P;
  CHECK(m.update(in)[Alarm::kNotPositiveDefinite]);
  CHECK(m.update(in)[Alarm::kCovarianceGrowth]);
  // The filter recovered (its P is fine again): the alarm for that step.
  P.P(8, 8) = 0.01;
  Health h;
  in = healthy(7);
  in.P = &P;
  in.health = &h;
  CHECK_FALSE(m.update(in)[Alarm::kNotPositiveDefinite]);
  h.record(Fault::kStateUnhealthy, 0.008);
  in = healthy(8);
  in.P = &P;
  in.health = &h;
  CHECK(m.update(in)[Alarm::kNotPositiveDefinite]);
  in = healthy(9);
  in.P = &P;
  in.health = &h;
  CHECK_FALSE(m.update(in)[Alarm::kNotPositiveDefinite]);
}

TEST_CASE("monitors: reset forgets, bad parameters throw, no allocation per update", "[57.9]") {
  CHECK_THROWS_AS(HealthMonitor(MonitorParams{}, 0, kDt), std::invalid_argument);
  CHECK_THROWS_AS(HealthMonitor(MonitorParams{}, io::kMaxFeet + 1, kDt), std::invalid_argument);
  CHECK_THROWS_AS(HealthMonitor(MonitorParams{}, 4, 0.0), std::invalid_argument);
  MonitorParams bad;
  bad.force_sigma = -1.0;
  CHECK_THROWS_WITH(HealthMonitor(bad, 4, kDt), Catch::Contains("force_sigma"));
  bad = MonitorParams{};
  bad.exteroception_timeout = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(HealthMonitor(bad, 4, kDt), Catch::Contains("exteroception_timeout"));

  HealthMonitor m(MonitorParams{}, 4, kDt);
  BaseCovariance P, wide;
  wide.P *= 400.0;  // position sigma 20 m
  Health h;
  std::vector<MonitorInput> inputs;
  for (int k = 0; k < 3000; ++k) {
    MonitorInput in = healthy(k);
    in.P = k > 2500 ? &wide : &P;  // covariance growth
    in.health = &h;
    in.has_exteroception = true;
    if (k > 1000) in.force[0] += 50.0;  // drift
    if (k > 1500) in.q[0] = 0.1;        // frozen ...
    if (k > 1500) in.dq[0] = 0.0;       // ... rate 0
    if (k > 2000) in.t += 0.003;        // one dropout (3 periods) at row 2001
    inputs.push_back(in);
  }
  const long before = test::allocationCount();
  for (const MonitorInput& in : inputs) m.update(in);
  CHECK(test::allocationCount() == before);
  CHECK(m.report().uncertain);
  for (const Alarm a :
       {Alarm::kImuDropout, Alarm::kStuckEncoder, Alarm::kForceDrift, Alarm::kCovarianceGrowth}) {
    CHECK(m.report().count[static_cast<int>(a)] == 1);
  }
  m.reset();
  for (int a = 0; a < kNumAlarms; ++a) {
    CHECK_FALSE(m.report().active[a]);
    CHECK(m.report().count[a] == 0);
  }
  CHECK(m.forceNoiseScale(0) == 1.0);
  CHECK(alarmName(Alarm::kForceDrift) == std::string("force-sensor drift"));
}
