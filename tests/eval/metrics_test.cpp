// eval::compare on constructed errors whose metrics are known in closed form.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "eval/metrics.hpp"

using legkit::EstimateSample;
using legkit::eval::Trajectory;

namespace {

// A truth moving along x at 1 m/s for 10 rows of 0.1 s: distance 0.9 m.
legkit::io::Log straightLine() {
  legkit::io::Log log;
  log.layout.ground_truth = true;
  for (int k = 0; k < 10; ++k) {
    legkit::io::LogRow r;
    r.t = 0.1 * k;
    r.gt_p = Eigen::Vector3d(r.t, 0.0, 0.3);
    r.gt_v = Eigen::Vector3d(1.0, 0.0, 0.0);
    log.rows.push_back(r);
  }
  return log;
}

Trajectory copyOf(const legkit::io::Log& log) {
  Trajectory est;
  for (const auto& r : log.rows) est.push_back({r.t, r.gt_q, r.gt_v, r.gt_p});
  return est;
}

// A truth winding through 3D, on no line or plane, so that every rotation of it shows: 60 rows of
// 0.1 s.
legkit::io::Log curve() {
  legkit::io::Log log;
  log.layout.ground_truth = true;
  for (int k = 0; k < 60; ++k) {
    legkit::io::LogRow r;
    r.t = 0.1 * k;
    r.gt_p = Eigen::Vector3d(2.0 * std::cos(0.2 * k), std::sin(0.3 * k), 0.3 + 0.05 * k);
    r.gt_q = Eigen::AngleAxisd(0.2 * k, Eigen::Vector3d::UnitZ());
    log.rows.push_back(r);
  }
  return log;
}

// The truth moved rigidly, p_hat = R p + t and R_hat = R R_true: every alignment that may rotate
// as R does undoes it.
Trajectory moved(const legkit::io::Log& log, const Eigen::Quaterniond& R,
                 const Eigen::Vector3d& t) {
  Trajectory est;
  for (const auto& r : log.rows) est.push_back({r.t, R * r.gt_q, R * r.gt_v, R * r.gt_p + t});
  return est;
}

Eigen::Quaterniond yawed(double psi) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ()));
}

}  // namespace

TEST_CASE("a perfect estimate has zero error and the truth's distance", "[eval]") {
  const auto log = straightLine();
  const auto m = legkit::eval::compare(log, copyOf(log));
  CHECK(m.position_rmse == 0.0);
  CHECK(m.velocity_rmse == 0.0);
  CHECK(m.tilt_rmse_deg == 0.0);
  CHECK(m.yaw_rmse_deg == 0.0);
  CHECK(m.distance == Approx(0.9));
}

TEST_CASE("constant offsets give their RMSE and drift", "[eval]") {
  const auto log = straightLine();
  Trajectory est = copyOf(log);
  for (auto& e : est) {
    e.p += Eigen::Vector3d(0.03, 0.04, 0.0);  // |e_p| = 0.05
    e.v += Eigen::Vector3d(0.0, 0.0, 0.2);
  }
  const auto m = legkit::eval::compare(log, est);
  CHECK(m.position_rmse == Approx(0.05));
  CHECK(m.velocity_rmse == Approx(0.2));
  CHECK(m.final_position_error == Approx(0.05));
  CHECK(m.drift_percent == Approx(100.0 * 0.05 / 0.9));
}

TEST_CASE("tilt and yaw errors separate roll/pitch from heading", "[eval]") {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                            Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  // A heading error alone (a world z rotation) is invisible to the tilt error.
  const Eigen::Matrix3d yawed = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()) * R;
  CHECK(legkit::eval::tiltError(yawed, R) == Approx(0.0).margin(1e-15));
  CHECK(legkit::eval::yawError(yawed, R) == Approx(0.1));
  // A pitch error alone changes the tilt by exactly that angle.
  const Eigen::Matrix3d pitched = R * Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY());
  CHECK(legkit::eval::tiltError(pitched, R) == Approx(0.05));
  // Yaw error wraps across +-pi.
  const Eigen::Matrix3d a = Eigen::AngleAxisd(3.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d b = Eigen::AngleAxisd(-3.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  CHECK(legkit::eval::yawError(a, b) == Approx(6.2 - 2.0 * M_PI));
}

TEST_CASE("compare rejects logs without truth and misaligned estimates", "[eval]") {
  auto log = straightLine();
  Trajectory est = copyOf(log);
  est.pop_back();
  CHECK_THROWS_WITH(legkit::eval::compare(log, est), Catch::Contains("9 estimates for 10"));
  est = copyOf(log);
  est[3].t += 1e-3;
  CHECK_THROWS_WITH(legkit::eval::compare(log, est), Catch::Contains("log row 3"));
  log.layout.ground_truth = false;
  CHECK_THROWS_WITH(legkit::eval::compare(log, copyOf(log)), Catch::Contains("ground-truth"));
}

TEST_CASE("ATE removes the offset of the first pose; RPE sees only relative motion", "[eval]") {
  const auto log = straightLine();
  // The whole estimate shifted by 2 m and turned 90 degrees about z: rigidly wrong from the
  // start, so after aligning the first pose ATE is zero, and every relative motion agrees.
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  Trajectory est;
  for (const auto& r : log.rows) {
    est.push_back({r.t, turn * r.gt_q, turn * r.gt_v, turn * r.gt_p + Eigen::Vector3d(2, 0, 0)});
  }
  const auto m = legkit::eval::compare(log, est, {0.5});
  CHECK(m.position_rmse > 1.0);
  CHECK(m.ate_rmse == Approx(0.0).margin(1e-12));
  REQUIRE(m.rpe.size() == 1);
  CHECK(m.rpe[0].pairs == 5);  // i = 0..4 reach 0.5 m further within the 0.9 m run
  CHECK(m.rpe[0].translation_rmse == Approx(0.0).margin(1e-12));
  CHECK(m.rpe[0].rotation_rmse_deg == Approx(0.0).margin(1e-9));
}

TEST_CASE("RPE of an estimate that moves 10 % too far is 10 % of the distance", "[eval]") {
  const auto log = straightLine();
  Trajectory est = copyOf(log);
  for (auto& e : est) e.p.x() *= 1.1;
  const auto m = legkit::eval::compare(log, est, {0.5, 5.0});
  // Pairs 0.5 m apart (rows i, i+5) are estimated 0.55 m apart.
  CHECK(m.rpe[0].translation_rmse == Approx(0.05).epsilon(1e-9));
  CHECK(m.rpe[0].translation_percent == Approx(10.0).epsilon(1e-9));
  CHECK(m.rpe[1].pairs == 0);  // the run is shorter than 5 m
  CHECK(m.ate_rmse > 0.0);
}

TEST_CASE("SE(3) ATE aligns away any rigid motion, 4-DoF ATE one about z only", "[eval]") {
  const auto log = curve();
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  Eigen::Vector4d w;
  for (int i = 0; i < 4; ++i) w(i) = normal(rng);
  const Eigen::Quaterniond random(w(0), w(1), w(2), w(3));
  const Eigen::Vector3d t(normal(rng), normal(rng), normal(rng));
  const auto any = legkit::eval::compare(log, moved(log, random.normalized(), t));
  CHECK(any.position_rmse > 0.1);
  CHECK(any.ate_se3_rmse == Approx(0.0).margin(1e-12));

  const auto about_z = legkit::eval::compare(log, moved(log, yawed(2.0), t));
  CHECK(about_z.ate_se3_rmse == Approx(0.0).margin(1e-12));
  CHECK(about_z.ate_4dof_rmse == Approx(0.0).margin(1e-12));

  // A roll of 0.1 rad: gravity's direction is observable, so the 4-DoF alignment keeps it.
  const Eigen::Quaterniond rolled = yawed(2.0) * Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX());
  const auto roll = legkit::eval::compare(log, moved(log, rolled, t));
  CHECK(roll.ate_se3_rmse == Approx(0.0).margin(1e-12));
  CHECK(roll.ate_4dof_rmse > 0.01);
}

TEST_CASE("4-DoF ATE: the yaw turns the estimate onto the truth, not away from it", "[eval]") {
  // With psi's sign flipped the fit would turn by twice the error: ATE ~ 2 sin(psi) * radius.
  const auto log = curve();
  for (const double psi : {0.3, -0.3, 1.5, -2.5}) {
    INFO("psi " << psi);
    const auto m = legkit::eval::compare(log, moved(log, yawed(psi), Eigen::Vector3d::Zero()));
    CHECK(m.position_rmse > 0.2);
    CHECK(m.ate_4dof_rmse == Approx(0.0).margin(1e-12));
  }
}

TEST_CASE("With noise, the least-squares ATEs are at most the first-pose ATE", "[eval]") {
  // A yawed, shifted estimate with noisy positions: the first-pose transform (here a yaw and a
  // shift) is one of the 4-DoF candidates, which are SE(3) candidates.
  const auto log = curve();
  Trajectory est = moved(log, yawed(0.4), Eigen::Vector3d(1.0, -2.0, 0.5));
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (auto& e : est) e.p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  const auto m = legkit::eval::compare(log, est);
  CHECK(m.ate_se3_rmse > 0.0);
  CHECK(m.ate_se3_rmse <= m.ate_4dof_rmse);
  CHECK(m.ate_4dof_rmse <= m.ate_rmse);
}

TEST_CASE("The aligned ATEs ignore masked rows and need 3 valid rows", "[eval]") {
  auto log = curve();
  log.layout.gt_valid = true;
  log.rows[10].gt_valid = false;
  const Trajectory est = moved(log, yawed(1.0), Eigen::Vector3d(0.5, 0.5, 0.0));
  const auto clean = legkit::eval::compare(log, est);
  CHECK(clean.ate_4dof_rmse == Approx(0.0).margin(1e-12));
  // Garbage in the masked row, truth and estimate alike: the same numbers.
  auto garbage_log = log;
  garbage_log.rows[10].gt_p = Eigen::Vector3d(1e3, -1e3, 1e3);
  Trajectory garbage = est;
  garbage[10].p = Eigen::Vector3d(-5e2, 7e2, 0.0);
  const auto masked = legkit::eval::compare(garbage_log, garbage);
  CHECK(masked.ate_se3_rmse == clean.ate_se3_rmse);
  CHECK(masked.ate_4dof_rmse == clean.ate_4dof_rmse);

  for (std::size_t k = 2; k < log.rows.size(); ++k) log.rows[k].gt_valid = false;
  const auto two = legkit::eval::compare(log, est);
  CHECK(two.scored_rows == 2);
  CHECK(std::isnan(two.ate_se3_rmse));
  CHECK(std::isnan(two.ate_4dof_rmse));
  CHECK_FALSE(std::isnan(two.ate_rmse));  // the first-pose ATE needs one row
}
