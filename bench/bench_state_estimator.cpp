// Time of one StateEstimator::update (section 57.11): the samples into a log row, the contact
// pipeline (the Schmitt trigger on the foot sensors, p_c, rolling foot, slip check) and the
// filter's step, plus the output copy and the ring buffer; and of one stateAt() query 2.5 ms
// back (the MPC's). Rows of a 10 s physics trot (seed 1), turned into samples before any timing.
// The target (issue 14): under 1 % of a 1 kHz loop, 10 us per update.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "estimation/state_estimator.hpp"
#include "sim/physics_simulator.hpp"

namespace {

using namespace legkit;

struct Samples {
  ImuSample imu;
  JointSample joints;
  ForceSample forces;
};

const std::vector<Samples>& trotSamples() {
  static const std::vector<Samples> samples = [] {
    sim::PhysicsOptions options = sim::PhysicsOptions::forScenario("physics-trot");
    options.duration = 10.0;
    const io::Log log = sim::simulatePhysics(options).log;
    std::vector<Samples> all(log.rows.size());
    for (std::size_t k = 0; k < log.rows.size(); ++k) {
      const io::LogRow& row = log.rows[k];
      all[k].imu = {row.t, row.gyro, row.acc};
      all[k].joints.q.head<io::kNumJoints>() = row.q;
      all[k].joints.dq.head<io::kNumJoints>() = row.dq;
      for (int f = 0; f < io::kNumLegs; ++f) all[k].forces.force[f] = row.force[f];
      all[k].forces.valid = true;
    }
    return all;
  }();
  return samples;
}

Settings managerSettings(const std::string& estimator, const std::string& contact) {
  Settings s;
  s.estimators = {estimator};
  s.pipeline.contact = contact;
  s.initialisation.enabled = false;  // the filter from the first sample: every update timed runs it
  return s;
}

// Each iteration: one update; the manager restarts (untimed) at the end of the log.
void BM_Update(benchmark::State& state, const std::string& estimator, const std::string& contact) {
  const std::vector<Samples>& samples = trotSamples();
  StateEstimator manager(managerSettings(estimator, contact));
  std::size_t k = 0;
  for (auto _ : state) {
    const Samples& s = samples[k];
    benchmark::DoNotOptimize(manager.update(s.imu, s.joints, s.forces).x.p.x());
    if (++k == samples.size()) {
      state.PauseTiming();
      manager.reset();
      k = 0;
      state.ResumeTiming();
    }
  }
}

// One MPC query 2.5 ms before the newest state (interpolated between two of a full buffer).
void BM_StateAt(benchmark::State& state) {
  const std::vector<Samples>& samples = trotSamples();
  StateEstimator manager(managerSettings("invariant-ekf", "schmitt"));
  for (std::size_t k = 0; k < 1000; ++k) {
    manager.update(samples[k].imu, samples[k].joints, samples[k].forces);
  }
  const double t = manager.output().x.t - 0.0025;
  for (auto _ : state) benchmark::DoNotOptimize(manager.stateAt(t).x.p.x());
}

BENCHMARK_CAPTURE(BM_Update, inekf_schmitt, "invariant-ekf", "schmitt");
BENCHMARK_CAPTURE(BM_Update, eskf_schmitt, "eskf", "schmitt");
BENCHMARK_CAPTURE(BM_Update, linear_kf_schmitt, "linear-kf", "schmitt");
BENCHMARK_CAPTURE(BM_Update, inekf_fallback, "invariant-ekf", "fallback");
BENCHMARK(BM_StateAt);

}  // namespace
