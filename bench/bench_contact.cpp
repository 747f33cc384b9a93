// Time per sample of the contact detectors of legkit_contact (section 57.6; issue 13's target:
// under 50 ns per foot per sample), each on four feet: the gait clock, the GRF threshold and the
// Schmitt trigger on the foot sensor, the same two on the force from joint torques, the kinematic
// detector, the force from joint torques alone (one h(q, nu) by RNEA for the robot plus four 3x3
// solves: it costs what model::QuadrupedDynamics costs, bench_dynamics), and two fallback chains
// (every detector of a chain runs on every sample, so a chain costs the sum of its detectors).
// The counter ns_per_foot is the time per update divided by 4.
//
// Inputs: 1024 samples generated before the timing loop (index i & 1023) of a robot trotting in
// place at 2 Hz: joint angles swinging +-0.3 rad about a standing pose, their rates, torques of
// that order, foot forces from 0 to 60 N (so the triggers switch), a base rocking by a few
// degrees; 1 ms apart.
//
//   cmake -S . -B build -DLEGKIT_BUILD_BENCH=ON && cmake --build build --target bench_contact
//   ./build/bench/bench_contact
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "estimation/contact/detectors.hpp"
#include "estimation/contact/fallback_detector.hpp"
#include "estimation/contact/foot_force.hpp"
#include "estimation/contact/gait_clock.hpp"

namespace {

using namespace legkit;

constexpr std::size_t kN = 1024;
constexpr std::size_t kMask = kN - 1;

const std::vector<contact::ContactSignals>& samples() {
  static const std::vector<contact::ContactSignals> signals = [] {
    const model::QuadrupedKinematics kin;
    std::mt19937 gen(13);
    std::normal_distribution<double> n(0.0, 1.0);
    std::vector<contact::ContactSignals> out;
    for (std::size_t k = 0; k < kN; ++k) {
      const double t = 0.001 * static_cast<double>(k), w = 2.0 * M_PI * 2.0;
      contact::ContactSignals s;
      s.t = t;
      s.dt = 0.001;
      s.base.valid = true;
      s.base.R =
          Eigen::AngleAxisd(0.05 * std::sin(w * t), Eigen::Vector3d::UnitX()).toRotationMatrix();
      s.base.v = Eigen::Vector3d(0.0, 0.0, 0.05 * std::cos(w * t));
      s.base.p = Eigen::Vector3d(0.0, 0.0, 0.3);
      s.gyro = Eigen::Vector3d(0.05 * w * std::cos(w * t), 0.0, 0.0) +
               0.1 * Eigen::Vector3d(n(gen), n(gen), n(gen));
      s.acc = s.base.R.transpose() * Eigen::Vector3d(0.0, 0.0, 9.81);
      s.has_joints = s.has_torque = true;
      for (int leg = 0; leg < model::kNumLegs; ++leg) {
        const double phase = w * t + (leg == 1 || leg == 2 ? M_PI : 0.0);
        const Eigen::Vector3d q(0.0, 0.8 + 0.3 * std::sin(phase), -1.6 + 0.3 * std::cos(phase));
        const Eigen::Vector3d dq(0.0, 0.3 * w * std::cos(phase), -0.3 * w * std::sin(phase));
        s.q.segment<3>(3 * leg) = q;
        s.dq.segment<3>(3 * leg) = dq;
        s.tau.segment<3>(3 * leg) = Eigen::Vector3d(n(gen), 5.0 * n(gen), 10.0 * n(gen));
        contact::FootSignals& f = s.feet[leg];
        f.force = std::max(0.0, 60.0 * std::sin(phase) + 2.0 * n(gen));
        f.has_kinematics = true;
        f.p_body = kin.footPosition(leg, q);
        f.v_body = kin.footJacobian(leg, q) * dq;
      }
      out.push_back(s);
    }
    return out;
  }();
  return signals;
}

void perFoot(benchmark::State& state) {
  state.counters["ns_per_foot"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * model::kNumLegs,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// One detector by its makeDetector name.
void BM_Detector(benchmark::State& state, const char* name) {
  contact::DetectorContext context;
  context.gait = contact::GaitSchedule{};
  const std::unique_ptr<contact::ContactDetector> d = contact::makeDetector(name, context);
  const std::vector<contact::ContactSignals>& s = samples();
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(d->update(s[i++ & kMask]));
  perFoot(state);
}
BENCHMARK_CAPTURE(BM_Detector, gait_clock, "gait-clock");
BENCHMARK_CAPTURE(BM_Detector, grf_threshold, "grf-threshold");
BENCHMARK_CAPTURE(BM_Detector, schmitt, "schmitt");
BENCHMARK_CAPTURE(BM_Detector, kinematic, "kinematic");
BENCHMARK_CAPTURE(BM_Detector, grf_threshold_torque, "grf-threshold-torque");
BENCHMARK_CAPTURE(BM_Detector, schmitt_torque, "schmitt-torque");
// The recommended chain: schmitt > momentum-observer > kinematic > gait-clock (lazy: healthy
// sensors, Schmitt's cost).
BENCHMARK_CAPTURE(BM_Detector, fallback, "fallback");

// The force from joint torques alone.
void BM_FootForceFromTorque(benchmark::State& state) {
  const contact::FootForceFromTorque ff(model::QuadrupedGeometry::go2(),
                                        model::QuadrupedInertia::go2());
  const std::vector<contact::ContactSignals>& s = samples();
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(ff.estimate(s[i++ & kMask]));
  perFoot(state);
}
BENCHMARK(BM_FootForceFromTorque);

// A chain without the model-based detectors: schmitt > kinematic > gait-clock.
void BM_SensorChain(benchmark::State& state) {
  contact::DetectorContext context;
  context.gait = contact::GaitSchedule{};
  std::vector<std::unique_ptr<contact::ContactDetector>> chain;
  for (const char* n : {"schmitt", "kinematic", "gait-clock"})
    chain.push_back(contact::makeDetector(n, context));
  contact::FallbackDetector d(std::move(chain));
  const std::vector<contact::ContactSignals>& s = samples();
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(d.update(s[i++ & kMask]));
  perFoot(state);
}
BENCHMARK(BM_SensorChain);

}  // namespace
