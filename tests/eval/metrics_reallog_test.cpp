// eval::compare on the truth of a real robot's log (issue 14): a pose-only truth differentiated,
// motion-capture dropouts masked, an RPE without pairs "not computed", and a distance that a
// jittering truth does not inflate. Each number is known in closed form or bounded with a margin
// that the unhandled case misses by far.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "eval/metrics.hpp"

namespace eval = legkit::eval;
namespace io = legkit::io;
using legkit::EstimateSample;

namespace {

// A truth with the pose only, sampled at 100 Hz for `seconds`, position p(t).
template <typename Path>
io::Log poseOnly(double seconds, Path p) {
  io::Log log;
  log.layout.ground_truth = true;
  log.layout.gt_velocity = false;
  log.layout.gt_valid = true;
  const int n = static_cast<int>(std::lround(seconds * 100.0));
  for (int k = 0; k < n; ++k) {
    io::LogRow r;
    r.t = 0.01 * k;
    r.gt_p = p(r.t);
    log.rows.push_back(r);
  }
  return log;
}

eval::Trajectory copyOf(const io::Log& log) {
  eval::Trajectory est;
  for (const io::LogRow& r : log.rows)
    est.push_back({r.t, r.gt_q, Eigen::Vector3d::Zero(), r.gt_p});
  return est;
}

// A circle of radius 1 m at 1 rad/s: |v| = 1 m/s.
Eigen::Vector3d circle(double t) {
  return {std::cos(t), std::sin(t), 0.3};
}
Eigen::Vector3d circleVelocity(double t) {
  return {-std::sin(t), std::cos(t), 0.0};
}

}  // namespace

TEST_CASE("A pose-only truth is differentiated over the stated window", "[eval][57.0]") {
  const io::Log log = poseOnly(3.0, circle);
  eval::Trajectory est = copyOf(log);
  for (EstimateSample& e : est) e.v = circleVelocity(e.t);
  const eval::Metrics m = eval::compare(log, est);
  CHECK(m.velocity_differentiated);
  CHECK(m.velocity_method ==
        "central difference of gt_p over a 0.05 s window, valid rows only (the log has no "
        "gt_vx..gt_vz)");
  CHECK(m.velocity_rows == 300);
  // A central difference over +-2 rows (0.02 s) errs by h^2/6 |v''| = 6.7e-5 m/s inside, a
  // one-sided one at the two ends by up to h/2 |v'| = 0.01 m/s on 3 rows each.
  CHECK(m.velocity_rmse > 1e-5);
  CHECK(m.velocity_rmse < 2e-3);
  // The same estimate scored as if it stood still: the truth's speed.
  for (EstimateSample& e : est) e.v.setZero();
  CHECK(eval::compare(log, est).velocity_rmse == Approx(1.0).epsilon(1e-3));

  // Row 100 by hand: (p_102 - p_98) / 0.04 s.
  const eval::TruthVelocity v = eval::truthVelocity(log);
  REQUIRE(v.available[100]);
  CHECK((v.v[100] - (log.rows[102].gt_p - log.rows[98].gt_p) / 0.04).norm() < 1e-12);
  // Row 0 one-sided: (p_2 - p_0) / 0.02 s.
  CHECK((v.v[0] - (log.rows[2].gt_p - log.rows[0].gt_p) / 0.02).norm() < 1e-12);
  // A wider window is a different filter.
  const eval::TruthVelocity wide = eval::truthVelocity(log, 0.2);
  CHECK((wide.v[100] - (log.rows[110].gt_p - log.rows[90].gt_p) / 0.2).norm() < 1e-12);
  CHECK_THROWS_AS(eval::truthVelocity(log, 0.0), std::invalid_argument);
}

TEST_CASE("A truth with gt_v is taken as it is", "[eval][57.0]") {
  io::Log log = poseOnly(1.0, circle);
  log.layout.gt_velocity = true;
  for (io::LogRow& r : log.rows) r.gt_v = Eigen::Vector3d(0.0, 0.0, 2.0);
  const eval::Metrics m = eval::compare(log, copyOf(log));
  CHECK_FALSE(m.velocity_differentiated);
  CHECK(m.velocity_method == "the log's gt_vx..gt_vz");
  CHECK(m.velocity_rmse == Approx(2.0));
}

TEST_CASE("Dropout rows are masked out of every metric", "[eval][57.0]") {
  // 20 rows along x, 0.1 m apart; rows 5, 6, 7 and the last one are a motion-capture dropout
  // whose truth is garbage (a zero quaternion, 100 m away) and whose estimate is far off too.
  io::Log log;
  log.layout.ground_truth = true;
  log.layout.gt_valid = true;
  eval::Trajectory est;
  for (int k = 0; k < 20; ++k) {
    io::LogRow r;
    r.t = 0.1 * k;
    r.gt_p = Eigen::Vector3d(0.1 * k, 0.0, 0.3);
    r.gt_v = Eigen::Vector3d(1.0, 0.0, 0.0);
    EstimateSample e{r.t, r.gt_q, r.gt_v, r.gt_p + Eigen::Vector3d(0.0, 0.05, 0.0)};
    if ((k >= 5 && k <= 7) || k == 19) {
      r.gt_valid = false;
      r.gt_p.x() = 100.0;
      r.gt_q.coeffs().setZero();
      e.p.z() = -50.0;
      e.v.x() = 30.0;
      e.q = Eigen::Quaterniond(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitX()));
    }
    log.rows.push_back(r);
    est.push_back(e);
  }
  const eval::Metrics m = eval::compare(log, est, {0.45});
  CHECK(m.masked_rows == 4);
  CHECK(m.scored_rows == 16);
  CHECK(m.position_rmse == Approx(0.05));
  CHECK(m.velocity_rmse == 0.0);
  CHECK(m.tilt_rmse_deg == 0.0);
  CHECK(m.yaw_rmse_deg == 0.0);
  CHECK(m.ate_rmse == Approx(0.0).margin(1e-12));  // a constant offset, aligned away
  CHECK(m.final_position_error == Approx(0.05));   // at row 18, the last valid one
  CHECK(m.distance == Approx(1.8));                // x from 0 to 1.8 over the valid rows
  // Pairs of valid rows 0.45 m apart: i = 0..4 and 8..13 (j = i + 5, or 8 for i = 0..3: the
  // first valid row that far), 11 pairs; a straight line valid on every row gives 15.
  REQUIRE(m.rpe.size() == 1);
  CHECK(m.rpe[0].computed);
  CHECK(m.rpe[0].pairs == 11);
  CHECK(m.rpe[0].translation_rmse == Approx(0.0).margin(1e-12));

  // Without the flag column the same rows would be scored.
  io::Log unflagged = log;
  unflagged.layout.gt_valid = false;
  for (io::LogRow& r : unflagged.rows) r.gt_q = Eigen::Quaterniond::Identity();
  const eval::Metrics all = eval::compare(unflagged, est, {0.45});
  CHECK(all.masked_rows == 0);
  CHECK(all.position_rmse > 10.0);
}

TEST_CASE("A truth missing on every row scores nothing and says so", "[eval][57.0]") {
  io::Log log = poseOnly(0.5, circle);
  for (io::LogRow& r : log.rows) r.gt_valid = false;
  const eval::Metrics m = eval::compare(log, copyOf(log));
  CHECK(m.scored_rows == 0);
  CHECK(m.masked_rows == 50);
  CHECK(std::isnan(m.position_rmse));
  CHECK(std::isnan(m.velocity_rmse));
  CHECK(std::isnan(m.ate_rmse));
  CHECK(std::isnan(m.drift_percent));
  REQUIRE(m.rpe.size() == 2);
  CHECK_FALSE(m.rpe[0].computed);
}

TEST_CASE("An RPE without a single pair is not computed, never 0", "[eval][57.0]") {
  const io::Log log = poseOnly(2.0, circle);  // 2 m of path
  eval::Trajectory est = copyOf(log);
  for (EstimateSample& e : est) e.p *= 1.1;
  const eval::Metrics m = eval::compare(log, est, {1.0, 5.0});
  REQUIRE(m.rpe.size() == 2);
  CHECK(m.rpe[0].computed);
  CHECK(m.rpe[0].pairs > 0);
  CHECK(m.rpe[0].translation_rmse > 0.05);
  CHECK_FALSE(m.rpe[1].computed);
  CHECK(m.rpe[1].pairs == 0);
  CHECK(std::isnan(m.rpe[1].translation_rmse));
  CHECK(std::isnan(m.rpe[1].translation_percent));
  CHECK(std::isnan(m.rpe[1].rotation_rmse_deg));
}

TEST_CASE("Jitter of the truth does not inflate the distance travelled", "[eval][57.0]") {
  std::mt19937 rng(14);
  std::normal_distribution<double> jitter(0.0, 1e-3);  // motion capture: 1 mm per axis
  const auto noisy = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(p + Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng)));
  };
  // Standing still for 10 s: true distance 0.
  const io::Log still = poseOnly(10.0, [&](double) { return noisy(Eigen::Vector3d(0, 0, 0.3)); });
  eval::Trajectory est = copyOf(still);
  for (EstimateSample& e : est) e.p = Eigen::Vector3d(0.02, 0.0, 0.3);  // 2 cm off
  const eval::Metrics m = eval::compare(still, est);
  CHECK(m.distance == 0.0);
  // The differentiated jitter: sqrt(6) sigma / 0.04 s (the rows the 0.05 s window spans at 100 Hz).
  CHECK(m.velocity_rmse == Approx(std::sqrt(6.0) * 1e-3 / 0.04).epsilon(0.1));
  CHECK(std::isnan(m.drift_percent));  // no distance to divide by: "n/c", not 0 %
  CHECK_FALSE(m.rpe[0].computed);      // no RPE pair made of jitter either
  // Summed sample by sample (d_min = 0), the same jitter walks metres.
  eval::TruthOptions naive;
  naive.distance_step = 0.0;
  const eval::Metrics summed = eval::compare(still, est, {1.0}, naive);
  CHECK(summed.distance > 1.5);
  CHECK(summed.rpe[0].computed);

  // Walking 2 m at 0.2 m/s (2 mm per sample) with the same jitter: within 2 % of 2 m, where the
  // sample-by-sample sum overshoots by more than 25 %.
  const io::Log walk =
      poseOnly(10.0, [&](double t) { return noisy(Eigen::Vector3d(0.2 * t, 0.0, 0.3)); });
  const double distance = eval::compare(walk, copyOf(walk)).distance;
  INFO("distance " << distance << " m, true 1.998 m");
  CHECK(std::abs(distance - 1.998) < 0.04);
  CHECK(eval::compare(walk, copyOf(walk), {1.0}, naive).distance > 1.25 * 1.998);
}
