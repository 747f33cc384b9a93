// Time of `legkit allan`'s analysis (target: two hours of 1 kHz six-axis data in under 2 s):
// analyseImu on 7.2 million samples of the kit's Go2 IMU model at rest (model/imu_model.hpp,
// generated once before the timing loop): per axis the overlapping Allan deviation at octave
// averaging factors m = 1, 2, 4, ... up to a quarter of the record (21 of them), both line fits
// and the minimum. Also the same at about ten factors per decade (allanFactors(N, 10^0.1)).
//
//   cmake -S . -B build -DLEGKIT_BUILD_BENCH=ON && cmake --build build --target bench_allan
//   ./build/bench/bench_allan
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "estimation/imu/allan.hpp"
#include "model/imu_model.hpp"

namespace {

constexpr double kRate = 1000.0;           // [Hz]
constexpr std::size_t kSamples = 7200000;  // two hours

const legkit::imu::ImuRecording& twoHours() {
  static const legkit::imu::ImuRecording rec = [] {
    std::mt19937_64 gen(57);
    legkit::model::ImuBias bias;
    legkit::imu::ImuRecording r;
    r.tau0 = 1.0 / kRate;
    r.values.reserve(kSamples * legkit::imu::ImuRecording::kAxes);
    for (std::size_t k = 0; k < kSamples; ++k) {
      const legkit::model::ImuReading m = legkit::model::synthesiseReading(
          legkit::model::ImuNoise::go2(), r.tau0, Eigen::Matrix3d::Identity(),
          Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), bias, gen);
      r.values.insert(r.values.end(), m.w_m.data(), m.w_m.data() + 3);
      r.values.insert(r.values.end(), m.a_m.data(), m.a_m.data() + 3);
    }
    return r;
  }();
  return rec;
}

// The whole analysis: six axes, curves, lines, minima.
void BM_AnalyseTwoHoursSixAxes(benchmark::State& state) {
  const legkit::imu::ImuRecording& rec = twoHours();
  for (auto _ : state) {
    legkit::imu::AllanAnalysis analysis = legkit::imu::analyseImu(rec);
    benchmark::DoNotOptimize(analysis);
  }
  state.counters["taus"] = static_cast<double>(legkit::imu::allanFactors(kSamples).size());
}
BENCHMARK(BM_AnalyseTwoHoursSixAxes)->Unit(benchmark::kMillisecond)->Iterations(3);

// The same at about ten averaging factors per decade (60 of them), as `legkit allan
// --ratio 1.2589`.
void BM_AnalyseTwoHoursSixAxesDense(benchmark::State& state) {
  const legkit::imu::ImuRecording& rec = twoHours();
  legkit::imu::AllanOptions options;
  options.ratio = std::pow(10.0, 0.1);
  for (auto _ : state) {
    legkit::imu::AllanAnalysis analysis = legkit::imu::analyseImu(rec, options);
    benchmark::DoNotOptimize(analysis);
  }
  state.counters["taus"] =
      static_cast<double>(legkit::imu::allanFactors(kSamples, options.ratio).size());
}
BENCHMARK(BM_AnalyseTwoHoursSixAxesDense)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace
