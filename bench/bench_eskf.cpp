// Time per step of the error-state EKF on the default trot (bench/trot_inputs.hpp), and the cost
// of its error transition Phi next to the InEKF's (exercise 57.5.3): the ESKF's Phi depends on
// the estimate and the input, so it is built at every step; lie::imu::phiWithBias is the
// imperfect InEKF's Phi for the same 27-dimensional error (SE_6(3) plus the two biases).
#include <benchmark/benchmark.h>

#include <random>

#include "bench/trot_inputs.hpp"
#include "estimation/invariant/eskf.hpp"
#include "lie/imu_dynamics.hpp"
#include "lie/sek3.hpp"

namespace {

constexpr int kInputs = 1024;
constexpr double kDt = 1e-3;

void BM_EskfStep(benchmark::State& state) {
  legkit::invariant::Eskf filter;
  legkit::bench::runFilter(state, filter);
}
BENCHMARK(BM_EskfStep);

// Random inputs (1 kHz step, |w| ~ 1.6 rad/s, |a| ~ 5 m/s^2), made before the timing loop.
struct Inputs {
  std::vector<lie::SO3d> R;
  std::vector<Eigen::Vector3d> w, a;
  Inputs() {
    std::mt19937 gen(3);
    std::normal_distribution<double> n(0.0, 1.0);
    const auto draw = [&](double s) { return Eigen::Vector3d(s * n(gen), s * n(gen), s * n(gen)); };
    for (int k = 0; k < kInputs; ++k) {
      R.push_back(lie::SO3d::Random(gen));
      w.push_back(draw(1.0));
      a.push_back(draw(3.0));
    }
  }
};

void BM_EskfTransition(benchmark::State& state) {
  const Inputs in;
  legkit::invariant::eskf::State x;
  int k = 0;
  for (auto _ : state) {
    x.R = in.R[k];
    auto Phi = legkit::invariant::eskf::transition(x, {in.w[k], in.a[k]}, kDt);
    benchmark::DoNotOptimize(Phi);
    k = (k + 1) & (kInputs - 1);
  }
}
BENCHMARK(BM_EskfTransition);

void BM_InekfPhiWithBias(benchmark::State& state) {
  const Inputs in;
  std::vector<lie::SEK3<double, 6>> X;
  std::mt19937 gen(5);
  for (int k = 0; k < kInputs; ++k) X.push_back(lie::SEK3<double, 6>::Random(gen, 2.0));
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  int k = 0;
  for (auto _ : state) {
    auto Phi = lie::imu::phiWithBias(X[k], in.w[k], in.a[k], g, kDt);
    benchmark::DoNotOptimize(Phi);
    k = (k + 1) & (kInputs - 1);
  }
}
BENCHMARK(BM_InekfPhiWithBias);

}  // namespace
