// Exercise 57.7.2: a robot pushed on ice (every foot slides at once): the legs' common velocity
// against the IMU alone, and the feet against each other, on the physics simulator's log.
#include <catch2/catch.hpp>
#include <cmath>

#include "estimation/leg_odometry/base_velocity.hpp"
#include "ex57_7_2.hpp"
#include "exercises/exercise_check.hpp"
#include "sim/physics_simulator.hpp"

namespace {

// physics-ice-push, 4.5 s (seed 5772): standing on ice (mu 0.1), pushed sideways with 50 N for
// 0.2 s at t = 3 s.
const legkit::io::Log& icePushLog() {
  static const legkit::io::Log log = [] {
    legkit::sim::PhysicsOptions options =
        legkit::sim::PhysicsOptions::forScenario("physics-ice-push");
    options.duration = 4.5;
    options.seed = 5772;
    return legkit::sim::simulatePhysics(options).log;
  }();
  return log;
}

constexpr double kAnchor = 2.5;  // [s], half a second before the push

}  // namespace

TEST_CASE("57.7.2 the legs' velocity is the kit's leg odometry", "[ex57.7.2][hint 1]") {
  const legkit::model::QuadrupedKinematics kin;
  const legkit::io::Log& log = icePushLog();
  const std::vector<ex57_7_2::Comparison> c = ex57_7_2::legsVersusImu(log, kAnchor, kin);
  REQUIRE(c.size() == 2000);
  const std::size_t first = log.rows.size() - c.size();
  for (std::size_t k = 0; k < c.size(); k += 97) {
    const legkit::io::LogRow& row = log.rows[first + k];
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    int n = 0;
    for (int leg = 0; leg < 4; ++leg) {
      if (!row.contact[leg]) continue;
      const Eigen::Vector3d q = row.q.segment<3>(3 * leg), dq = row.dq.segment<3>(3 * leg);
      mean += legkit::leg_odometry::baseVelocityFromFoot(row.gt_q.toRotationMatrix(), row.gyro,
                                                         kin.footPosition(leg, q),
                                                         kin.footJacobian(leg, q) * dq);
      ++n;
    }
    INFO("t = " << row.t << " s");
    REQUIRE(c[k].t == row.t);
    REQUIRE_NEAR(c[k].v_legs, mean / n, 1e-12);
  }
  // The anchor row starts from the truth.
  REQUIRE_NEAR(c.front().v_imu, log.rows[first].gt_v, 1e-15);
}

TEST_CASE("57.7.2 pushed on ice: the feet agree, the IMU does not", "[ex57.7.2][hint 2]") {
  const legkit::model::QuadrupedKinematics kin;
  const legkit::io::Log& log = icePushLog();
  const std::vector<ex57_7_2::Comparison> c = ex57_7_2::legsVersusImu(log, kAnchor, kin);
  const std::size_t first = log.rows.size() - c.size();
  // RMS over the rows of [t0, t1) of |v_legs - v_imu|, of the spread, of |v_imu - v| and of the
  // true speed |v|. (Per row the gyro's white noise alone puts a few cm/s into each foot's
  // velocity: compare windows, not single rows.)
  struct Window {
    double gap = 0.0, spread = 0.0, imu_error = 0.0, speed = 0.0;
  };
  const auto window = [&](double t0, double t1) {
    Window w;
    int n = 0;
    for (std::size_t k = 0; k < c.size(); ++k) {
      const legkit::io::LogRow& row = log.rows[first + k];
      if (row.t < t0 || row.t >= t1) continue;
      w.gap += (c[k].v_legs - c[k].v_imu).squaredNorm();
      w.spread += c[k].spread * c[k].spread;
      w.imu_error += (c[k].v_imu - row.gt_v).squaredNorm();
      w.speed += row.gt_v.squaredNorm();
      ++n;
    }
    w.gap = std::sqrt(w.gap / n), w.spread = std::sqrt(w.spread / n);
    w.imu_error = std::sqrt(w.imu_error / n), w.speed = std::sqrt(w.speed / n);
    return w;
  };
  const Window before = window(2.5, 3.0), slide = window(3.1, 3.3), all = window(2.5, 3.5);
  double t_all_slide = -1.0;
  for (const legkit::io::LogRow& row : log.rows) {
    bool every = true;
    for (int leg = 0; leg < 4; ++leg) every = every && row.gt_feet[leg].slip_speed > 0.02;
    if (every) {
      t_all_slide = row.t;
      break;
    }
  }
  INFO("every foot slides (true slip speed > 0.02 m/s) from " << t_all_slide << " s");
  INFO("RMS over 2.5-3.0 s (standing): |v_legs - v_imu| " << before.gap << " m/s, spread "
                                                          << before.spread << " m/s");
  INFO("RMS over 3.1-3.3 s (sliding): true speed " << slide.speed << " m/s, |v_legs - v_imu| "
                                                   << slide.gap << " m/s, spread " << slide.spread
                                                   << " m/s");
  INFO("RMS |v_imu - v| over 2.5-3.5 s: " << all.imu_error << " m/s");
  REQUIRE(t_all_slide > 3.0);
  REQUIRE(t_all_slide < 3.1);
  // The IMU alone stays with the truth over the second; the legs do not see the slide...
  REQUIRE_BELOW(all.imu_error, 0.05);
  REQUIRE_BELOW(before.gap, 0.08);
  REQUIRE_ABOVE(slide.gap, 3.0 * before.gap);
  // ...and the feet disagree with each other less than the legs disagree with the IMU.
  REQUIRE_BELOW(slide.spread, 0.8 * slide.gap);
}
