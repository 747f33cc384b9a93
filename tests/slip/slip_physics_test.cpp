// Section 57.7 against physics (seed 3): the slip detector fed by the ESKF
// (estimation/invariant/eskf.hpp) on the log's contact flags (LogFrontend), with the filter's
// previous estimate and covariance, scored on the simulator's true slip (gt_feet[].slip_speed).
// Figures (print them with `test_slip_physics -s`):
//  - physics-ice, 8 s (FR foot on a mu 0.1 patch, naive controller): every one of the 39 true
//    slips (slip speed above 0.1 m/s for more than 20 ms, in contact) detected, delay median 2 ms,
//    max 3 ms (the 3-sample confirmation);
//  - physics-trot, 30 s (dry, mu 0.6): 10 false alarms per minute (a detection with the foot's true
//    slip speed at or below 0.1 m/s from 20 ms before to 20 ms after it; the touchdowns' short
//    true slides are not false); the all-feet test never fires;
//  - physics-ice-push, 5 s (every foot on ice, pushed sideways at 3 s): every foot slides from
//    3.093 s, the all-feet test (57.7.2) fires at 3.116 s (23 ms) and never before the push;
//  - terrain (TerrainClassifier on the detector's flags and the true ground forces): physics-trot
//    normal (mu_hat 0.51, lower bound 0.60, true 0.6), physics-ice-push ice (mu_hat 0.090, true
//    0.1); physics-ice, whose patch is under one foot only, normal (mu_hat 0.36);
//  - the filter's velocity RMSE with the reactions: physics-ice none 0.072, drop 0.043 m/s;
//    physics-ice-push none 0.079, imu-only 0.047 m/s.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <vector>

#include "estimation/invariant/eskf.hpp"
#include "estimation/log_frontend.hpp"
#include "estimation/slip/slip_guard.hpp"
#include "estimation/slip/terrain.hpp"
#include "model/quadruped.hpp"
#include "sim/physics_simulator.hpp"

using namespace legkit;  // NOLINT(google-build-using-namespace)
using Approx = Catch::Detail::Approx;

namespace {

constexpr double kSlipSpeed = 0.1;      // a true slip: slip speed above this [m/s]
constexpr double kSlipDuration = 0.02;  // for longer than this [s]

io::Log simulate(const std::string& scenario, double duration) {
  sim::PhysicsOptions o = sim::PhysicsOptions::forScenario(scenario);
  o.duration = duration;
  o.seed = 3;
  const sim::PhysicsResult r = sim::simulatePhysics(o);
  REQUIRE_FALSE(r.status.fell);
  return r.log;
}

struct Replay {
  const io::Log* log = nullptr;
  std::vector<slip::SlipReport> reports;  // per row
  double velocity_rmse = 0.0;             // of the filter's world velocity [m/s]
};

// The ESKF on the log's contact flags, the guard (reaction `reaction`) between the input and the
// filter, checked against the filter's previous estimate and covariance.
Replay replay(const io::Log& log, slip::SlipReaction reaction) {
  Replay r;
  r.log = &log;
  const std::vector<StepInput> inputs =
      LogFrontend(log.layout, model::QuadrupedKinematics()).inputs(log);
  invariant::Eskf filter;
  EstimateSample x0;
  x0.t = log.rows[0].t;
  x0.q = log.rows[0].gt_q;
  x0.v = log.rows[0].gt_v;
  x0.p = log.rows[0].gt_p;
  filter.reset(x0);
  slip::SlipGuard guard(slip::SlipParams{}, reaction);
  std::optional<StepInput> storage;
  r.reports.resize(inputs.size());
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    const StepInput& in =
        guard.apply(inputs[k], filter.estimate(), filter.covariance(), storage, &r.reports[k]);
    filter.step(in);
    r.velocity_rmse += (filter.estimate().v - log.rows[k].gt_v).squaredNorm();
  }
  r.velocity_rmse = std::sqrt(r.velocity_rmse / inputs.size());
  return r;
}

struct Episode {
  int foot;
  double start, end;  // [s]
};

// The true slip episodes: a foot in contact sliding faster than kSlipSpeed for > kSlipDuration.
std::vector<Episode> trueSlips(const io::Log& log) {
  std::vector<Episode> out;
  for (int foot = 0; foot < io::kNumLegs; ++foot) {
    double start = -1.0;
    for (std::size_t k = 0; k <= log.rows.size(); ++k) {
      const bool on = k < log.rows.size() && log.rows[k].gt_feet[foot].contact &&
                      log.rows[k].gt_feet[foot].slip_speed > kSlipSpeed;
      if (on && start < 0.0) start = log.rows[k].t;
      if (!on && start >= 0.0) {
        const double end = log.rows[k - 1].t;
        if (end - start > kSlipDuration) out.push_back({foot, start, end});
        start = -1.0;
      }
    }
  }
  return out;
}

// Detection episodes of one foot: maximal runs of rows the report calls it slipping. False when the
// foot's true slip speed stays at or below kSlipSpeed from 20 ms before to 20 ms after it.
struct Alarms {
  int episodes = 0, false_alarms = 0;
};
Alarms alarms(const Replay& r) {
  Alarms a;
  const std::size_t n = r.log->rows.size();
  for (int foot = 0; foot < io::kNumLegs; ++foot) {
    std::size_t k = 0;
    while (k < n) {
      if (!r.reports[k].slipping(foot)) {
        ++k;
        continue;
      }
      std::size_t end = k;
      while (end < n && r.reports[end].slipping(foot)) ++end;
      bool true_slip = false;
      for (std::size_t j = k >= 20 ? k - 20 : 0; j < std::min(n, end + 20); ++j) {
        true_slip = true_slip || r.log->rows[j].gt_feet[foot].slip_speed > kSlipSpeed;
      }
      ++a.episodes;
      a.false_alarms += true_slip ? 0 : 1;
      k = end;
    }
  }
  return a;
}

// The terrain class at the end of a replay, from the detector's slip flags and the true ground
// forces (|f_t| along x: only its magnitude matters).
slip::TerrainClassifier terrain(const Replay& r) {
  slip::TerrainClassifier c;
  std::array<Eigen::Vector3d, io::kNumLegs> f;
  for (std::size_t k = 0; k < r.reports.size(); ++k) {
    const io::LogRow& row = r.log->rows[k];
    for (int i = 0; i < io::kNumLegs; ++i) {
      f[i] = Eigen::Vector3d(row.gt_feet[i].tangential_force, 0.0, row.gt_feet[i].normal_force);
    }
    c.update(r.reports[k], f.data(), io::kNumLegs, k == 0 ? 0.0 : row.t - r.log->rows[k - 1].t);
  }
  return c;
}

// Onsets of the all-feet test (SlipReport::imu_disagrees).
std::vector<double> allFeetOnsets(const Replay& r) {
  std::vector<double> t;
  for (std::size_t k = 0; k < r.reports.size(); ++k) {
    if (r.reports[k].imu_disagrees && (k == 0 || !r.reports[k - 1].imu_disagrees)) {
      t.push_back(r.log->rows[k].t);
    }
  }
  return t;
}

}  // namespace

TEST_CASE("physics-ice: every true slip detected within 10 ms; slip handling helps the ESKF",
          "[57.7][slip][physics]") {
  const io::Log log = simulate("physics-ice", 8.0);
  const Replay ice = replay(log, slip::SlipReaction::kNone);
  const std::vector<Episode> slips = trueSlips(log);
  std::vector<double> delays;
  for (const Episode& e : slips) {
    for (std::size_t k = 0; k < log.rows.size(); ++k) {
      const double t = log.rows[k].t;
      if (t >= e.start && t <= e.end && ice.reports[k].slipping(e.foot)) {
        delays.push_back(t - e.start);
        break;
      }
    }
  }
  std::sort(delays.begin(), delays.end());
  const Alarms a = alarms(ice);
  std::printf(
      "physics-ice 8 s: %zu true slips (> %.1f m/s for > %.0f ms), %zu detected; delay "
      "median %.1f ms, max %.1f ms; %d detections, %d with no true slip\n",
      slips.size(), kSlipSpeed, 1e3 * kSlipDuration, delays.size(),
      delays.empty() ? -1.0 : 1e3 * delays[delays.size() / 2],
      delays.empty() ? -1.0 : 1e3 * delays.back(), a.episodes, a.false_alarms);
  CHECK(slips.size() >= 20);
  CHECK(delays.size() == slips.size());
  REQUIRE_FALSE(delays.empty());
  CHECK(delays[delays.size() / 2] <= 0.005);
  CHECK(delays.back() <= 0.010);

  const Replay drop = replay(log, slip::SlipReaction::kDrop);
  const Replay inflate = replay(log, slip::SlipReaction::kInflate);
  std::printf("physics-ice ESKF velocity RMSE: none %.4f, inflate %.4f, drop %.4f m/s\n",
              ice.velocity_rmse, inflate.velocity_rmse, drop.velocity_rmse);
  CHECK(drop.velocity_rmse < 0.8 * ice.velocity_rmse);
  CHECK(inflate.velocity_rmse < 0.8 * ice.velocity_rmse);
  const slip::TerrainClassifier t = terrain(ice);
  std::printf(
      "physics-ice terrain %s: mu_hat %.3f from %d onsets, lower bound %.3f, %.2f slips/s, "
      "slipping %.3f of stance\n",
      slip::terrainClassName(t.terrain()), t.frictionEstimate(), t.onsets(), t.frictionLowerBound(),
      t.slipRate(), t.slipFraction());
  // The patch is under the FR foot's path only: the other feet's touchdown slides are at mu 0.6.
  CHECK(t.terrain() == slip::TerrainClass::kNormal);
  CHECK(t.frictionEstimate() < 0.5);
  CHECK(t.frictionLowerBound() <= 0.6 * 1.05);
}

TEST_CASE("physics-trot (dry): false alarms below 20 per minute, the all-feet test silent",
          "[57.7][slip][physics]") {
  const io::Log log = simulate("physics-trot", 30.0);
  const Replay dry = replay(log, slip::SlipReaction::kNone);
  const Alarms a = alarms(dry);
  const double minutes = (log.rows.back().t - log.rows.front().t) / 60.0;
  const std::vector<double> all = allFeetOnsets(dry);
  std::printf("physics-trot 30 s: %d detections, %d false (%.1f per minute); all-feet onsets %zu\n",
              a.episodes, a.false_alarms, a.false_alarms / minutes, all.size());
  CHECK(a.false_alarms / minutes < 20.0);
  const slip::TerrainClassifier t = terrain(dry);
  std::printf(
      "physics-trot terrain %s: mu_hat %.3f from %d onsets, lower bound %.3f, %.2f slips/s, "
      "slipping %.3f of stance\n",
      slip::terrainClassName(t.terrain()), t.frictionEstimate(), t.onsets(), t.frictionLowerBound(),
      t.slipRate(), t.slipFraction());
  CHECK(all.empty());
  CHECK(t.terrain() == slip::TerrainClass::kNormal);  // mu 0.6
  CHECK(t.frictionEstimate() > 0.4);
  CHECK(t.frictionEstimate() < 0.7);
  CHECK(t.frictionLowerBound() <= 0.6 * 1.05);
}

TEST_CASE("physics-ice-push: every foot slides and the IMU sees it (57.7.2)",
          "[57.7][slip][physics]") {
  const io::Log log = simulate("physics-ice-push", 5.0);
  double truth_start = -1.0;  // first row where every foot slides faster than kSlipSpeed
  for (const io::LogRow& row : log.rows) {
    bool all = true;
    for (int f = 0; f < io::kNumLegs; ++f) all = all && row.gt_feet[f].slip_speed > kSlipSpeed;
    if (all) {
      truth_start = row.t;
      break;
    }
  }
  const Replay none = replay(log, slip::SlipReaction::kNone);
  const std::vector<double> onsets = allFeetOnsets(none);
  std::printf(
      "physics-ice-push: every foot slides from %.3f s; all-feet test first fires at "
      "%.3f s\n",
      truth_start, onsets.empty() ? -1.0 : onsets.front());
  REQUIRE(truth_start > 3.0);  // the push starts at 3 s
  REQUIRE_FALSE(onsets.empty());
  CHECK(onsets.front() >= truth_start);
  CHECK(onsets.front() <= truth_start + 0.05);

  const slip::TerrainClassifier t = terrain(none);
  std::printf(
      "physics-ice-push terrain %s: mu_hat %.3f from %d onsets, lower bound %.3f, %.2f "
      "slips/s, slipping %.3f of stance\n",
      slip::terrainClassName(t.terrain()), t.frictionEstimate(), t.onsets(), t.frictionLowerBound(),
      t.slipRate(), t.slipFraction());
  CHECK(t.terrain() == slip::TerrainClass::kIce);  // mu 0.1 everywhere
  CHECK(t.frictionEstimate() == Approx(0.1).margin(0.03));
  CHECK(t.frictionLowerBound() <= 0.1 * 1.05);
  const Replay imu_only = replay(log, slip::SlipReaction::kImuOnly);
  std::printf("physics-ice-push ESKF velocity RMSE: none %.4f, imu-only %.4f m/s\n",
              none.velocity_rmse, imu_only.velocity_rmse);
  CHECK(imu_only.velocity_rmse < 0.8 * none.velocity_rmse);
}
