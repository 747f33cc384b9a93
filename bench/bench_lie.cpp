// Time per operation of lie/: SO(3), SE(3), SE_2(3), SE_6(3) (fixed K) and SE_6(3) with a
// run-time number of columns, plus the IMU propagation and the bias-augmented Phi.
//
// Every benchmark draws its inputs from 1024 elements (or tangents, or points) generated before
// the timing loop and cycles through them with index i & 1023, so that neither a constant input
// nor the random-number generator is timed. Results go through benchmark::DoNotOptimize.
// Inputs: uniformly random rotations with N(0, 1) columns; tangents with N(0, 1) components
// (rotation angles mostly between 0.5 and 3, i.e. both sides of the Taylor switches in
// so3_series.hpp), and, for the IMU, 1 kHz-sized increments. BM_LogSmall takes rotations of
// about 0.1 rad instead.
//
//   cmake --build build --target bench_lie && ./build/bench/bench_lie --benchmark_min_time=0.2
#include <benchmark/benchmark.h>

#include <lie/lie.hpp>
#include <random>
#include <vector>

namespace {

using lie::SE23d;
using lie::SE3d;
using lie::SO3d;
using SE63d = lie::SEK3<double, 6>;    // R, v, p, 4 feet with K fixed at compile time
using SE63dyn = lie::SEKd<double, 6>;  // the same with K chosen at run time (here 6)

constexpr std::size_t kN = 1024;
constexpr std::size_t kMask = kN - 1;

// How to draw random elements, tangents and points of each group.
template <typename G>
struct Draw {
  static constexpr Eigen::Index kCols = G::kDynamic ? G::MaxK : G::K;
  static G element(std::mt19937& gen) { return G::Random(gen, 1.0, kCols); }
  static typename G::Tangent tangent(std::mt19937& gen) {
    std::normal_distribution<double> n01;
    typename G::Tangent xi(3 + 3 * kCols);
    for (Eigen::Index i = 0; i < xi.size(); ++i) xi(i) = n01(gen);
    return xi;
  }
};

template <>
struct Draw<SO3d> {
  static SO3d element(std::mt19937& gen) { return SO3d::Random(gen); }
  static SO3d::Tangent tangent(std::mt19937& gen) {
    std::normal_distribution<double> n01;
    return SO3d::Tangent(n01(gen), n01(gen), n01(gen));
  }
};

template <typename G>
std::vector<G> elements() {
  std::mt19937 gen(42);
  std::vector<G> out;
  out.reserve(kN);
  for (std::size_t i = 0; i < kN; ++i) out.push_back(Draw<G>::element(gen));
  return out;
}

template <typename G>
std::vector<typename G::Tangent> tangents() {
  std::mt19937 gen(7);
  std::vector<typename G::Tangent> out;
  out.reserve(kN);
  for (std::size_t i = 0; i < kN; ++i) out.push_back(Draw<G>::tangent(gen));
  return out;
}

std::vector<Eigen::Vector3d> vectors(double scale, unsigned seed) {
  std::mt19937 gen(seed);
  std::normal_distribution<double> n01;
  std::vector<Eigen::Vector3d> out(kN);
  for (auto& v : out) v = scale * Eigen::Vector3d(n01(gen), n01(gen), n01(gen));
  return out;
}

// Group operations -------------------------------------------------------------------------

template <typename G>
void BM_Exp(benchmark::State& state) {
  const auto xi = tangents<G>();
  std::size_t i = 0;
  for (auto _ : state) {
    G X = G::Exp(xi[i++ & kMask]);
    benchmark::DoNotOptimize(X);
  }
}

template <typename G>
void BM_Log(benchmark::State& state) {
  const auto X = elements<G>();
  std::size_t i = 0;
  for (auto _ : state) {
    typename G::Tangent xi = X[i++ & kMask].Log();
    benchmark::DoNotOptimize(xi);
  }
}

// Log of small rotations, Exp of tangents scaled by 0.05 (angles ~0.1 rad, like an estimator's
// corrections): the small-angle branch of SO3::logOfMatrix, which Haar rotations rarely take.
template <typename G>
void BM_LogSmall(benchmark::State& state) {
  const auto xi = tangents<G>();
  std::vector<G> X;
  X.reserve(kN);
  for (const auto& t : xi) X.push_back(G::Exp(0.05 * t));
  std::size_t i = 0;
  for (auto _ : state) {
    typename G::Tangent out = X[i++ & kMask].Log();
    benchmark::DoNotOptimize(out);
  }
}

template <typename G>
void BM_Compose(benchmark::State& state) {
  const auto X = elements<G>();
  std::size_t i = 0;
  for (auto _ : state) {
    G Z = X[i & kMask] * X[(i + 1) & kMask];
    ++i;
    benchmark::DoNotOptimize(Z);
  }
}

template <typename G>
void BM_Inverse(benchmark::State& state) {
  const auto X = elements<G>();
  std::size_t i = 0;
  for (auto _ : state) {
    G Z = X[i++ & kMask].inverse();
    benchmark::DoNotOptimize(Z);
  }
}

template <typename G>
void BM_Act(benchmark::State& state) {
  const auto X = elements<G>();
  const auto x = vectors(1.0, 3);
  std::size_t i = 0;
  for (auto _ : state) {
    Eigen::Vector3d y = X[i & kMask].act(x[(i + 1) & kMask]);
    ++i;
    benchmark::DoNotOptimize(y);
  }
}

template <typename G>
void BM_Adj(benchmark::State& state) {
  const auto X = elements<G>();
  std::size_t i = 0;
  for (auto _ : state) {
    typename G::AdjointMatrix A = X[i++ & kMask].Adj();
    benchmark::DoNotOptimize(A);
  }
}

template <typename G>
void BM_Jr(benchmark::State& state) {
  const auto xi = tangents<G>();
  std::size_t i = 0;
  for (auto _ : state) {
    typename G::Jacobian J = G::Jr(xi[i++ & kMask]);
    benchmark::DoNotOptimize(J);
  }
}

template <typename G>
void BM_JrInv(benchmark::State& state) {
  const auto xi = tangents<G>();
  std::size_t i = 0;
  for (auto _ : state) {
    typename G::Jacobian J = G::JrInv(xi[i++ & kMask]);
    benchmark::DoNotOptimize(J);
  }
}

#define LIE_BENCH_GROUP(G)           \
  BENCHMARK_TEMPLATE(BM_Exp, G);     \
  BENCHMARK_TEMPLATE(BM_Log, G);     \
  BENCHMARK_TEMPLATE(BM_Compose, G); \
  BENCHMARK_TEMPLATE(BM_Inverse, G); \
  BENCHMARK_TEMPLATE(BM_Act, G);     \
  BENCHMARK_TEMPLATE(BM_Adj, G);     \
  BENCHMARK_TEMPLATE(BM_Jr, G);      \
  BENCHMARK_TEMPLATE(BM_JrInv, G)

LIE_BENCH_GROUP(SO3d);
LIE_BENCH_GROUP(SE3d);
BENCHMARK_TEMPLATE(BM_LogSmall, SO3d);
BENCHMARK_TEMPLATE(BM_LogSmall, SE3d);
LIE_BENCH_GROUP(SE23d);
LIE_BENCH_GROUP(SE63d);
LIE_BENCH_GROUP(SE63dyn);

// IMU: exact propagation and the bias-augmented Phi, as one InEKF prediction step uses them ----

const Eigen::Vector3d kGravity(0.0, 0.0, -9.81);
constexpr double kDt = 1e-3;

template <typename G>
void BM_ImuPropagate(benchmark::State& state) {
  const auto X = elements<G>();
  const auto w = vectors(1.0, 11);  // rad/s: theta = |w| dt ~ 1e-3, the Taylor side
  const auto a = vectors(3.0, 13);  // m/s^2
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++ & kMask;
    G Y = lie::imu::propagate(X[k], w[k], a[(k + 1) & kMask], kGravity, kDt);
    benchmark::DoNotOptimize(Y);
  }
}

template <typename G>
void BM_ImuPhiWithBias(benchmark::State& state) {
  const auto X = elements<G>();
  const auto w = vectors(1.0, 11);
  const auto a = vectors(3.0, 13);
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++ & kMask;
    auto F = lie::imu::phiWithBias(X[k], w[k], a[(k + 1) & kMask], kGravity, kDt);
    benchmark::DoNotOptimize(F);
  }
}

BENCHMARK_TEMPLATE(BM_ImuPropagate, SE23d);
BENCHMARK_TEMPLATE(BM_ImuPropagate, SE63d);
BENCHMARK_TEMPLATE(BM_ImuPropagate, SE63dyn);
BENCHMARK_TEMPLATE(BM_ImuPhiWithBias, SE63d);
BENCHMARK_TEMPLATE(BM_ImuPhiWithBias, SE63dyn);

}  // namespace
