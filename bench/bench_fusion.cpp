// Time per call of section 57.8's fusion (issue 15's targets: the loose pose update under 5 us,
// re-propagating 80 ms of 1 kHz history under 200 us, one smoother window update under 5 ms):
//   BM_MapOdomUpdate   MapOdomAlignment::update(z, odometry pose at z's stamp): the gate, the
//                      Kalman update of T_MO and its covariance (Joseph form)
//   BM_OdomHistoryAt   OdomHistory::at(t): the odometry pose at a stamp 80 ms old, interpolated
//   BM_DelayedPose     DelayedFilter<InvariantEkf>::updatePose with a pose 80 ms old: the update
//                      at its stamp and the re-propagation of the 80 samples since (1 kHz); the
//                      filter with its 0.5 s of history is restored (untimed) before each call
//   BM_DelayedStep     DelayedFilter<InvariantEkf>::step with its history full: the InEKF's step
//                      and the history's snapshot of it
//   BM_SmootherWindow  FixedLagSmoother: 0.1 s of input (100 samples at 1 kHz, the poses that
//                      arrived), i.e. one new keyframe and its window solve (2 s window, default
//                      options); restarted (untimed) when the 10 s run is used up, timed only
//                      once the window is full
//
// The data: 10 s of the default analytic trot (seed 1), the InEKF (default parameters) run over
// it for the odometry poses and covariances, the simulated SLAM poses of that truth
// (fusion::simulatePoses, default options: 10 Hz, 80 ms late); all made before any timing.
// Results go through benchmark::DoNotOptimize.
//
//   cmake --build build --target bench_fusion && ./build/bench/bench_fusion
#include <benchmark/benchmark.h>

#include <vector>

#include "estimation/fusion/delayed_filter.hpp"
#include "estimation/fusion/fixed_lag_smoother.hpp"
#include "estimation/fusion/map_odom.hpp"
#include "estimation/fusion/odom_history.hpp"
#include "estimation/fusion/pose_simulator.hpp"
#include "estimation/invariant/invariant_ekf.hpp"
#include "estimation/log_frontend.hpp"
#include "sim/simulator.hpp"

namespace {

using namespace legkit;

struct Setup {
  io::Log log;
  std::vector<fusion::OdomPose> odom;  // the InEKF's pose at each row
  std::vector<fusion::PoseMeasurement> poses;
  std::vector<fusion::OdomPose> odom_at_pose;  // the odometry at each pose's stamp
  std::vector<StepInput> inputs;
  Setup() {
    sim::SimOptions options;
    options.duration = 10.0;
    log = sim::simulate(options).log;
    inputs = LogFrontend(log.layout, model::QuadrupedKinematics()).inputs(log);
    const io::LogRow& first = log.rows.front();
    invariant::InvariantEkf filter;
    filter.reset({first.t, first.gt_q, first.gt_v, first.gt_p});
    for (const StepInput& in : inputs) {
      filter.step(in);
      const EstimateSample x = filter.estimate();
      const Eigen::Matrix<double, 9, 9>& P = filter.covariance()->P;
      fusion::OdomPose o{in.t, lie::SO3d::fromQuaternion(x.q), x.p, fusion::Matrix6d::Zero()};
      o.cov << P.block<3, 3>(0, 0), P.block<3, 3>(0, 6), P.block<3, 3>(6, 0), P.block<3, 3>(6, 6);
      odom.push_back(o);
    }
    poses = fusion::simulatePoses(log, fusion::PoseSimulatorOptions{}, 1).poses;
    fusion::OdomHistory history(odom.size());
    for (const fusion::OdomPose& o : odom) history.push(o);
    for (const fusion::PoseMeasurement& z : poses) odom_at_pose.push_back(history.at(z.t).pose);
  }
};

const Setup& setup() {
  static const Setup s;
  return s;
}

// One pose update per iteration, cycling through the run's poses; each pass shifts the stamps by
// the run's length so that they keep increasing (the alignment refuses a pose out of order).
void BM_MapOdomUpdate(benchmark::State& state) {
  const Setup& s = setup();
  const std::size_t n = s.poses.size();
  const double span = s.log.rows.back().t + 1.0;
  fusion::MapOdomAlignment alignment;
  std::size_t i = 0;
  double shift = 0.0;
  for (auto _ : state) {
    fusion::PoseMeasurement z = s.poses[i];
    fusion::OdomPose o = s.odom_at_pose[i];
    z.t += shift;
    z.t_arrival += shift;
    o.t = z.t;
    benchmark::DoNotOptimize(alignment.update(z, o));
    if (++i == n) {
      i = 0;
      shift += span;
    }
  }
  const fusion::MapOdomAlignment::Counts& c = alignment.counts();
  state.counters["rejected"] = c.rejected();
  state.counters["used"] = c.used + c.jump_updates + c.initialised;
}
BENCHMARK(BM_MapOdomUpdate);

// The odometry pose 80 ms before the newest sample of a 1024-sample (1 s) history.
void BM_OdomHistoryAt(benchmark::State& state) {
  const Setup& s = setup();
  fusion::OdomHistory history(1024);
  for (std::size_t k = 0; k < 2000; ++k) history.push(s.odom[k]);
  double t = history.newestTime() - 0.08;
  for (auto _ : state) {
    benchmark::DoNotOptimize(history.at(t));
    t += 1e-9;  // a new stamp each call, never past the newest sample
  }
}
BENCHMARK(BM_OdomHistoryAt);

// A pose stamped 80 ms before the newest of 2000 samples (the truth with 2 cm / 0.005 rad noise
// figures), applied to a copy of the delayed InEKF each iteration.
void BM_DelayedPose(benchmark::State& state) {
  const Setup& s = setup();
  constexpr std::size_t kNewest = 1999, kLate = 80;
  const io::LogRow& first = s.log.rows.front();
  fusion::DelayedFilter<invariant::InvariantEkf> ready{invariant::InvariantEkf{}};
  ready.reset({first.t, first.gt_q, first.gt_v, first.gt_p});
  for (std::size_t k = 0; k <= kNewest; ++k) ready.step(s.inputs[k]);
  const io::LogRow& stamp = s.log.rows[kNewest - kLate];
  fusion::PoseMeasurement z;
  z.t = s.inputs[kNewest - kLate].t;
  z.t_arrival = s.inputs[kNewest].t;
  z.R_MB = lie::SO3d::fromQuaternion(stamp.gt_q);
  z.p_MB = stamp.gt_p;
  z.cov.diagonal() << 2.5e-5, 2.5e-5, 2.5e-5, 4e-4, 4e-4, 4e-4;
  fusion::DelayedFilter<invariant::InvariantEkf> filter = ready;
  for (auto _ : state) {
    state.PauseTiming();
    filter = ready;
    state.ResumeTiming();
    benchmark::DoNotOptimize(filter.updatePose(z));
  }
  state.counters["replayed"] = filter.stats().last_replayed;
  state.counters["used"] = static_cast<double>(filter.stats().used);
}
BENCHMARK(BM_DelayedPose);

// One sample into the delayed InEKF with its 0.5 s of history full: the filter's step and its
// share of the history's snapshots. Goes on through the log's 10 s, restarting (untimed) at its
// end.
void BM_DelayedStep(benchmark::State& state) {
  const Setup& s = setup();
  const io::LogRow& first = s.log.rows.front();
  fusion::DelayedFilter<invariant::InvariantEkf> ready{invariant::InvariantEkf{}};
  ready.reset({first.t, first.gt_q, first.gt_v, first.gt_p});
  constexpr std::size_t kWarm = fusion::DelayedFilter<invariant::InvariantEkf>::kDefaultCapacity;
  for (std::size_t k = 0; k < kWarm; ++k) ready.step(s.inputs[k]);
  fusion::DelayedFilter<invariant::InvariantEkf> filter = ready;
  std::size_t k = kWarm;
  for (auto _ : state) {
    if (k == s.inputs.size()) {
      state.PauseTiming();
      filter = ready;
      k = kWarm;
      state.ResumeTiming();
    }
    filter.step(s.inputs[k++]);
    benchmark::DoNotOptimize(filter.estimate());
  }
}
BENCHMARK(BM_DelayedStep);

void BM_SmootherWindow(benchmark::State& state) {
  const Setup& s = setup();
  constexpr std::size_t kPerKeyframe = 100, kFull = 2100;  // samples: 0.1 s; past the 2 s window
  const io::LogRow& first = s.log.rows.front();
  const InitialState x0{{first.t, first.gt_q, first.gt_v, first.gt_p}};
  fusion::FixedLagSmoother smoother;
  std::size_t k = 0, pose = 0;
  // Feeds samples [k, end) and the poses that arrived by then.
  const auto feed = [&](std::size_t end) {
    for (; k < end; ++k) {
      smoother.addStep(s.inputs[k]);
      for (; pose < s.poses.size() && s.poses[pose].t_arrival <= s.inputs[k].t; ++pose) {
        smoother.addPose(s.poses[pose]);
      }
    }
  };
  const auto restart = [&] {
    smoother.initialise(x0);
    k = pose = 0;
    feed(kFull);
  };
  restart();
  double cpu = 0.0;
  for (auto _ : state) {
    if (k + kPerKeyframe > s.inputs.size()) {
      state.PauseTiming();
      restart();
      state.ResumeTiming();
    }
    feed(k + kPerKeyframe);
    cpu += smoother.stats().last_solve_cpu_s;
  }
  state.counters["solve_cpu_us"] =
      benchmark::Counter(1e6 * cpu, benchmark::Counter::kAvgIterations);
  state.counters["keyframes"] = smoother.stats().keyframes;
}
BENCHMARK(BM_SmootherWindow)->Unit(benchmark::kMillisecond);

}  // namespace
