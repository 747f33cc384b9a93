// Time per step of the linear Kalman filter (section 57.4) on 10 s of the default trot
// (bench/trot_inputs.hpp): attitude filter, prediction, and one stacked update of the stance feet
// and the leg-odometry velocity. Variants switch the velocity update and the attitude terms off.
#include <benchmark/benchmark.h>

#include "bench/trot_inputs.hpp"
#include "estimation/linear_kf/linear_kf.hpp"

namespace {

using legkit::linear_kf::LinearKf;
using legkit::linear_kf::LinearKfParams;

void BM_LinearKfStep(benchmark::State& state) {
  LinearKf filter;
  legkit::bench::runFilter(state, filter);
}
BENCHMARK(BM_LinearKfStep);

void BM_LinearKfStepNoLegVelocity(benchmark::State& state) {
  LinearKfParams params;
  params.use_leg_velocity = false;
  LinearKf filter(params);
  legkit::bench::runFilter(state, filter);
}
BENCHMARK(BM_LinearKfStepNoLegVelocity);

void BM_LinearKfStepChapterModel(benchmark::State& state) {
  // The chapter's plain filter: no leg velocity, no attitude terms, no acceleration compensation.
  LinearKfParams params;
  params.use_leg_velocity = false;
  params.model_attitude_error = false;
  params.accel_compensation_time = 0.0;
  LinearKf filter(params);
  legkit::bench::runFilter(state, filter);
}
BENCHMARK(BM_LinearKfStepChapterModel);

}  // namespace
