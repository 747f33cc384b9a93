// Time per sample of the two learned/model-based contact detectors of section 57.6 (issue 13's
// target: under 50 ns per foot per sample): the logistic contact probability ("probabilistic",
// estimation/contact/logistic_contact.hpp) and the generalized momentum observer
// ("momentum-observer", momentum_observer.hpp), each on four feet; the figure per foot is the
// time per update divided by 4 (measured, CPU time at a load of 6-8 on 2 cores: 41 ns and
// 1.18 us per foot). The observer computes M (CRBA), h (RNEA) and the four feet's
// J_c at every sample and solves a 12 x 12 system: it cannot meet 50 ns per foot, and the
// benchmark says by how much.
//
// Inputs: 1024 samples generated before the timing loop (index i & 1023) of a robot trotting in
// place: joint angles swinging +-0.3 rad about a standing pose at 2 Hz, their rates, torques and
// foot forces of that order, a base rocking by a few degrees; 1 ms apart. The logistic model's
// weights are fitted by trainLogistic on a synthetic set (their values do not change the cost).
//
//   cmake --build build --target bench_contact_learned && ./build/bench/bench_contact_learned
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "estimation/contact/logistic_contact.hpp"
#include "estimation/contact/logistic_training.hpp"
#include "estimation/contact/momentum_observer.hpp"

namespace {

using namespace legkit;

constexpr std::size_t kN = 1024;
constexpr std::size_t kMask = kN - 1;

struct Setup {
  model::QuadrupedGeometry geometry = model::QuadrupedGeometry::go2();
  model::QuadrupedInertia inertia = model::QuadrupedInertia::go2();
  std::vector<contact::ContactSignals> signals;
  contact::LogisticModel model;
  contact::GaitSchedule gait;

  Setup() {
    const model::QuadrupedKinematics kin(geometry);
    std::mt19937 gen(13);
    std::normal_distribution<double> n(0.0, 1.0);
    for (std::size_t k = 0; k < kN; ++k) {
      const double t = 0.001 * static_cast<double>(k), w = 2.0 * M_PI * 2.0;
      contact::ContactSignals s;
      s.t = t;
      s.dt = 0.001;
      s.base.valid = true;
      s.base.R =
          Eigen::AngleAxisd(0.05 * std::sin(w * t), Eigen::Vector3d::UnitX()).toRotationMatrix();
      s.base.v = Eigen::Vector3d(0.5, 0.0, 0.05 * std::cos(w * t));
      s.gyro = Eigen::Vector3d(0.05 * w * std::cos(w * t), 0.0, 0.0) +
               0.1 * Eigen::Vector3d(n(gen), n(gen), n(gen));
      s.has_joints = s.has_torque = true;
      for (int leg = 0; leg < model::kNumLegs; ++leg) {
        const double phase = w * t + (leg == 1 || leg == 2 ? M_PI : 0.0);
        const Eigen::Vector3d q(0.0, 0.8 + 0.3 * std::sin(phase), -1.6 + 0.3 * std::cos(phase));
        const Eigen::Vector3d dq(0.0, 0.3 * w * std::cos(phase), -0.3 * w * std::sin(phase));
        s.q.segment<3>(3 * leg) = q;
        s.dq.segment<3>(3 * leg) = dq;
        s.tau.segment<3>(3 * leg) = Eigen::Vector3d(n(gen), 5.0 * n(gen), 10.0 * n(gen));
        contact::FootSignals& f = s.feet[leg];
        f.force = std::max(0.0, 60.0 * std::sin(phase));
        f.has_kinematics = true;
        f.p_body = kin.footPosition(leg, q);
        f.v_body = kin.footJacobian(leg, q) * dq;
      }
      signals.push_back(s);
    }
    // A model fitted to force > 20 N as the label.
    std::vector<contact::ContactFeatures> x;
    std::vector<bool> y;
    for (const contact::ContactSignals& s : signals)
      for (int leg = 0; leg < model::kNumLegs; ++leg) {
        x.push_back(contact::contactFeatures(s, leg, &gait));
        y.push_back(s.feet[leg].force + 10.0 * n(gen) > 20.0);
      }
    model = contact::trainLogistic(x, y);
  }
};

const Setup& setup() {
  static const Setup s;
  return s;
}

void BM_LogisticDetector(benchmark::State& state) {
  const Setup& s = setup();
  contact::LogisticContactDetector d(s.model, s.gait);
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(d.update(s.signals[i++ & kMask]));
  state.counters["ns_per_foot"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * model::kNumLegs,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_LogisticDetector);

void BM_MomentumObserver(benchmark::State& state) {
  const Setup& s = setup();
  contact::MomentumObserver d(s.geometry, s.inertia);
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(d.update(s.signals[i++ & kMask]));
  state.counters["ns_per_foot"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * model::kNumLegs,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_MomentumObserver);

}  // namespace
