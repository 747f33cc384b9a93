// Time per call of section 57.7's slip and terrain code (target: the slip check under 200 ns per
// foot): SlipDetector::check on four stance feet with a full 9 x 9 BaseCovariance (reported per
// call and, as a counter, per foot), SlipGuard::apply with the drop reaction on inputs where one
// foot in eight slides, and fitGroundPlane through four footholds.
//
// The calls cycle through 1024 inputs generated before the timing loop (index i & 1023): a level
// trunk walking at about 0.5 m/s, four feet under the hips with body-frame velocities that hold
// (plus a 0.3 m/s slide on one foot of every eighth input), gyro ~ 0.3 rad/s per axis, one sample
// every 1 ms. Results go through benchmark::DoNotOptimize.
//
//   cmake --build build --target bench_slip && ./build/bench/bench_slip
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <optional>
#include <random>
#include <vector>

#include "estimation/slip/plane_fit.hpp"
#include "estimation/slip/slip_guard.hpp"

namespace {

using legkit::BaseCovariance;
using legkit::EstimateSample;
using legkit::StepInput;

constexpr std::size_t kN = 1024;
constexpr std::size_t kMask = kN - 1;
constexpr int kFeet = 4;

struct Setup {
  std::vector<StepInput> inputs;
  std::vector<EstimateSample> estimates;
  std::vector<std::array<Eigen::Vector3d, kFeet>> footholds;
  BaseCovariance P;
  Setup() {
    std::mt19937 gen(57);
    std::normal_distribution<double> n(0.0, 1.0);
    const std::array<Eigen::Vector3d, kFeet> hips = {
        Eigen::Vector3d(0.19, 0.14, -0.3), Eigen::Vector3d(0.19, -0.14, -0.3),
        Eigen::Vector3d(-0.19, 0.14, -0.3), Eigen::Vector3d(-0.19, -0.14, -0.3)};
    Eigen::Matrix<double, 9, 9> L = Eigen::Matrix<double, 9, 9>::Identity() * 0.01;
    L(3, 0) = L(4, 1) = 0.005;
    P.P = L * L.transpose();
    for (std::size_t k = 0; k < kN; ++k) {
      EstimateSample x;
      x.t = 0.001 * k;
      x.q = Eigen::AngleAxisd(0.05 * n(gen), Eigen::Vector3d::UnitZ());
      x.v = Eigen::Vector3d(0.5 + 0.05 * n(gen), 0.05 * n(gen), 0.02 * n(gen));
      StepInput in;
      in.t = x.t + 0.001;
      in.dt = 0.001;
      in.imu.w_m = Eigen::Vector3d(0.3 * n(gen), 0.3 * n(gen), 0.3 * n(gen));
      in.imu.a_m = Eigen::Vector3d(0.5 * n(gen), 0.5 * n(gen), 9.81 + 0.5 * n(gen));
      const Eigen::Matrix3d R = x.q.toRotationMatrix();
      std::array<Eigen::Vector3d, kFeet> world{};
      for (int i = 0; i < kFeet; ++i) {
        legkit::ContactMeasurement& c = in.contacts[i];
        c.foot = i;
        c.p_body = hips[i] + 0.02 * Eigen::Vector3d(n(gen), n(gen), n(gen));
        c.cov = Eigen::Matrix3d::Identity() * 2.5e-5;
        const Eigen::Vector3d slide =
            (k % 8 == 0 && i == 1) ? Eigen::Vector3d(0.3, 0.0, 0.0) : Eigen::Vector3d::Zero();
        c.v_body = Eigen::Vector3d(-R.transpose() * (x.v + slide) - in.imu.w_m.cross(c.p_body));
        world[i] = R * c.p_body + Eigen::Vector3d(0.0, 0.0, 0.3 + 0.01 * n(gen));
      }
      in.num_contacts = kFeet;
      inputs.push_back(in);
      estimates.push_back(x);
      footholds.push_back(world);
    }
  }
};

const Setup& setup() {
  static const Setup s;
  return s;
}

void BM_SlipCheck(benchmark::State& state) {
  const Setup& s = setup();
  legkit::slip::SlipDetector detector;
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(detector.check(s.inputs[i & kMask], s.estimates[i & kMask], s.P));
    ++i;
  }
  state.counters["per_foot"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * kFeet,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_SlipCheck);

void BM_SlipGuardDrop(benchmark::State& state) {
  const Setup& s = setup();
  legkit::slip::SlipGuard guard(legkit::slip::SlipParams{}, legkit::slip::SlipReaction::kDrop);
  const std::optional<BaseCovariance> P = s.P;
  std::optional<StepInput> storage;
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        guard.apply(s.inputs[i & kMask], s.estimates[i & kMask], P, storage).num_contacts);
    ++i;
  }
}
BENCHMARK(BM_SlipGuardDrop);

void BM_GroundPlaneFit(benchmark::State& state) {
  const Setup& s = setup();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(legkit::slip::fitGroundPlane(s.footholds[i & kMask].data(), kFeet));
    ++i;
  }
}
BENCHMARK(BM_GroundPlaneFit);

}  // namespace
