// The pose simulator (estimation/fusion/pose_simulator.hpp): its noise matches the covariance it
// reports (NEES), the latency, the rate, the loop-closure jump, the corridor, determinism, options.
#include <catch2/catch.hpp>
#include <cmath>

#include "estimation/fusion/pose_simulator.hpp"

using legkit::fusion::MapDrift;
using legkit::fusion::PoseMeasurement;
using legkit::fusion::PoseSimulatorOptions;
using legkit::fusion::simulatePoses;
using Vector6d = Eigen::Matrix<double, 6, 1>;

namespace {

// A truth of `duration` s at 100 Hz: a circle of radius 5 m at 0.5 m/s, heading along the path.
legkit::io::Log circleTruth(double duration) {
  legkit::io::Log log;
  log.layout.ground_truth = true;
  const double w = 0.1;  // [rad/s]
  for (int k = 0; k * 0.01 <= duration; ++k) {
    legkit::io::LogRow row;
    row.t = 0.01 * k;
    row.gt_p = Eigen::Vector3d(5.0 * std::sin(w * row.t), 5.0 - 5.0 * std::cos(w * row.t), 0.3);
    row.gt_q = Eigen::Quaterniond(Eigen::AngleAxisd(w * row.t, Eigen::Vector3d::UnitZ()));
    log.rows.push_back(row);
  }
  return log;
}

// The pose without noise: D T_WB (the simulator header's model).
PoseMeasurement noiseFree(const legkit::io::LogRow& row, const MapDrift& d) {
  const Eigen::Matrix3d R_D = Eigen::AngleAxisd(d.yaw, Eigen::Vector3d::UnitZ()).matrix();
  PoseMeasurement z;
  z.R_MB = lie::SO3d::fromQuaternion(Eigen::Quaterniond(R_D * row.gt_q.toRotationMatrix()));
  z.p_MB = R_D * row.gt_p + d.p;
  return z;
}

const legkit::io::LogRow& rowAt(const legkit::io::Log& log, double t) {
  return log.rows.at(static_cast<std::size_t>(std::lround(t / 0.01)));
}

// (dtheta, dp) of z about the noise-free pose: R = Exp(dtheta) R_nf, p = p_nf + dp.
Vector6d error(const PoseMeasurement& z, const PoseMeasurement& nf) {
  Vector6d e;
  e.head<3>() = (z.R_MB * nf.R_MB.inverse()).Log();
  e.tail<3>() = z.p_MB - nf.p_MB;
  return e;
}

}  // namespace

TEST_CASE("simulated poses: rate, latency, noise consistent with the covariance",
          "[fusion][extero]") {
  const auto truth = circleTruth(100.0);
  PoseSimulatorOptions o;
  o.corridor_start = 30.0;
  o.corridor_end = 50.0;
  o.loop_closure_time = 70.0;
  const auto sim = simulatePoses(truth, o, 7);
  REQUIRE(sim.poses.size() == sim.drift.size());
  CHECK(sim.poses.size() == 1001);  // 10 Hz over 100 s, both ends
  double nees = 0.0;
  int n = 0;
  for (std::size_t k = 0; k < sim.poses.size(); ++k) {
    const auto& z = sim.poses[k];
    CHECK(z.t_arrival - z.t == Approx(0.08).margin(1e-12));
    CHECK(z.valid);
    if (k > 0) CHECK(z.t - sim.poses[k - 1].t == Approx(0.1).margin(0.011));
    const Vector6d e = error(z, noiseFree(rowAt(truth, z.t), sim.drift[k]));
    if (!sim.drift[k].in_corridor) {
      nees += e.dot(z.cov.ldlt().solve(e));
      ++n;
    }
  }
  // The mean of n chi-square(6) draws: 6 with standard deviation sqrt(12 / n); 4 sigma.
  nees /= n;
  INFO("mean NEES " << nees << " over " << n << " poses");
  CHECK(std::abs(nees - 6.0) < 4.0 * std::sqrt(12.0 / n));
}

TEST_CASE("simulated poses: the drift, the loop-closure jump and the corridor",
          "[fusion][extero]") {
  const auto truth = circleTruth(100.0);
  PoseSimulatorOptions o;
  o.corridor_start = 30.0;
  o.corridor_end = 50.0;
  o.corridor_axis = 1;
  o.loop_closure_time = 70.0;
  o.drift_position = 0.02;
  const auto sim = simulatePoses(truth, o, 11);
  std::size_t jump = 0;
  while (sim.poses[jump].t < o.loop_closure_time) ++jump;
  // Before the closure the map has drifted (the corridor's 0.05 m/s for 20 s on y, and the walk).
  const MapDrift before = sim.drift[jump - 1];
  CHECK(std::abs(before.p.y()) > 0.5);
  CHECK(before.yaw != 0.0);
  // At the closure the drift is snapped back to zero: the poses jump by what had accumulated.
  CHECK(sim.drift[jump].p.norm() == 0.0);
  CHECK(sim.drift[jump].yaw == 0.0);
  const auto& row = rowAt(truth, sim.poses[jump].t);
  const Eigen::Vector3d error_after = sim.poses[jump].p_MB - row.gt_p;
  CHECK(error_after.norm() < 5 * 0.02 * std::sqrt(3.0));  // the white noise only
  const auto& row_before = rowAt(truth, sim.poses[jump - 1].t);
  CHECK((sim.poses[jump - 1].p_MB - row_before.gt_p).norm() > 0.5);
  // After it the drift starts afresh.
  CHECK(sim.drift.back().p.norm() > 0.0);

  // The corridor: reported sigma 5 m on map y there only, and the value along y drifts at the
  // given rate (20 s * 0.05 m/s = 1 m, plus the walk, 0.02 m/sqrt(s) * sqrt(20 s) = 0.09 m).
  const PoseMeasurement* first = nullptr;
  const PoseMeasurement* last = nullptr;
  std::size_t k_first = 0, k_last = 0;
  for (std::size_t k = 0; k < sim.poses.size(); ++k) {
    const bool inside = sim.poses[k].t >= 30.0 && sim.poses[k].t < 50.0;
    CHECK(sim.drift[k].in_corridor == inside);
    CHECK(sim.poses[k].cov(4, 4) == (inside ? 25.0 : 0.02 * 0.02));
    CHECK(sim.poses[k].cov(3, 3) == 0.02 * 0.02);
    if (inside && !first) first = &sim.poses[k], k_first = k;
    if (inside) last = &sim.poses[k], k_last = k;
  }
  REQUIRE(first);
  const double drifted = sim.drift[k_last].p.y() - sim.drift[k_first].p.y();
  CHECK(drifted == Approx(0.05 * (last->t - first->t)).margin(4 * 0.02 * std::sqrt(20.0)));
  const double seen = (last->p_MB - rowAt(truth, last->t).gt_p).y() -
                      (first->p_MB - rowAt(truth, first->t).gt_p).y();
  CHECK(seen == Approx(1.0).margin(0.5));  // the poses' error along y shows that drift
}

TEST_CASE("simulated poses: deterministic, invalid truth skipped, bad options named",
          "[fusion][extero]") {
  auto truth = circleTruth(5.0);
  const auto a = simulatePoses(truth, {}, 3);
  const auto b = simulatePoses(truth, {}, 3);
  const auto c = simulatePoses(truth, {}, 4);
  REQUIRE(a.poses.size() == b.poses.size());
  for (std::size_t k = 0; k < a.poses.size(); ++k) {
    CHECK(a.poses[k].p_MB == b.poses[k].p_MB);
    CHECK(a.poses[k].R_MB.matrix() == b.poses[k].R_MB.matrix());
  }
  CHECK(a.poses[3].p_MB != c.poses[3].p_MB);

  // A truth row flagged missing gives no pose.
  truth.layout.gt_valid = true;
  for (auto& row : truth.rows) row.gt_valid = !(row.t > 1.95 && row.t < 2.25);
  const auto gaps = simulatePoses(truth, {}, 3);
  CHECK(gaps.poses.size() == a.poses.size() - 3);
  for (const auto& z : gaps.poses) CHECK(!(z.t > 1.95 && z.t < 2.25));

  PoseSimulatorOptions o;
  o.latency = 0.0;
  CHECK_THROWS_WITH(simulatePoses(truth, o, 1), Catch::StartsWith("PoseSimulatorOptions.latency"));
  o = {};
  o.corridor_axis = 2;
  CHECK_THROWS_WITH(simulatePoses(truth, o, 1),
                    Catch::StartsWith("PoseSimulatorOptions.corridor_axis: expected 0 (x) or 1"));
  o = {};
  o.corridor_end = o.corridor_start - 1.0;
  CHECK_THROWS_WITH(simulatePoses(truth, o, 1),
                    Catch::StartsWith("PoseSimulatorOptions.corridor_end"));
  o = {};
  o.sigma_position = std::nan("");
  CHECK_THROWS_WITH(simulatePoses(truth, o, 1),
                    Catch::StartsWith("PoseSimulatorOptions.sigma_position"));
  truth.layout.ground_truth = false;
  CHECK_THROWS_WITH(simulatePoses(truth, {}, 1), Catch::Contains("has no ground truth"));
}
