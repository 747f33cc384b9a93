// The inputs every filter benchmark replays: 10 s of the default trot (Go2-class sensors, seed 1)
// turned into StepInputs by the log front end before any timing starts, so that only the
// filter's step is timed.
//
// runFilter(state, filter) times Estimator::step over the whole sequence, restarting from the
// true initial state each pass (the reset is excluded from the timing), and reports the time per
// step as the benchmark's time per iteration.
#pragma once

#include <benchmark/benchmark.h>

#include <vector>

#include "estimation/estimator.hpp"
#include "estimation/log_frontend.hpp"
#include "sim/simulator.hpp"

namespace legkit::bench {

struct TrotInputs {
  EstimateSample x0;
  std::vector<StepInput> steps;
};

inline const TrotInputs& trotInputs() {
  static const TrotInputs inputs = [] {
    sim::SimOptions options;
    options.duration = 10.0;
    const io::Log log = sim::simulate(options).log;
    TrotInputs result;
    const io::LogRow& first = log.rows.front();
    result.x0 = {first.t, first.gt_q, first.gt_v, first.gt_p};
    result.steps = LogFrontend(log.layout, model::QuadrupedKinematics()).inputs(log);
    return result;
  }();
  return inputs;
}

// Each benchmark iteration is one filter step; the sequence restarts (untimed) at its end.
inline void runFilter(benchmark::State& state, Estimator& filter) {
  const TrotInputs& inputs = trotInputs();
  filter.reset(inputs.x0);
  std::size_t k = 0;
  for (auto _ : state) {
    filter.step(inputs.steps[k]);
    benchmark::ClobberMemory();
    if (++k == inputs.steps.size()) {
      state.PauseTiming();
      filter.reset(inputs.x0);
      k = 0;
      state.ResumeTiming();
    }
  }
}

}  // namespace legkit::bench
