// Exercise 57.6.3: a late contact detector, by hand on a made-up log, then its cost to the kit's
// linear KF on a physics trot, recomputed here with the kit.
#include <catch2/catch.hpp>
#include <cmath>

#include "estimation/linear_kf/linear_kf.hpp"
#include "estimation/log_frontend.hpp"
#include "ex57_6_3.hpp"
#include "exercises/exercise_check.hpp"
#include "sim/physics_simulator.hpp"
#include "sim/simulator.hpp"

using ex57_6_3::DetectionDelay;

namespace {

// 6 s of the analytic 2 Hz trot at 0.5 m/s (sim/simulator.hpp), seed fixed: rigid point feet
// that never slip, contact flags exact.
const legkit::io::Log& trotLog() {
  static const legkit::io::Log log = [] {
    legkit::sim::SimOptions options;
    options.scenario = legkit::sim::scenarioByName("trot");
    options.duration = 6.0;
    options.seed = 5763;
    return legkit::sim::simulate(options).log;
  }();
  return log;
}

// 6 s of the physics trot (1 s standing, 1 s speeding up, 4 s at 0.5 m/s): round feet that roll
// and impacts; the log's contact flags are the true contacts (normal force above 1 N).
const legkit::io::Log& physicsTrotLog() {
  static const legkit::io::Log log = [] {
    legkit::sim::PhysicsOptions options = legkit::sim::PhysicsOptions::forScenario("physics-trot");
    options.duration = 6.0;
    options.seed = 5763;
    return legkit::sim::simulatePhysics(options).log;
  }();
  return log;
}

// The kit's linear KF over the log from its true initial state: RMS of |p_hat - p| [m].
double kitPositionRmse(const legkit::io::Log& log) {
  const legkit::LogFrontend frontend(log.layout, legkit::model::QuadrupedKinematics{});
  legkit::linear_kf::LinearKf kf;
  legkit::EstimateSample x0;
  x0.t = log.rows[0].t;
  x0.q = log.rows[0].gt_q;
  x0.v = log.rows[0].gt_v;
  x0.p = log.rows[0].gt_p;
  kf.reset(x0);
  double sum_sq = 0.0;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const double dt = k == 0 ? 0.0 : log.rows[k].t - log.rows[k - 1].t;
    kf.step(frontend.input(log.rows[k], dt));
    sum_sq += (kf.estimate().p - log.rows[k].gt_p).squaredNorm();
  }
  return std::sqrt(sum_sq / static_cast<double>(log.rows.size()));
}

// Rows of foot 0's and foot 1's flags, made up: foot 0 stands 5 rows, swings 15, stands 10; foot
// 1 touches down for 3 rows only.
legkit::io::Log madeUpLog() {
  legkit::io::Log log;
  log.layout.contact = true;
  for (int k = 0; k < 30; ++k) {
    legkit::io::LogRow row;
    row.t = 0.001 * k;
    row.gyro = Eigen::Vector3d(k, 0.0, 0.0);
    row.contact[0] = k < 5 || k >= 20;
    row.contact[1] = k >= 10 && k < 13;
    row.contact[2] = row.contact[3] = true;
    log.rows.push_back(row);
  }
  return log;
}

}  // namespace

TEST_CASE("57.6.3 delayContacts by hand", "[ex57.6.3][hint 1]") {
  const legkit::io::Log log = madeUpLog();
  const legkit::io::Log late = ex57_6_3::delayContacts(log, DetectionDelay{5, 3});
  REQUIRE(late.rows.size() == log.rows.size());
  for (int k = 0; k < 30; ++k) {
    INFO("row " << k);
    // Foot 0: the lift-off at row 5 is reported at row 8, the touchdown at row 20 at row 25.
    REQUIRE(late.rows[k].contact[0] == (k < 8 || k >= 25));
    // Foot 1's 3-row stance is shorter than the 5-row touchdown delay: never reported.
    REQUIRE_FALSE(late.rows[k].contact[1]);
    REQUIRE(late.rows[k].contact[2]);
    REQUIRE(late.rows[k].t == log.rows[k].t);
    REQUIRE(late.rows[k].gyro == log.rows[k].gyro);
  }
  // No delay: the log's own flags.
  const legkit::io::Log same = ex57_6_3::delayContacts(log, DetectionDelay{0, 0});
  for (int k = 0; k < 30; ++k) REQUIRE(same.rows[k].contact == log.rows[k].contact);
}

TEST_CASE("57.6.3 positionRmse is the kit's linear KF against the truth", "[ex57.6.3][hint 2]") {
  const legkit::io::Log& log = trotLog();
  REQUIRE(log.rows.size() == 6000);
  const double expected = kitPositionRmse(log);
  REQUIRE_NEAR(ex57_6_3::positionRmse(log), expected, 1e-9);
}

TEST_CASE("57.6.3 a 10 ms delay costs position accuracy", "[ex57.6.3][hint 3]") {
  const legkit::io::Log& log = trotLog();
  const ex57_6_3::DelayCost cost = ex57_6_3::delayCost(log, DetectionDelay{10, 10});
  INFO("on time " << cost.on_time << " m, 10 ms late " << cost.delayed << " m");
  REQUIRE_NEAR(cost.on_time, kitPositionRmse(log), 1e-9);
  // Recomputed here with the kit, on the flags as the exercise delayed them (checked by hand
  // above).
  REQUIRE_NEAR(cost.delayed, kitPositionRmse(ex57_6_3::delayContacts(log, {10, 10})), 1e-9);
  REQUIRE_NEAR(cost.increase, cost.delayed - cost.on_time, 1e-12);
  REQUIRE_ABOVE(cost.increase, 0.0);
}

TEST_CASE("57.6.3 which edge costs: the late lift-off", "[ex57.6.3][hint 4]") {
  // Analytic trot. A late touchdown only withholds 10 good measurements per stance; a late
  // lift-off feeds the filter 10 measurements of a foot that is already moving.
  const ex57_6_3::DelayCost touchdown = ex57_6_3::delayCost(trotLog(), DetectionDelay{10, 0});
  const ex57_6_3::DelayCost liftoff = ex57_6_3::delayCost(trotLog(), DetectionDelay{0, 10});
  const ex57_6_3::DelayCost both = ex57_6_3::delayCost(trotLog(), DetectionDelay{10, 10});
  INFO("analytic trot, position RMS on time " << touchdown.on_time << " m; increase with a 10 ms"
                                              << " late touchdown " << touchdown.increase
                                              << " m, late lift-off " << liftoff.increase
                                              << " m, both " << both.increase << " m");
  REQUIRE_BELOW(std::abs(touchdown.increase), 0.0005);
  REQUIRE_ABOVE(liftoff.increase, 0.001);
  // Physics trot: the late lift-off costs there too.
  const ex57_6_3::DelayCost physics = ex57_6_3::delayCost(physicsTrotLog(), DetectionDelay{0, 10});
  const ex57_6_3::DelayCost physics_touchdown =
      ex57_6_3::delayCost(physicsTrotLog(), DetectionDelay{10, 0});
  const ex57_6_3::DelayCost physics_both =
      ex57_6_3::delayCost(physicsTrotLog(), DetectionDelay{10, 10});
  INFO("physics trot, position RMS on time " << physics.on_time << " m; increase with a 10 ms"
                                             << " late lift-off " << physics.increase
                                             << " m, late touchdown " << physics_touchdown.increase
                                             << " m, both " << physics_both.increase << " m");
  REQUIRE_ABOVE(physics.increase, 0.001);
}
