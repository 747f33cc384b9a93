// A recorded log's conditioning (estimation/log_conditioning.hpp): jittery stamps smoothed, gaps
// kept, joint velocities from the angles, held IMU rows counted; a clocked log left alone.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "estimation/log_conditioning.hpp"
#include "estimation/settings.hpp"
#include "sim/simulator.hpp"

using namespace legkit;

namespace {

constexpr double kPeriod = 0.01;

// Rows sampled every `period`, stamped late by a uniform delay in [0, 0.8 period) (seed fixed).
std::vector<double> jitteredStamps(int n, double period, std::vector<double>& true_t) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> delay(0.0, 0.8 * period);
  std::vector<double> t(n);
  true_t.resize(n);
  for (int k = 0; k < n; ++k) {
    true_t[k] = k * period;
    t[k] = true_t[k] + delay(rng);
  }
  return t;
}

double maxError(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) m = std::max(m, std::abs(a[k] - b[k]));
  return m;
}

io::Log simulatedTrot() {
  sim::SimOptions options;
  options.scenario = sim::scenarioByName("trot");
  options.duration = 1.0;
  return sim::simulate(options).log;
}

}  // namespace

TEST_CASE("a clocked log has no jitter and its stamps are left alone", "[57.11][frontend]") {
  io::Log log = simulatedTrot();
  const io::Log recorded = log;
  const ConditioningReport report = condition(log, {});
  CHECK(report.jitter < 1e-6);  // the rounding of k dt
  CHECK_FALSE(report.stamps_smoothed);
  CHECK_FALSE(report.velocities_from_angles);
  for (std::size_t k = 0; k < log.rows.size(); ++k)
    REQUIRE(io::exactlyEqual(log.rows[k], recorded.rows[k]));
}

TEST_CASE("smoothed stamps: a line stays, jitter averages out, a drift and a gap stay",
          "[57.11][frontend]") {
  SECTION("a straight line is its own fit") {
    std::vector<double> t(50);
    for (std::size_t k = 0; k < t.size(); ++k) t[k] = 3.0 + 0.01 * static_cast<double>(k);
    CHECK(maxError(smoothedStamps(t), t) < 1e-12);
  }
  SECTION(
      "jitter of up to 0.8 periods: within a quarter period of the clock, plus the mean delay") {
    std::vector<double> clock;
    const std::vector<double> t = jitteredStamps(400, kPeriod, clock);
    CHECK(stampJitter(t) > kStampJitterLimit);
    // Less the mean delay (a constant offset, which no smoothing can see), the stamps are off by
    // up to 0.4 periods, the smoothed ones by 0.05 periods RMS, a quarter period at most.
    std::vector<double> logged = t;
    std::vector<double> smooth = smoothedStamps(t);
    for (double& s : logged) s -= 0.4 * kPeriod;
    for (double& s : smooth) s -= 0.4 * kPeriod;
    CHECK(maxError(logged, clock) > 0.35 * kPeriod);
    CHECK(maxError(smooth, clock) < 0.25 * kPeriod);
  }
  SECTION("a rate that drifts by 20 % over the log is followed to 2 % of a period") {
    std::vector<double> t(300);
    for (std::size_t k = 0; k < t.size(); ++k) {
      const double x = static_cast<double>(k);
      t[k] = kPeriod * (x + 0.2 * x * x / 600.0);
    }
    // A line fitted to a parabola over +-10 rows is off by its curvature times 37 rows^2.
    CHECK(maxError(smoothedStamps(t), t) < 0.02 * kPeriod);
  }
  SECTION("a dropout is a gap, not jitter: neither measured nor smoothed across") {
    std::vector<double> t;
    for (int k = 0; k < 30; ++k) t.push_back(k * kPeriod);
    for (int k = 0; k < 30; ++k) t.push_back(5.0 + k * kPeriod);
    CHECK(stampJitter(t) < 1e-6);
    CHECK(maxError(smoothedStamps(t), t) < 1e-9);
  }
}

TEST_CASE("condition: jittery stamps smoothed on auto, joint velocities from the angles",
          "[57.11][frontend]") {
  io::Log log = simulatedTrot();
  std::vector<double> clock;
  const double period = log.rows[1].t - log.rows[0].t;
  const std::vector<double> t = jitteredStamps(static_cast<int>(log.rows.size()), period, clock);
  for (std::size_t k = 0; k < log.rows.size(); ++k) log.rows[k].t = t[k];
  log.rows[5].gyro = log.rows[4].gyro;
  log.rows[5].acc = log.rows[4].acc;

  SECTION("auto smooths, logged keeps") {
    io::Log kept = log;
    CHECK_FALSE(
        condition(kept, {StampHandling::kLogged, JointVelocitySource::kLogged}).stamps_smoothed);
    CHECK(kept.rows[10].t == t[10]);
    const ConditioningReport report = condition(log, {});
    CHECK(report.stamps_smoothed);
    CHECK(report.held_imu_rows == 1);
    CHECK(report.max_stamp_shift > 0.0);
    CHECK(log.rows[10].t != t[10]);
    CHECK_THAT(report.describe(), Catch::Matchers::Contains("smoothed"));
  }
  SECTION("angles: the backward difference on the smoothed stamps, row 0 taking row 1's") {
    const io::Log recorded = log;
    const ConditioningReport report =
        condition(log, {StampHandling::kAuto, JointVelocitySource::kAngles});
    REQUIRE(report.velocities_from_angles);
    for (std::size_t k = 1; k < log.rows.size(); ++k) {
      const io::JointVector expected =
          (recorded.rows[k].q - recorded.rows[k - 1].q) / (log.rows[k].t - log.rows[k - 1].t);
      REQUIRE((log.rows[k].dq - expected).norm() < 1e-9 * (1.0 + expected.norm()));
    }
    CHECK(log.rows[0].dq == log.rows[1].dq);
    // The simulated velocities and the differences agree to the differentiated noise: the
    // encoder noise (1.75e-4 rad) over 1 ms, 0.25 rad/s RMS per joint.
    double sum = 0.0;
    for (std::size_t k = 1; k < log.rows.size(); ++k)
      sum += (log.rows[k].dq - recorded.rows[k].dq).squaredNorm();
    CHECK(std::sqrt(sum / (12.0 * static_cast<double>(log.rows.size()))) < 0.5);
  }
}

TEST_CASE("the settings name the conditioning under frontend:", "[57.11][frontend][config]") {
  const Settings s = settingsFromYaml(
      "frontend:\n  timestamps: \"logged\"\n  joint_velocities: \"angles\"\n", "test.yaml");
  CHECK(s.conditioning.stamps == StampHandling::kLogged);
  CHECK(s.conditioning.joint_velocities == JointVelocitySource::kAngles);
  CHECK(defaultSettings().conditioning.stamps == StampHandling::kAuto);
  CHECK(defaultSettings().conditioning.joint_velocities == JointVelocitySource::kAuto);
  CHECK_THROWS_WITH(settingsFromYaml("frontend:\n  joint_velocities: \"filtered\"\n", "test.yaml"),
                    Catch::Matchers::Contains("joint_velocities"));
}
