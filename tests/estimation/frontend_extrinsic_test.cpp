// The IMU extrinsic (issue 14, item 2): the frame maps of estimation/imu_extrinsic_frames.hpp, the
// front end moving every kind of foot into the IMU frame, and a trot logged by an IMU mounted at
// a lever arm of 0.2 m and turned by 20 deg, run with and without the extrinsic.
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>

#include "estimation/contact_pipeline.hpp"
#include "estimation/imu_extrinsic_frames.hpp"
#include "estimation/invariant/eskf.hpp"
#include "estimation/invariant/invariant_ekf.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "lie/so3.hpp"
#include "model/imu_noise.hpp"
#include "trot_log.hpp"

using namespace legkit;

namespace {

// The mount of the tests: 20 deg about a tilted axis, 0.2 m from the base origin.
model::ImuExtrinsic mount() {
  model::ImuExtrinsic e;
  e.q_BI = Eigen::Quaterniond(
      Eigen::AngleAxisd(20.0 * M_PI / 180.0, Eigen::Vector3d(0.3, -0.5, 1.0).normalized()));
  e.p_BI = Eigen::Vector3d(0.15, -0.1, 0.09);  // |p_BI| = 0.2 m
  return e;
}

// The log an IMU at `e` would have recorded on the same run as `base_log`, whose base-origin
// readings are those of `exact` (the same run without noise or bias): the exact base rate w_B
// and specific force f_B, the angular acceleration dw_B as the central difference of w_B, moved
// to the IMU's point (imuReadingAt), plus the base log's noise and bias turned into the IMU's
// axes. Feet and truth stay the base's.
io::Log offsetImuLog(const io::Log& base_log, const io::Log& exact, const model::ImuExtrinsic& e) {
  io::Log log = base_log;
  const std::size_t n = log.rows.size();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t a = k == 0 ? 0 : k - 1, b = k + 1 == n ? k : k + 1;
    const Eigen::Vector3d dw_B =
        (exact.rows[b].gyro - exact.rows[a].gyro) / (exact.rows[b].t - exact.rows[a].t);
    const model::ImuReading exact_I = imuReadingAt(e, exact.rows[k].gyro, dw_B, exact.rows[k].acc);
    log.rows[k].gyro = exact_I.w_m + vectorInImu(e, base_log.rows[k].gyro - exact.rows[k].gyro);
    log.rows[k].acc = exact_I.a_m + vectorInImu(e, base_log.rows[k].acc - exact.rows[k].acc);
  }
  return log;
}

struct Scores {
  eval::Metrics m;
  double anees = 0.0;
};

template <typename Filter>
Scores scores(const io::Log& log, const model::ImuExtrinsic& e) {
  Filter filter;
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, e);
  const eval::RunResult run = eval::runOnLog(filter, log, frontend, eval::initialState(log));
  REQUIRE_FALSE(run.failed());
  return {eval::compare(log, run.trajectory), eval::normalisedAnees(run)};
}

}  // namespace

TEST_CASE("extrinsic frames: base -> IMU -> base is the identity, feet move as stated",
          "[57.11][extrinsic]") {
  const model::ImuExtrinsic e = mount();
  const Eigen::Matrix3d R_BI = e.q_BI.toRotationMatrix();
  const Eigen::Vector3d p_B(0.2, 0.15, -0.3);
  CHECK(pointInImu(e, p_B).isApprox(R_BI.transpose() * (p_B - e.p_BI), 1e-14));
  CHECK((R_BI * pointInImu(e, p_B) + e.p_BI).isApprox(p_B, 1e-14));
  CHECK(baseOriginInImu(e).isApprox(pointInImu(e, Eigen::Vector3d::Zero()), 1e-14));

  EstimateSample x_B;
  x_B.t = 1.5;
  x_B.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  x_B.v = Eigen::Vector3d(0.4, -0.2, 0.1);
  x_B.p = Eigen::Vector3d(3.0, 1.0, 0.3);
  const Eigen::Vector3d w_B(0.5, -1.2, 2.0);
  const EstimateSample x_I = imuFromBase(e, x_B, w_B);
  // The IMU point's world position and velocity from rigid-body kinematics.
  CHECK(x_I.p.isApprox(x_B.p + x_B.q * e.p_BI, 1e-14));
  CHECK(x_I.v.isApprox(x_B.v + x_B.q * w_B.cross(e.p_BI), 1e-14));
  const EstimateSample back = baseFromImu(e, x_I, vectorInImu(e, w_B));
  CHECK(back.q.angularDistance(x_B.q) < 1e-12);
  CHECK((back.v - x_B.v).norm() < 1e-12);
  CHECK((back.p - x_B.p).norm() < 1e-12);
}

TEST_CASE("extrinsic frames: the base covariance is the IMU's through the numerical Jacobian",
          "[57.11][extrinsic]") {
  const model::ImuExtrinsic e = mount();
  EstimateSample x_I;
  x_I.q = Eigen::Quaterniond(Eigen::AngleAxisd(-0.9, Eigen::Vector3d(2, -1, 1).normalized()));
  x_I.v = Eigen::Vector3d(0.3, 0.1, -0.05);
  x_I.p = Eigen::Vector3d(1.0, 2.0, 0.4);
  const Eigen::Vector3d w_I(1.5, -0.7, 2.5);
  // d (base error) / d (IMU error) in BaseCovariance's convention, by central differences.
  const EstimateSample x_B = baseFromImu(e, x_I, w_I);
  Eigen::Matrix<double, 9, 9> J;
  const double h = 1e-6;
  for (int i = 0; i < 9; ++i) {
    Eigen::Matrix<double, 9, 1> d = Eigen::Matrix<double, 9, 1>::Zero();
    d[i] = h;
    const auto perturbed = [&](double sign) {
      EstimateSample x = x_I;
      x.q = Eigen::Quaterniond(lie::SO3d::Exp(sign * d.head<3>()).matrix() *
                               x_I.q.toRotationMatrix());
      x.v += sign * d.segment<3>(3);
      x.p += sign * d.tail<3>();
      const EstimateSample b = baseFromImu(e, x, w_I);
      Eigen::Matrix<double, 9, 1> err;
      err << lie::SO3d::fromQuaternion(b.q)
                 .compose(lie::SO3d::fromQuaternion(x_B.q).inverse())
                 .Log(),
          b.v - x_B.v, b.p - x_B.p;
      return err;
    };
    J.col(i) = (perturbed(1.0) - perturbed(-1.0)) / (2.0 * h);
  }
  BaseCovariance P_I;
  const Eigen::Matrix<double, 9, 9> A = Eigen::Matrix<double, 9, 9>::Random();
  P_I.P = A * A.transpose() + Eigen::Matrix<double, 9, 9>::Identity();
  const BaseCovariance P_B = baseCovarianceFromImu(e, x_I, w_I, P_I);
  CHECK(P_B.P.isApprox(J * P_I.P * J.transpose(), 1e-7));
  // Without attitude the velocity-position block is passed on.
  P_I.has_attitude = false;
  CHECK(baseCovarianceFromImu(e, x_I, w_I, P_I).P == P_I.P);
}

TEST_CASE("extrinsic: the front end moves joints and foot columns into the IMU frame",
          "[57.11][extrinsic]") {
  const model::ImuExtrinsic e = mount();
  const Eigen::Matrix3d R_BI = e.q_BI.toRotationMatrix();
  const io::Log joints = test::trotLog(0.05, 3, false);
  const LogFrontend base(joints.layout, model::QuadrupedKinematics());
  const LogFrontend moved(joints.layout, model::QuadrupedKinematics(), FrontendNoise{}, e);
  const io::LogRow& row = joints.rows[20];
  const StepInput in_B = base.input(row, 1e-3), in_I = moved.input(row, 1e-3);
  REQUIRE(in_B.num_contacts > 0);
  REQUIRE(in_I.num_contacts == in_B.num_contacts);
  for (int k = 0; k < in_B.num_contacts; ++k) {
    const ContactMeasurement &b = in_B.contacts[k], &i = in_I.contacts[k];
    CHECK(i.p_body.isApprox(R_BI.transpose() * (b.p_body - e.p_BI), 1e-12));
    CHECK(i.v_body->isApprox(R_BI.transpose() * *b.v_body, 1e-12));
    CHECK(i.cov.isApprox(R_BI.transpose() * b.cov * R_BI, 1e-12));
  }
  CHECK(in_I.imu.w_m == row.gyro);  // the IMU's readings are the IMU's already

  // Foot columns are base-frame positions (and velocities) too.
  io::Log feet = joints;
  feet.layout.joints = false;
  feet.layout.foot_columns = io::FootCovariance::kFull;
  feet.layout.foot_velocity = true;
  for (int k = 0; k < in_B.num_contacts; ++k) {
    const ContactMeasurement& b = in_B.contacts[k];
    feet.rows[20].feet[b.foot] = {b.p_body, b.cov, *b.v_body};
  }
  const StepInput f_I = LogFrontend(feet.layout, model::QuadrupedKinematics(), FrontendNoise{}, e)
                            .input(feet.rows[20], 1e-3);
  REQUIRE(f_I.num_contacts == in_I.num_contacts);
  for (int k = 0; k < f_I.num_contacts; ++k) {
    CHECK(f_I.contacts[k].p_body.isApprox(in_I.contacts[k].p_body, 1e-12));
    CHECK(f_I.contacts[k].v_body->isApprox(*in_I.contacts[k].v_body, 1e-12));
    CHECK(f_I.contacts[k].cov.isApprox(in_I.contacts[k].cov, 1e-12));
  }
}

TEST_CASE("extrinsic: an IMU 0.2 m and 20 deg off the base, with and without the extrinsic",
          "[57.11][extrinsic]") {
  const double duration = 10.0;
  const unsigned seed = 4;
  const io::Log base_log = test::trotLog(duration, seed, false);
  const io::Log offset_log = offsetImuLog(base_log, test::trotLog(duration, seed, true), mount());
  const model::ImuExtrinsic none;

  const Scores eskf_base = scores<invariant::Eskf>(base_log, none);
  const Scores eskf_ext = scores<invariant::Eskf>(offset_log, mount());
  const Scores eskf_none = scores<invariant::Eskf>(offset_log, none);
  const Scores inekf_base = scores<invariant::InvariantEkf>(base_log, none);
  const Scores inekf_ext = scores<invariant::InvariantEkf>(offset_log, mount());
  const Scores inekf_none = scores<invariant::InvariantEkf>(offset_log, none);
  std::ostringstream table;
  for (const auto& [name, s] : {std::pair{"eskf base", eskf_base},
                                {"eskf extrinsic", eskf_ext},
                                {"eskf none", eskf_none},
                                {"inekf base", inekf_base},
                                {"inekf extrinsic", inekf_ext},
                                {"inekf none", inekf_none}}) {
    table << name << ": position RMSE " << s.m.position_rmse << " m, velocity RMSE "
          << s.m.velocity_rmse << " m/s, tilt " << s.m.tilt_rmse_deg << " deg, yaw "
          << s.m.yaw_rmse_deg << " deg, ANEES " << s.anees << "\n";
  }
  INFO(table.str());
  // With the extrinsic: position and attitude as with the IMU at the base, within 10 % (+ 2 mm,
  // 0.02 deg). The velocity is the IMU point's plus R (w x r_IB) with the row's measured rate, so
  // it carries the gyro's white noise through the lever arm, sqrt(2) sigma_g |p_BI| per sample
  // (0.036 m/s for the Go2's 0.004 rad/s/sqrt(Hz) at 1 kHz): its RMSE is the base run's and that
  // added in quadrature, within 5 %. ANEES rises for the same reason (the covariance map takes w
  // as exact) but stays within 2 of the base run's.
  const model::ImuNoise noise = model::ImuNoise::go2();
  const double lever = std::sqrt(2.0) * noise.gyroSampleSigma(1e-3) * mount().p_BI.norm();
  for (const auto& [b, x] : {std::pair{eskf_base, eskf_ext}, {inekf_base, inekf_ext}}) {
    CHECK(std::abs(x.m.position_rmse - b.m.position_rmse) < 0.1 * b.m.position_rmse + 2e-3);
    CHECK(std::abs(x.m.tilt_rmse_deg - b.m.tilt_rmse_deg) < 0.1 * b.m.tilt_rmse_deg + 0.02);
    CHECK(std::abs(x.m.yaw_rmse_deg - b.m.yaw_rmse_deg) < 0.1 * b.m.yaw_rmse_deg + 0.02);
    CHECK(x.m.velocity_rmse == Approx(std::hypot(b.m.velocity_rmse, lever)).epsilon(0.05));
    CHECK(std::abs(x.anees - b.anees) < 2.0);
  }
  // The contact pipeline on the log's flags carries the extrinsic the same way (its rolling foot
  // is left out with a mount, and the analytic trot's feet do not roll).
  invariant::Eskf filter;
  ContactPipeline pipeline(
      LogFrontend(offset_log.layout, model::QuadrupedKinematics(), FrontendNoise{}, mount()),
      PipelineOptions{});
  const eval::RunResult piped =
      eval::runOnLog(filter, offset_log, pipeline, eval::initialState(offset_log));
  REQUIRE_FALSE(piped.failed());
  CHECK(eval::compare(offset_log, piped.trajectory).position_rmse ==
        Approx(eskf_ext.m.position_rmse).epsilon(1e-9));
  // Without it the IMU's pose is scored as the base's: 20 deg of mount, 0.2 m of lever arm.
  for (const auto& [b, n] : {std::pair{eskf_base, eskf_none}, {inekf_base, inekf_none}}) {
    CHECK(n.m.tilt_rmse_deg > 5.0);
    CHECK(n.m.position_rmse > 10.0 * b.m.position_rmse);
    CHECK(n.anees > 50.0 * b.anees);
  }
}
