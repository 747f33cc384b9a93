// eval::compare on constructed errors whose metrics are known in closed form.
#include <catch2/catch.hpp>
#include <cmath>

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
