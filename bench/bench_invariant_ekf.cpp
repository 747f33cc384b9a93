// Time per step of the right-invariant EKF on the default trot (bench/trot_inputs.hpp): four feet
// of capacity, IMU biases estimated, both discretisations (the kit's exact closed-form Phi and the
// reference implementation's first-order I + A dt), and the cost of the two parts of a step.
#include <benchmark/benchmark.h>

#include "bench/trot_inputs.hpp"
#include "estimation/invariant/invariant_ekf.hpp"

namespace {

using legkit::invariant::InvariantEkf;
using legkit::invariant::InvariantEkfParams;
using legkit::invariant::inekf::Discretisation;

InvariantEkfParams paramsWith(Discretisation discretisation) {
  InvariantEkfParams params;
  params.discretisation = discretisation;
  return params;
}

void BM_InekfStepExact(benchmark::State& state) {
  InvariantEkf filter(paramsWith(Discretisation::kExact));
  legkit::bench::runFilter(state, filter);
}
BENCHMARK(BM_InekfStepExact);

void BM_InekfStepFirstOrder(benchmark::State& state) {
  InvariantEkf filter(paramsWith(Discretisation::kFirstOrder));
  legkit::bench::runFilter(state, filter);
}
BENCHMARK(BM_InekfStepFirstOrder);

// Propagation alone: the trot's inputs with their contacts removed (no feet held, 15 states).
void BM_InekfPropagateOnly(benchmark::State& state) {
  const legkit::bench::TrotInputs& inputs = legkit::bench::trotInputs();
  std::vector<legkit::StepInput> steps = inputs.steps;
  for (legkit::StepInput& in : steps) in.num_contacts = 0;
  InvariantEkf filter;
  filter.reset(inputs.x0);
  std::size_t k = 0;
  for (auto _ : state) {
    filter.step(steps[k]);
    benchmark::ClobberMemory();
    if (++k == steps.size()) {
      state.PauseTiming();
      filter.reset(inputs.x0);
      k = 0;
      state.ResumeTiming();
    }
  }
}
BENCHMARK(BM_InekfPropagateOnly);

}  // namespace
