// Time for the four feet of one sample (positions and Jacobians) through model::LegKinematics:
// the analytic Go2 (QuadrupedLegKinematics) against the kit's Go2 MJCF loaded from a file by
// MujocoLegKinematics (one mj_kinematics + mj_comPos per sample, one mj_jac per foot).
//
// The samples cycle through 1024 joint vectors drawn uniformly within the Go2's limits before the
// timing loop, so every sample is a new q. Results go through benchmark::DoNotOptimize.
//
//   cmake -S . -B build -DLEGKIT_BUILD_BENCH=ON
//   cmake --build build --target bench_leg_kinematics && ./build/bench/bench_leg_kinematics
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "model/mjcf.hpp"
#include "model/mujoco_kinematics.hpp"
#include "model/quadruped_inertia.hpp"
#include "model/quadruped_leg_kinematics.hpp"

namespace {

using namespace legkit::model;

constexpr std::size_t kN = 1024;
constexpr std::size_t kMask = kN - 1;

std::vector<LegJointVector> go2Angles() {
  const QuadrupedGeometry g = QuadrupedGeometry::go2();
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<LegJointVector> qs(kN, LegJointVector::Zero());
  for (LegJointVector& q : qs) {
    for (int k = 0; k < 12; ++k) {
      const int leg = k / 3, j = k % 3;
      q[k] = g.q_min[leg][j] + (g.q_max[leg][j] - g.q_min[leg][j]) * unit(gen);
    }
  }
  return qs;
}

MujocoLegKinematics loadGo2() {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "legkit_bench_leg_kinematics_go2.xml";
  std::ofstream(path) << quadrupedMjcf(QuadrupedGeometry::go2(), QuadrupedInertia::go2());
  MujocoLegKinematics legs = MujocoLegKinematics::fromFile(
      path.string(), "base", {"FL_foot", "FR_foot", "RL_foot", "RR_foot"});
  std::filesystem::remove(path);
  return legs;
}

void allFeet(benchmark::State& state, const LegKinematics& legs) {
  const std::vector<LegJointVector> qs = go2Angles();
  Eigen::Vector3d p;
  FootJacobian J;
  std::size_t i = 0;
  for (auto _ : state) {
    const LegJointVector& q = qs[i++ & kMask];
    for (int foot = 0; foot < legs.numFeet(); ++foot) {
      legs.foot(foot, q, p, J);
      benchmark::DoNotOptimize(p);
      benchmark::DoNotOptimize(J);
    }
  }
}

void BM_FourFeet_Analytic(benchmark::State& state) {
  allFeet(state, QuadrupedLegKinematics());
}
BENCHMARK(BM_FourFeet_Analytic);

void BM_FourFeet_Mujoco(benchmark::State& state) {
  const MujocoLegKinematics legs = loadGo2();
  allFeet(state, legs);
}
BENCHMARK(BM_FourFeet_Mujoco);

}  // namespace
