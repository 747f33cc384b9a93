// Exercise 57.9.1: the sensor-health monitor on a simulated physics trot (7 s at 1 kHz): no alarm
// on the clean log, each injected fault found within a stated time.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>

#include "ex57_9_1.hpp"
#include "exercises/exercise_check.hpp"
#include "sim/physics_simulator.hpp"

using ex57_9_1::Fault;
using ex57_9_1::Response;

namespace {

// The clean log: a physics trot (MuJoCo, 7 s, seed 5791) with the kit's force-sensor model (2 N
// of noise, a 3 N offset) but this exercise's force range. Shared by the test cases.
const legkit::io::Log& cleanLog() {
  static const legkit::io::Log log = [] {
    legkit::sim::PhysicsOptions options = legkit::sim::PhysicsOptions::forScenario("physics-trot");
    options.duration = 7.0;
    options.seed = 5791;
    options.force_sensor.saturation = ex57_9_1::kForceRange;
    return legkit::sim::simulatePhysics(options).log;
  }();
  return log;
}

// The clean log with `edit` applied to every row at or after t_fault.
legkit::io::Log inject(double t_fault, const std::function<void(legkit::io::LogRow&)>& edit) {
  legkit::io::Log log = cleanLog();
  for (legkit::io::LogRow& row : log.rows)
    if (row.t >= t_fault) edit(row);
  return log;
}

// The time of the first row on which `fault` is active (NaN: never) and whether any fault was
// active before t_fault.
struct Found {
  double t_first = NAN;
  bool any_before = false;
};
Found firstDetection(const legkit::io::Log& log, Fault fault, double t_fault) {
  ex57_9_1::SensorMonitor monitor(ex57_9_1::defaultThresholds());
  Found found;
  for (const legkit::io::LogRow& row : log.rows) {
    const ex57_9_1::Report& r = monitor.update(row);
    if (row.t < t_fault)
      for (bool active : r) found.any_before = found.any_before || active;
    if (std::isnan(found.t_first) && r[static_cast<int>(fault)]) found.t_first = row.t;
  }
  return found;
}

// Detected no earlier than the fault and at most `within` seconds after it; nothing before.
void requireDetected(const legkit::io::Log& log, Fault fault, double t_fault, double within) {
  const Found found = firstDetection(log, fault, t_fault);
  INFO("fault at " << t_fault << " s, first detected at " << found.t_first << " s");
  REQUIRE(!found.any_before);
  REQUIRE(found.t_first >= t_fault);
  REQUIRE(found.t_first <= t_fault + within);
}

}  // namespace

TEST_CASE("57.9.1 the responses", "[ex57.9.1][hint 1]") {
  // Without an IMU sample the filter cannot predict: carry the last good one through.
  REQUIRE(ex57_9_1::responseTo(Fault::kImuDropout) == Response::kHold);
  REQUIRE(ex57_9_1::responseTo(Fault::kImuSaturation) == Response::kHold);
  // One impossible joint reading: drop that leg's measurement for the step.
  REQUIRE(ex57_9_1::responseTo(Fault::kEncoderJump) == Response::kIgnoreSample);
  // A dead encoder does not come back by itself: the leg's kinematics are wrong until repaired.
  REQUIRE(ex57_9_1::responseTo(Fault::kEncoderFrozen) == Response::kAlarm);
  // A clipped force still says "contact"; a drifting one must weigh less, or stop being used.
  const Response saturated = ex57_9_1::responseTo(Fault::kForceSaturation);
  REQUIRE((saturated == Response::kIgnoreSample || saturated == Response::kInflateR));
  const Response drift = ex57_9_1::responseTo(Fault::kForceDrift);
  REQUIRE((drift == Response::kInflateR || drift == Response::kAlarm));
}

TEST_CASE("57.9.1 no false alarm on the clean log", "[ex57.9.1][hint 2]") {
  const legkit::io::Log& log = cleanLog();
  ex57_9_1::SensorMonitor monitor(ex57_9_1::defaultThresholds());
  double max_gyro = 0.0, max_accel = 0.0, max_step = 0.0, max_force = 0.0, max_swing = 0.0;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const legkit::io::LogRow& row = log.rows[k];
    const ex57_9_1::Report& r = monitor.update(row);
    for (int f = 0; f < ex57_9_1::kNumFaults; ++f) {
      INFO("fault " << f << " at t = " << row.t << " s");
      REQUIRE(!r[f]);
    }
    max_gyro = std::max(max_gyro, row.gyro.cwiseAbs().maxCoeff());
    max_accel = std::max(max_accel, row.acc.cwiseAbs().maxCoeff());
    if (k > 0) max_step = std::max(max_step, (row.q - log.rows[k - 1].q).cwiseAbs().maxCoeff());
    for (int leg = 0; leg < 4; ++leg) {
      max_force = std::max(max_force, row.force[leg]);
      if (!row.contact[leg]) max_swing = std::max(max_swing, std::abs(row.force[leg]));
    }
  }
  INFO("clean log: max |gyro| " << max_gyro << " rad/s, |accel| " << max_accel
                                << " m/s^2, joint step " << max_step << " rad, force " << max_force
                                << " N, swing |force| " << max_swing << " N");
  REQUIRE(max_force < 0.99 * ex57_9_1::kForceRange);
}

TEST_CASE("57.9.1 an IMU dropout is found on the first row after the gap", "[ex57.9.1][hint 2]") {
  legkit::io::Log log = cleanLog();  // 20 ms without a sample: the rows of [3, 3.02) removed
  const auto gap = [](const legkit::io::LogRow& row) { return row.t >= 3.0 && row.t < 3.02; };
  log.rows.erase(std::remove_if(log.rows.begin(), log.rows.end(), gap), log.rows.end());
  requireDetected(log, Fault::kImuDropout, 3.0, 0.021);
}

TEST_CASE("57.9.1 a saturated gyro is found on its first row", "[ex57.9.1][hint 2]") {
  const legkit::io::Log log = inject(4.0, [](legkit::io::LogRow& row) {
    if (row.t < 4.02) row.gyro.x() = ex57_9_1::kGyroRange;  // clipped during a 20 ms spin
  });
  requireDetected(log, Fault::kImuSaturation, 4.0, 0.0);
}

TEST_CASE("57.9.1 an encoder jump of 20 deg is found on its row", "[ex57.9.1][hint 2]") {
  // FR's knee encoder slips by 20 deg (an index-pulse error) and stays off.
  const legkit::io::Log log =
      inject(5.0, [](legkit::io::LogRow& row) { row.q[5] += 20.0 * M_PI / 180.0; });
  requireDetected(log, Fault::kEncoderJump, 5.0, 0.0);
}

TEST_CASE("57.9.1 a frozen encoder is found within 0.1 s", "[ex57.9.1][hint 2]") {
  const double q_frozen = [] {
    for (const legkit::io::LogRow& row : cleanLog().rows)
      if (row.t >= 6.0) return row.q[7];
    return 0.0;
  }();
  // RL's hip pitch reads the same value from 6 s on (a dead encoder's last count).
  const legkit::io::Log log =
      inject(6.0, [q_frozen](legkit::io::LogRow& row) { row.q[7] = q_frozen; });
  requireDetected(log, Fault::kEncoderFrozen, 6.0, 0.1);
}

TEST_CASE("57.9.1 a saturated force sensor is found on its first row", "[ex57.9.1][hint 2]") {
  const legkit::io::Log log = inject(2.0, [](legkit::io::LogRow& row) {
    if (row.t < 2.01) row.force[2] = ex57_9_1::kForceRange;  // RL hits a step edge hard
  });
  requireDetected(log, Fault::kForceSaturation, 2.0, 0.0);
}

TEST_CASE("57.9.1 a force sensor drifting by 50 N/s is found within 1 s", "[ex57.9.1][hint 2]") {
  // FL's offset grows by 50 N per second from 4 s on (a warming strain gauge, sped up).
  const legkit::io::Log log =
      inject(4.0, [](legkit::io::LogRow& row) { row.force[0] += 50.0 * (row.t - 4.0); });
  requireDetected(log, Fault::kForceDrift, 4.0, 1.0);
}
