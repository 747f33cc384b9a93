// Exercise 57.6.1: the design rules of the Schmitt trigger's four numbers, then the kit's
// SchmittDetector run with them on a physics trot and scored against the true contact.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "estimation/contact/schmitt_trigger.hpp"
#include "eval/contact_scores.hpp"
#include "ex57_6_1.hpp"
#include "exercises/exercise_check.hpp"
#include "sim/physics_simulator.hpp"

using ex57_6_1::DesignInputs;
using ex57_6_1::SchmittDesign;

namespace {

// 10 s of the physics 2 Hz trot (1 s standing, then 0.5 m/s), seed fixed: foot force sensors
// clamp(f_n + 3 + N(0, 2^2), 0, 150) N, the true contact in gt_feet.
const legkit::io::Log& trotLog() {
  static const legkit::io::Log log = [] {
    legkit::sim::PhysicsOptions options = legkit::sim::PhysicsOptions::forScenario("physics-trot");
    options.duration = 10.0;
    options.seed = 5761;
    return legkit::sim::simulatePhysics(options).log;
  }();
  return log;
}

// The kit's Schmitt detector on the log's force sensors, run from the first row and scored
// against the true contact from t = 0.5 s on (a detector starts in "no contact": its first
// touchdowns, on feet that were already standing, are not events of the log).
legkit::eval::ContactScores scoreOnTrot(const SchmittDesign& d) {
  legkit::contact::SchmittParams params;
  params.f_high = d.f_high;
  params.f_low = d.f_low;
  params.t_on = d.t_on;
  params.t_off = d.t_off;
  legkit::contact::SchmittDetector detector(params);
  const legkit::io::Log& log = trotLog();
  std::vector<double> t;
  std::vector<legkit::eval::FootFlags> detected, truth;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const legkit::io::LogRow& row = log.rows[k];
    legkit::contact::ContactSignals s;
    s.t = row.t;
    s.dt = k == 0 ? 0.0 : row.t - log.rows[k - 1].t;
    s.num_feet = 4;
    for (int i = 0; i < 4; ++i) s.feet[i].force = row.force[i];
    const legkit::contact::ContactEstimate e = detector.update(s);
    legkit::eval::FootFlags d_k{}, t_k{};
    for (int i = 0; i < 4; ++i) {
      d_k[i] = e.feet[i].usable() && e.feet[i].contact;
      t_k[i] = row.gt_feet[i].contact;
    }
    if (row.t < 0.5) continue;
    t.push_back(row.t);
    detected.push_back(d_k);
    truth.push_back(t_k);
  }
  return legkit::eval::scoreContacts(t, detected, truth, 4);
}

// The rules every design must keep, for any inputs.
void checkRules(const DesignInputs& in, const SchmittDesign& d) {
  // Noise alone must not reach F_low from an unloaded foot, nor span the band.
  REQUIRE_ABOVE(d.f_low, in.sensor_bias + 3.0 * in.sensor_sigma);
  REQUIRE_ABOVE(d.f_high - d.f_low, 5.0 * in.sensor_sigma);
  // F_high must be reached by a foot that carries its share when all four stand (half of the
  // trot's two-foot load), and read by the sensor (below saturation).
  REQUIRE_BELOW(d.f_high, 0.5 * in.foot_load);
  REQUIRE_BELOW(d.f_high, in.saturation);
  // The chapter's rule of thumb: T_on, T_off < 0.1 T_stance.
  REQUIRE_BELOW(d.t_on, 0.1 * in.stance_time);
  REQUIRE_BELOW(d.t_off, 0.1 * in.stance_time);
  REQUIRE_ABOVE(d.t_on, -1e-12);
  REQUIRE_ABOVE(d.t_off, -1e-12);
}

}  // namespace

TEST_CASE("57.6.1 the design keeps the rules for the 2 Hz trot", "[ex57.6.1][hint 1]") {
  const DesignInputs in;
  const SchmittDesign d = ex57_6_1::designSchmitt(in);
  INFO("F_high " << d.f_high << " N, F_low " << d.f_low << " N, T_on " << d.t_on * 1e3
                 << " ms, T_off " << d.t_off * 1e3 << " ms");
  checkRules(in, d);
}

TEST_CASE("57.6.1 the design follows the gait, the robot and the sensor", "[ex57.6.1][hint 2]") {
  // A 1 Hz trot (600 ms stance) of a 20 kg robot with a noisier, unbiased sensor.
  DesignInputs slow;
  slow.stance_time = 0.6;
  slow.foot_load = 20.0 * 9.81 / 2.0;
  slow.sensor_bias = 0.0;
  slow.sensor_sigma = 4.0;
  slow.saturation = 300.0;
  const SchmittDesign d = ex57_6_1::designSchmitt(slow);
  INFO("F_high " << d.f_high << " N, F_low " << d.f_low << " N, T_on " << d.t_on * 1e3
                 << " ms, T_off " << d.t_off * 1e3 << " ms");
  checkRules(slow, d);
  // A fast 4 Hz trot (150 ms stance): the hold times must shrink with it.
  DesignInputs fast;
  fast.stance_time = 0.15;
  const SchmittDesign f = ex57_6_1::designSchmitt(fast);
  INFO("4 Hz: T_on " << f.t_on * 1e3 << " ms, T_off " << f.t_off * 1e3 << " ms");
  checkRules(fast, f);
}

TEST_CASE("57.6.1 the kit's Schmitt detector with your numbers on a physics trot",
          "[ex57.6.1][hint 3]") {
  const SchmittDesign d = ex57_6_1::designSchmitt(DesignInputs{});
  const legkit::eval::ContactScores s = scoreOnTrot(d);
  INFO("precision " << s.precision << ", recall " << s.recall << ", F1 " << s.f1
                    << "; touchdown delay mean " << s.touchdown_delay_mean << " ms (p95 "
                    << s.touchdown_delay_p95 << "), lift-off " << s.liftoff_delay_mean
                    << " ms (p95 " << s.liftoff_delay_p95 << "); chatter " << s.chatter_per_min
                    << " /min; missed " << s.missed_touchdowns << " touchdowns, "
                    << s.missed_liftoffs << " lift-offs of " << s.touchdowns << ", " << s.liftoffs);
  REQUIRE(s.touchdowns >= 60);
  REQUIRE_ABOVE(s.f1, 0.97);
  REQUIRE_BELOW(s.chatter_per_min, 1.0);
  REQUIRE(s.missed_touchdowns + s.missed_liftoffs == 0);
  REQUIRE_BELOW(std::abs(s.touchdown_delay_mean), 15.0);
  REQUIRE_BELOW(std::abs(s.liftoff_delay_mean), 15.0);
  // The bounds are not lenient: the chapter's pitfall (T_on = T_off = 50 ms in this gait) and
  // thresholds inside the sensor's noise both fail them.
  const legkit::eval::ContactScores slow = scoreOnTrot({d.f_high, d.f_low, 0.05, 0.05});
  const legkit::eval::ContactScores noisy = scoreOnTrot({5.0, 4.0, 0.0, 0.0});
  const legkit::contact::SchmittParams kit;
  const legkit::eval::ContactScores kit_default =
      scoreOnTrot({kit.f_high, kit.f_low, kit.t_on, kit.t_off});
  INFO("T_on = T_off = 50 ms: F1 " << slow.f1 << ", touchdown delay " << slow.touchdown_delay_mean
                                   << " ms; F_high 5 N, F_low 4 N: chatter "
                                   << noisy.chatter_per_min << " /min; the kit's defaults (50 N, "
                                   << "20 N, 5 ms, 5 ms): F1 " << kit_default.f1 << ", recall "
                                   << kit_default.recall);
  REQUIRE_BELOW(slow.f1, 0.97);
  REQUIRE_ABOVE(slow.touchdown_delay_mean, 15.0);
  REQUIRE_ABOVE(noisy.chatter_per_min, 1.0);
}
