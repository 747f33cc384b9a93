// Time per step of the two-state implicit filter (section 57.5) on the default trot
// (bench/trot_inputs.hpp: 10 s, Go2-class sensors, seed 1), with one and with two Gauss-Newton
// iterations per step.
//
//   cmake --build build --target bench_tsif && ./build/bench/bench_tsif --benchmark_min_time=0.2
#include <benchmark/benchmark.h>

#include "bench/trot_inputs.hpp"
#include "estimation/invariant/tsif.hpp"

namespace {

void BM_TsifStep(benchmark::State& state) {
  legkit::invariant::TsifParams params;
  params.iterations = static_cast<int>(state.range(0));
  legkit::invariant::Tsif filter(params);
  legkit::bench::runFilter(state, filter);
}
BENCHMARK(BM_TsifStep)->ArgName("iterations")->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

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
