// Time of one estimator step on detected contacts (sections 57.6-57.7), the whole per-sample
// path of `legkit run`: ContactPipeline::step (what a detector sees of the row, the detector, the
// stance feet weighted by p_c, the slip check against the filter's estimate and covariance, the
// reaction) and then the filter's step. Rows of a 10 s physics trot (seed 1), simulated before
// any timing. Contacts from the log's flags ("truth", the old path plus the rolling foot and
// the slip check), the Schmitt trigger on the foot sensor, or the recommended fallback chain (lazy:
// with every sensor healthy only its first detector runs). The target (issue 13): under 1 % of
// a 1 kHz loop, 10 us.
#include <benchmark/benchmark.h>

#include <memory>
#include <string>

#include "estimation/contact_pipeline.hpp"
#include "estimation/estimators.hpp"
#include "sim/physics_simulator.hpp"

namespace {

using namespace legkit;

const io::Log& trotLog() {
  static const io::Log log = [] {
    sim::PhysicsOptions options = sim::PhysicsOptions::forScenario("physics-trot");
    options.duration = 10.0;
    return sim::simulatePhysics(options).log;
  }();
  return log;
}

// Each iteration: one row through the pipeline and the filter; the log restarts (untimed) at its
// end.
void BM_PipelineStep(benchmark::State& state, const std::string& estimator,
                     const std::string& contact, slip::SlipReaction reaction) {
  const io::Log& log = trotLog();
  PipelineOptions options;
  options.contact = contact;
  options.slip = reaction;
  // The planned gait for the chain's gait clock: GaitSchedule's defaults are the 2 Hz trot.
  contact::DetectorContext context;
  context.gait = contact::GaitSchedule{};
  context.gait->start = sim::physicsScenarioByName("physics-trot").stand_time;
  ContactPipeline pipeline(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, options,
                           context);
  const std::unique_ptr<Estimator> e = makeEstimator(estimator);
  Estimator& filter = *e;
  const io::LogRow& first = log.rows.front();
  const EstimateSample x0{first.t, first.gt_q, first.gt_v, first.gt_p};
  filter.reset(x0);
  pipeline.reset();
  std::size_t k = 0;
  for (auto _ : state) {
    const double dt = k == 0 ? 0.0 : log.rows[k].t - log.rows[k - 1].t;
    filter.step(pipeline.step(log.rows[k], dt, filter.estimate(), filter.covariance()));
    benchmark::ClobberMemory();
    if (++k == log.rows.size()) {
      state.PauseTiming();
      filter.reset(x0);
      pipeline.reset();
      k = 0;
      state.ResumeTiming();
    }
  }
}

using slip::SlipReaction;
BENCHMARK_CAPTURE(BM_PipelineStep, eskf_truth, "eskf", "truth", SlipReaction::kNone);
BENCHMARK_CAPTURE(BM_PipelineStep, eskf_schmitt_inflate, "eskf", "schmitt", SlipReaction::kInflate);
BENCHMARK_CAPTURE(BM_PipelineStep, eskf_fallback_inflate, "eskf", "fallback",
                  SlipReaction::kInflate);
BENCHMARK_CAPTURE(BM_PipelineStep, inekf_truth, "invariant-ekf", "truth", SlipReaction::kNone);
BENCHMARK_CAPTURE(BM_PipelineStep, inekf_schmitt_inflate, "invariant-ekf", "schmitt",
                  SlipReaction::kInflate);
BENCHMARK_CAPTURE(BM_PipelineStep, inekf_fallback_inflate, "invariant-ekf", "fallback",
                  SlipReaction::kInflate);

}  // namespace
