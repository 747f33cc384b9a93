// Time per call of the floating-base dynamics (model/floating_base_dynamics.hpp): the mass matrix
// M(q) (CRBA), the bias forces h(q, nu) (RNEA), both together (what a momentum observer needs at
// every sample), and the four feet's J_c.
//
// The calls cycle through 1024 random states generated before the timing loop (index i & 1023):
// any attitude, joint angles uniform within the limits, |v| ~ 1 m/s, |omega| ~ 2 rad/s and
// |dq| ~ 5 rad/s per axis (the states of test_model_floating_base_dynamics). Results go through
// benchmark::DoNotOptimize.
//
//   cmake --build build --target bench_dynamics && ./build/bench/bench_dynamics
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "model/floating_base_dynamics.hpp"

namespace {

using legkit::model::FloatingBaseState;
using legkit::model::kNumLegs;
using legkit::model::QuadrupedDynamics;
using legkit::model::QuadrupedGeometry;
using legkit::model::QuadrupedInertia;

constexpr std::size_t kN = 1024;
constexpr std::size_t kMask = kN - 1;

struct Setup {
  QuadrupedGeometry geometry = QuadrupedGeometry::go2();
  QuadrupedDynamics dynamics{geometry, QuadrupedInertia::go2()};
  std::vector<FloatingBaseState> states;
  Setup() {
    std::mt19937 gen(12);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::normal_distribution<double> n(0.0, 1.0);
    for (std::size_t k = 0; k < kN; ++k) {
      FloatingBaseState x;
      x.p = Eigen::Vector3d(n(gen), n(gen), n(gen));
      x.R = Eigen::Quaterniond(n(gen), n(gen), n(gen), n(gen)).normalized().toRotationMatrix();
      x.v = Eigen::Vector3d(n(gen), n(gen), n(gen));
      x.omega = 2.0 * Eigen::Vector3d(n(gen), n(gen), n(gen));
      for (int leg = 0; leg < kNumLegs; ++leg) {
        for (int j = 0; j < 3; ++j) {
          const double lo = geometry.q_min[leg][j], hi = geometry.q_max[leg][j];
          x.q[3 * leg + j] = lo + (hi - lo) * unit(gen);
          x.dq[3 * leg + j] = 5.0 * n(gen);
        }
      }
      states.push_back(x);
    }
  }
};

const Setup& setup() {
  static const Setup s;
  return s;
}

// Times `call` on the precomputed states in turn: the loop every benchmark below shares.
template <typename Call>
void timeOnStates(benchmark::State& state, const Call& call) {
  const Setup& s = setup();
  std::size_t i = 0;
  for (auto _ : state) call(s.dynamics, s.states[i++ & kMask]);
}

void BM_MassMatrix(benchmark::State& state) {
  timeOnStates(state, [](const QuadrupedDynamics& d, const FloatingBaseState& x) {
    auto M = d.massMatrix(x);
    benchmark::DoNotOptimize(M);
  });
}
BENCHMARK(BM_MassMatrix);

void BM_BiasForces(benchmark::State& state) {
  timeOnStates(state, [](const QuadrupedDynamics& d, const FloatingBaseState& x) {
    auto h = d.biasForces(x);
    benchmark::DoNotOptimize(h);
  });
}
BENCHMARK(BM_BiasForces);

void BM_MassMatrixAndBiasForces(benchmark::State& state) {
  timeOnStates(state, [](const QuadrupedDynamics& d, const FloatingBaseState& x) {
    auto M = d.massMatrix(x);
    auto h = d.biasForces(x);
    benchmark::DoNotOptimize(M);
    benchmark::DoNotOptimize(h);
  });
}
BENCHMARK(BM_MassMatrixAndBiasForces);

void BM_FootJacobians(benchmark::State& state) {  // all four feet
  timeOnStates(state, [](const QuadrupedDynamics& d, const FloatingBaseState& x) {
    for (int leg = 0; leg < kNumLegs; ++leg) {
      auto J = d.footJacobian(leg, x);
      benchmark::DoNotOptimize(J);
    }
  });
}
BENCHMARK(BM_FootJacobians);

}  // namespace
