// Exercise 57.11.1 (the capstone): each piece against the kit's own implementation or by hand, then
// the assembled estimator on a simulated physics trot (MuJoCo, 4 s, seed 5711) against the truth.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "contact_detector.hpp"
#include "estimation/contact/schmitt_trigger.hpp"
#include "estimation/leg_odometry/base_velocity.hpp"
#include "estimation/linear_kf/linear_kf.hpp"
#include "exercises/exercise_check.hpp"
#include "leg_odometry.hpp"
#include "linear_kf.hpp"
#include "sim/physics_simulator.hpp"
#include "state_estimator.hpp"

using ex57_11::Matrix18;
using ex57_11::Vector18;

namespace {

const legkit::io::Log& trotLog() {
  static const legkit::io::Log log = [] {
    legkit::sim::PhysicsOptions options = legkit::sim::PhysicsOptions::forScenario("physics-trot");
    options.duration = 4.0;
    options.seed = 5711;
    return legkit::sim::simulatePhysics(options).log;
  }();
  return log;
}

Matrix18 randomCovariance(std::mt19937& gen) {
  std::normal_distribution<double> n(0.0, 0.1);
  Matrix18 A;
  for (int i = 0; i < A.size(); ++i) A.data()[i] = n(gen);
  return A * A.transpose() + 1e-3 * Matrix18::Identity();
}

Vector18 randomState(std::mt19937& gen) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vector18 x;
  for (int i = 0; i < x.size(); ++i) x[i] = n(gen);
  return x;
}

}  // namespace

TEST_CASE("57.11.1 piece 1: predict is the kit's process model", "[ex57.11.1][hint 1]") {
  std::mt19937 gen(1);
  const ex57_11::KfNoise noise;
  for (int trial = 0; trial < 8; ++trial) {
    const double dt = 0.001 * (1 + trial);
    const ex57_11::Stance stance = {trial % 2 == 0, true, trial % 3 == 0, false};
    const Eigen::Vector3d a_w(0.3 * trial, -1.0, 0.5);
    const Vector18 x0 = randomState(gen);
    const Matrix18 P0 = randomCovariance(gen);
    ex57_11::LinearKf kf(noise);
    kf.reset(x0, P0);
    kf.predict(dt, a_w, stance);
    const auto model = legkit::linear_kf::processModel(
        dt, stance, {noise.accel_density, noise.foot_stance_density, noise.foot_swing_density});
    const Vector18 x_expected = model.F * x0 + model.B * a_w;
    const Matrix18 P_expected = model.F * P0 * model.F.transpose() + model.Q;
    INFO("dt = " << dt << " s");
    REQUIRE_NEAR(kf.x(), x_expected, 1e-12);
    REQUIRE_NEAR(kf.P(), P_expected, 1e-12);
  }
}

TEST_CASE("57.11.1 piece 1: the Joseph update, by hand", "[ex57.11.1][hint 1]") {
  std::mt19937 gen(2);
  const ex57_11::KfNoise noise;
  const Vector18 x0 = randomState(gen);
  const Matrix18 P0 = randomCovariance(gen);
  // By hand: the textbook gain and the Joseph form, for a stance foot's measurement of foot 2.
  ex57_11::Matrix3x18 H = ex57_11::Matrix3x18::Zero();
  H.block<3, 3>(0, 0) = -Eigen::Matrix3d::Identity();
  H.block<3, 3>(0, 12) = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d R =
      noise.foot_position_sigma * noise.foot_position_sigma * Eigen::Matrix3d::Identity();
  const Eigen::Vector3d z(0.2, -0.1, -0.3);
  const Eigen::Matrix<double, 18, 3> K =
      P0 * H.transpose() * (H * P0 * H.transpose() + R).inverse();
  const Matrix18 A = Matrix18::Identity() - K * H;
  const Vector18 x_expected = x0 + K * (z - H * x0);
  const Matrix18 P_expected = A * P0 * A.transpose() + K * R * K.transpose();
  ex57_11::LinearKf kf(noise);
  kf.reset(x0, P0);
  kf.updateFoot(2, z);
  REQUIRE_NEAR(kf.x(), x_expected, 1e-10);
  REQUIRE_NEAR(kf.P(), P_expected, 1e-10);
  // The same through the general update, and the velocity's H = [0 I 0].
  ex57_11::LinearKf general(noise);
  general.reset(x0, P0);
  general.update(z, H, R);
  REQUIRE_NEAR(general.x(), kf.x(), 1e-14);
  ex57_11::LinearKf velocity(noise);
  velocity.reset(x0, P0);
  velocity.updateVelocity(z);
  ex57_11::Matrix3x18 Hv = ex57_11::Matrix3x18::Zero();
  Hv.block<3, 3>(0, 3) = Eigen::Matrix3d::Identity();
  general.reset(x0, P0);
  general.update(z, Hv, noise.velocity_sigma * noise.velocity_sigma * Eigen::Matrix3d::Identity());
  REQUIRE_NEAR(velocity.P(), general.P(), 1e-14);
  // The Joseph form keeps P symmetric.
  REQUIRE_NEAR(kf.P(), Matrix18(kf.P().transpose()), 1e-15);
}

TEST_CASE("57.11.1 piece 2: the Schmitt trigger is the kit's on the log's forces",
          "[ex57.11.1][hint 2]") {
  const legkit::io::Log& log = trotLog();
  const ex57_11::SchmittConfig config;
  legkit::contact::SchmittParams kit_params;
  kit_params.f_high = config.f_high, kit_params.f_low = config.f_low;
  kit_params.t_on = config.t_on, kit_params.t_off = config.t_off;
  std::array<legkit::contact::SchmittTrigger, 4> kit = {
      legkit::contact::SchmittTrigger(kit_params), legkit::contact::SchmittTrigger(kit_params),
      legkit::contact::SchmittTrigger(kit_params), legkit::contact::SchmittTrigger(kit_params)};
  ex57_11::SchmittContactDetector detector(config);
  int switches = 0;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const legkit::io::LogRow& row = log.rows[k];
    const double dt = k == 0 ? 0.0 : row.t - log.rows[k - 1].t;
    const std::array<double, 4> f = {row.force[0], row.force[1], row.force[2], row.force[3]};
    const std::array<bool, 4> before = detector.contact();
    const std::array<bool, 4> got = detector.update(f, dt);
    for (int i = 0; i < 4; ++i) {
      const bool expected = kit[i].update(f[i], dt);
      switches += got[i] != before[i];
      if (got[i] != expected) {
        INFO("foot " << i << " at t = " << row.t << " s, force " << f[i] << " N");
        REQUIRE(got[i] == expected);
      }
    }
  }
  INFO(switches << " switches over the log");
  REQUIRE(switches > 20);  // the trot's touchdowns and lift-offs
}

TEST_CASE("57.11.1 piece 3: leg odometry is the kit's, per foot and fused", "[ex57.11.1][hint 3]") {
  const legkit::io::Log& log = trotLog();
  const legkit::model::QuadrupedKinematics kin;
  for (std::size_t k = 0; k < log.rows.size(); k += 37) {
    const legkit::io::LogRow& row = log.rows[k];
    const Eigen::Matrix3d R = row.gt_q.toRotationMatrix();
    const std::array<bool, 4> stance = {row.contact[0], row.contact[1], row.contact[2],
                                        row.contact[3]};
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    int n = 0;
    for (int leg = 0; leg < 4; ++leg) {
      const Eigen::Vector3d q = row.q.segment<3>(3 * leg), dq = row.dq.segment<3>(3 * leg);
      const Eigen::Vector3d expected = legkit::leg_odometry::baseVelocityFromFoot(
          R, row.gyro, kin.footPosition(leg, q), kin.footJacobian(leg, q) * dq);
      INFO("t = " << row.t << " s, leg " << leg);
      REQUIRE_NEAR(ex57_11::footBaseVelocity(kin, leg, R, row.gyro, row.q, row.dq), expected,
                   1e-12);
      if (stance[leg]) mean += expected, ++n;
    }
    const ex57_11::LegVelocity fused =
        ex57_11::legOdometry(kin, R, row.gyro, row.q, row.dq, stance);
    REQUIRE(fused.feet == n);
    REQUIRE_NEAR(fused.v, n > 0 ? Eigen::Vector3d(mean / n) : Eigen::Vector3d::Zero(), 1e-12);
  }
}

TEST_CASE("57.11.1 the assembled estimator follows the physics trot", "[ex57.11.1][hint 4]") {
  const legkit::io::Log& log = trotLog();
  const legkit::io::LogRow& first = log.rows.front();
  ex57_11::StateEstimator estimator(ex57_11::ManagerConfig{}, first.gt_q, first.gt_v, first.gt_p);
  double p_sq = 0.0, v_sq = 0.0, tilt_max = 0.0;
  int agree = 0, n = 0;
  Eigen::Vector3d p_error = Eigen::Vector3d::Zero();
  for (const legkit::io::LogRow& row : log.rows) {
    ex57_11::ImuSample imu{row.t, row.gyro, row.acc};
    ex57_11::JointSample joints{row.q, row.dq};
    ex57_11::ForceSample forces{{row.force[0], row.force[1], row.force[2], row.force[3]}};
    const ex57_11::BaseState& x = estimator.update(imu, joints, forces);
    REQUIRE(x.t == row.t);
    p_error = x.p - row.gt_p;
    p_sq += p_error.squaredNorm();
    v_sq += (x.v - row.gt_v).squaredNorm();
    const Eigen::Vector3d z_hat = x.q.toRotationMatrix().transpose().col(2);
    const Eigen::Vector3d z = row.gt_q.toRotationMatrix().transpose().col(2);
    tilt_max = std::max(tilt_max, std::acos(std::min(1.0, z_hat.dot(z))));
    for (int i = 0; i < 4; ++i) agree += x.contact[i] == row.contact[i];
    ++n;
  }
  const double p_rmse = std::sqrt(p_sq / n), v_rmse = std::sqrt(v_sq / n);
  const double travelled = (log.rows.back().gt_p - first.gt_p).head<2>().norm();
  const double contact_agreement = agree / (4.0 * n);
  INFO("over " << log.rows.back().t << " s, " << travelled << " m: position RMSE " << p_rmse
               << " m, final error " << p_error.norm() << " m, velocity RMSE " << v_rmse
               << " m/s, largest tilt error " << tilt_max * 180.0 / M_PI
               << " deg, contact agreement " << contact_agreement);
  // The measured figures (the reference solution's, above) with margin: position RMSE 0.037 m,
  // final error 0.082 m, velocity RMSE 0.038 m/s, tilt 1.5 deg, contacts 0.990.
  REQUIRE_ABOVE(contact_agreement, 0.97);
  REQUIRE_BELOW(tilt_max * 180.0 / M_PI, 3.0);
  REQUIRE_BELOW(v_rmse, 0.06);
  REQUIRE_BELOW(p_rmse, 0.06);
  REQUIRE_BELOW(p_error.head<2>().norm(), 0.15);
}
