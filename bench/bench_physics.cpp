// Speed of the physics simulator (issue 12's goal: at least 20x real time on one core): the 60 s
// physics trot with every sensor and the ground truth, and the log written as CSV to memory.
// x_real_time is simulated seconds per wall-clock second. Two physics rates: 2 kHz (the default)
// and 1 kHz (the log rate; a coarser step, for long studies).
#include <benchmark/benchmark.h>

#include <sstream>

#include "io/log_writer.hpp"
#include "sim/physics_simulator.hpp"

namespace {

void BM_PhysicsTrot60s(benchmark::State& state) {
  legkit::sim::PhysicsOptions o = legkit::sim::PhysicsOptions::forScenario("physics-trot");
  o.physics_rate = static_cast<double>(state.range(0));
  std::size_t bytes = 0;
  for (auto _ : state) {
    const legkit::sim::PhysicsResult run = legkit::sim::simulatePhysics(o);
    if (run.status.fell) state.SkipWithError(run.status.reason.c_str());
    std::ostringstream csv;
    legkit::io::writeLog(csv, run.log);
    bytes = csv.str().size();
    benchmark::DoNotOptimize(bytes);
  }
  state.counters["x_real_time"] = benchmark::Counter(
      o.duration * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["log_MB"] = static_cast<double>(bytes) / 1e6;
}
BENCHMARK(BM_PhysicsTrot60s)->Arg(2000)->Arg(1000)->Unit(benchmark::kSecond)->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
