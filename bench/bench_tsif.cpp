// Time per step of the two-state implicit filter (section 57.5) on the default trot
// (bench/trot_inputs.hpp: 10 s, Go2-class sensors, seed 1), with one and with two Gauss-Newton
// iterations per step.
//
//   cmake --build build --target bench_tsif && ./build/bench/bench_tsif --benchmark_min_time=0.2
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>

#include "bench/trot_inputs.hpp"
#include "estimation/invariant/tsif.hpp"

namespace {

void BM_TsifStep(benchmark::State& state) {
  legkit::invariant::TsifParams params;
  params.iterations = static_cast<int>(state.range(0));
  legkit::invariant::Tsif filter(params);
  legkit::bench::runFilter(state, filter);
}
BENCHMARK(BM_TsifStep)
    ->ArgName("iterations")
    ->Arg(1)
    ->Arg(2)
    ->Arg(5)
    ->Unit(benchmark::kMicrosecond);

// Not a timing: one pass over the trot with at most range(0) iterations, reporting the mean
// iterations per step, the largest count, and the largest position and attitude difference from
// the one-iteration filter (the ESKF's numbers) over the pass.
void BM_TsifIterationStats(benchmark::State& state) {
  const legkit::bench::TrotInputs& inputs = legkit::bench::trotInputs();
  legkit::invariant::TsifParams params;
  params.iterations = static_cast<int>(state.range(0));
  params.step_tolerance = std::pow(10.0, -static_cast<double>(state.range(1)));
  double mean = 0.0, max_iterations = 0.0, dp = 0.0, dtheta = 0.0;
  for (auto _ : state) {
    legkit::invariant::Tsif filter(params);
    legkit::invariant::Tsif one;
    filter.reset(inputs.x0);
    one.reset(inputs.x0);
    double sum = 0.0;
    for (const legkit::StepInput& in : inputs.steps) {
      filter.step(in);
      one.step(in);
      sum += filter.lastIterations();
      max_iterations = std::max(max_iterations, double(filter.lastIterations()));
      dp = std::max(dp, (filter.state().p - one.state().p).norm());
      dtheta = std::max(dtheta, filter.state().R.rminus(one.state().R).norm());
    }
    mean = sum / double(inputs.steps.size());
  }
  state.counters["mean_iterations"] = mean;
  state.counters["max_iterations"] = max_iterations;
  state.counters["max_dp_m"] = dp;
  state.counters["max_dtheta_rad"] = dtheta;
}
BENCHMARK(BM_TsifIterationStats)
    ->ArgNames({"max_iterations", "minus_log10_tolerance"})
    ->Args({5, 0})
    ->Args({5, 2})
    ->Args({5, 6})
    ->Args({5, 12})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

// The covariance() query (Lambda^-1's base block), done on demand, outside the step.
void BM_TsifCovariance(benchmark::State& state) {
  const legkit::bench::TrotInputs& inputs = legkit::bench::trotInputs();
  legkit::invariant::Tsif filter;
  filter.reset(inputs.x0);
  for (std::size_t k = 0; k < 3000; ++k) filter.step(inputs.steps[k]);
  for (auto _ : state) benchmark::DoNotOptimize(filter.covariance());
}
BENCHMARK(BM_TsifCovariance)->Unit(benchmark::kMicrosecond);

}  // namespace
