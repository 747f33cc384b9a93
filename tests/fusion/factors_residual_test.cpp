// The smoother's factors (section 57.8) vanish at the true states of a noise-free motion.
//
// The motion is a helix about the vertical, written in closed form (not integrated): the body
// turns at a constant body rate w_b whose world direction R_0 w_b is vertical, and moves at a
// constant body-frame velocity v_b, so
//   R(t) = R_0 Exp(w_b t),   v(t) = R(t) v_b,   p(t) = p_0 + R_0 Gamma_1(w_b t) v_b t,
// and the specific force f = w_b x v_b - R(t)^T g is constant too (R_0^T g is along w_b, which
// Exp(-w_b t) leaves alone). The gyro, accelerometer and leg velocity readings are therefore
// constant, and both preintegrations are exact for such input: the whitened residuals are zero
// to rounding. R_0 is tilted, so w_b has all three body components.
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <catch2/catch.hpp>
#include <cmath>
#include <tuple>

#include "estimation/fusion/factors.hpp"
#include "estimation/fusion/keyframe.hpp"
#include "lie/ceres/manifolds.hpp"
#include "lie/so3.hpp"
#include "sim/base_trajectory.hpp"

#include "ceres_catch.hpp"  // after Ceres: Catch's CHECK, not glog's

using Eigen::Matrix3d;
using Eigen::Vector3d;
using legkit::fusion::ImuFactor;
using legkit::fusion::LegOdometryFactor;
using legkit::fusion::LegPreintegrator;
using legkit::fusion::PoseFactor;
using legkit::fusion::PoseMeasurement;
using legkit::imu::Preintegrator;
using legkit::model::ImuBias;
using legkit::model::ImuReading;

namespace {

constexpr double kDt = 1e-3;

struct Helix {
  Matrix3d R_0;
  Vector3d w_b, v_b, p_0;
  Vector3d g = legkit::model::gravity();

  Helix() {
    R_0 = lie::SO3d::Exp(Vector3d(0.4, -0.3, 0.9)).matrix();
    w_b = R_0.transpose() * Vector3d(0.0, 0.0, 0.7);  // 0.7 rad/s yaw rate about the vertical
    v_b = Vector3d(0.6, -0.1, 0.05);                  // forward, a little sideways and up
    p_0 = Vector3d(1.0, 2.0, 0.3);
  }
  Matrix3d R(double t) const { return R_0 * lie::SO3d::Exp(Vector3d(w_b * t)).matrix(); }
  Vector3d v(double t) const { return R(t) * v_b; }
  Vector3d p(double t) const { return p_0 + R_0 * lie::Gamma<1>(Vector3d(w_b * t)) * v_b * t; }
  Vector3d specificForce(double t) const { return w_b.cross(v_b) - R(t).transpose() * g; }
};

}  // namespace

TEST_CASE("57.8 the helix is what it claims: p' = v, constant specific force", "[factors]") {
  const Helix h;
  const double t = 1.3, e = 1e-5;
  CHECK(((h.p(t + e) - h.p(t - e)) / (2 * e) - h.v(t)).norm() <= 1e-8);
  const Vector3d a = (h.v(t + e) - h.v(t - e)) / (2 * e);
  CHECK((h.R(t).transpose() * (a - h.g) - h.specificForce(0.0)).norm() <= 1e-8);
  CHECK((h.specificForce(t) - h.specificForce(0.0)).norm() <= 1e-12);
}

TEST_CASE("57.8 IMU, leg and pose factors vanish at the true states of a noise-free helix",
          "[factors]") {
  const Helix h;
  ImuBias b;  // the sensors' true biases, also the preintegrations' linearisation point
  b.b_g = Vector3d(0.01, -0.02, 0.005);
  b.b_a = Vector3d(-0.1, 0.05, 0.2);
  const Vector3d b_v(0.03, -0.01, 0.02);  // the legs' velocity bias

  const double t_i = 0.7;
  const int n = 100;  // 0.1 s between keyframes at 1 kHz
  const double t_j = t_i + n * kDt;
  Preintegrator pim(b);
  LegPreintegrator lpi(b.b_g, b_v);
  const Matrix3d Sigma_v = Vector3d(0.05, 0.05, 0.1).cwiseAbs2().asDiagonal();
  for (int k = 0; k < n; ++k) {
    const ImuReading m{h.w_b + b.b_g, h.specificForce(t_i + k * kDt) + b.b_a};
    pim.integrate(m, kDt);
    lpi.integrate(m.w_m, h.v_b + b_v, Sigma_v, kDt);
  }

  const Matrix3d R_i = h.R(t_i), R_j = h.R(t_j);
  const Vector3d v_i = h.v(t_i), v_j = h.v(t_j), p_i = h.p(t_i), p_j = h.p(t_j);
  // How far the keyframes are apart, so that a zero residual says something.
  REQUIRE((p_j - p_i).norm() > 0.05);
  REQUIRE(lie::SO3d::logOfMatrix(R_i.transpose() * R_j).norm() > 0.05);

  const ImuFactor imu(pim, h.g);
  const double* x_imu[] = {R_i.data(), v_i.data(), p_i.data(),   R_j.data(),
                           v_j.data(), p_j.data(), b.b_g.data(), b.b_a.data()};
  Eigen::Matrix<double, 9, 1> r_imu;
  REQUIRE(imu.Evaluate(x_imu, r_imu.data(), nullptr));
  INFO("IMU residual (whitened) " << r_imu.transpose());
  CHECK(r_imu.cwiseAbs().maxCoeff() <= 1e-6);

  const LegOdometryFactor leg(lpi);
  const double* x_leg[] = {R_i.data(), p_i.data(), p_j.data(), b_v.data(), b.b_g.data()};
  Vector3d r_leg;
  REQUIRE(leg.Evaluate(x_leg, r_leg.data(), nullptr));
  INFO("leg residual (whitened) " << r_leg.transpose());
  CHECK(r_leg.cwiseAbs().maxCoeff() <= 1e-6);

  PoseMeasurement z;
  z.t = t_j;
  z.R_MB = lie::SO3d::fromMatrix(R_j);
  z.p_MB = p_j;
  z.cov.diagonal() << 1e-6, 1e-6, 1e-6, 1e-4, 1e-4, 1e-4;
  const PoseFactor pose(z);
  const double* x_pose[] = {R_j.data(), p_j.data()};
  Eigen::Matrix<double, 6, 1> r_pose;
  REQUIRE(pose.Evaluate(x_pose, r_pose.data(), nullptr));
  CHECK(r_pose.cwiseAbs().maxCoeff() <= 1e-9);

  // The same factors see a wrong state: each residual is far from zero (whitened, > 3 sigma).
  const Vector3d p_j_wrong = p_j + Vector3d(0.05, 0.0, 0.0);
  x_imu[5] = p_j_wrong.data();
  x_leg[2] = p_j_wrong.data();
  x_pose[1] = p_j_wrong.data();
  REQUIRE(imu.Evaluate(x_imu, r_imu.data(), nullptr));
  REQUIRE(leg.Evaluate(x_leg, r_leg.data(), nullptr));
  REQUIRE(pose.Evaluate(x_pose, r_pose.data(), nullptr));
  CHECK(r_imu.norm() > 3.0);
  CHECK(r_leg.norm() > 3.0);
  CHECK(r_pose.norm() > 3.0);
  // A wrong velocity bias moves only the leg factor.
  const Vector3d b_v_wrong = b_v + Vector3d(0.05, 0.0, 0.0);
  x_leg[2] = p_j.data();
  x_leg[3] = b_v_wrong.data();
  REQUIRE(leg.Evaluate(x_leg, r_leg.data(), nullptr));
  CHECK(r_leg.norm() > 3.0);
}

TEST_CASE("57.8 a Ceres solve on the SO3 manifold returns the factors to the helix's states",
          "[factors]") {
  // Two keyframes 0.1 s apart, an exteroceptive pose on each, the IMU and leg factors between
  // them, the biases known (held constant). From attitudes 0.3 rad off, positions 0.2 m off and
  // velocities 0.5 m/s off, the solver must return to the true states: this exercises the ambient
  // Jacobians through SO3Manifold exactly as the smoother will.
  const Helix h;
  const double t_i = 0.2;
  const int n = 100;
  const double t_j = t_i + n * kDt;
  Preintegrator pim;
  LegPreintegrator lpi;
  const Matrix3d Sigma_v = Vector3d(0.05, 0.05, 0.1).cwiseAbs2().asDiagonal();
  for (int k = 0; k < n; ++k) {
    pim.integrate(ImuReading{h.w_b, h.specificForce(t_i + k * kDt)}, kDt);
    lpi.integrate(h.w_b, h.v_b, Sigma_v, kDt);
  }

  legkit::fusion::Keyframe kf[2];
  const double t[2] = {t_i, t_j};
  const Vector3d dtheta[2] = {Vector3d(0.3, -0.1, 0.2), Vector3d(-0.2, 0.25, 0.1)};
  for (int m = 0; m < 2; ++m) {
    kf[m].t = t[m];
    kf[m].Rmat() = h.R(t[m]) * lie::SO3d::Exp(dtheta[m]).matrix();
    Eigen::Map<Vector3d>(kf[m].v.data()) = h.v(t[m]) + Vector3d(0.5, -0.3, 0.2);
    Eigen::Map<Vector3d>(kf[m].p.data()) = h.p(t[m]) + Vector3d(-0.2, 0.1, 0.15);
  }

  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  lie::ceres::SO3Manifold so3;
  for (int m = 0; m < 2; ++m) {
    PoseMeasurement z;
    z.t = t[m];
    z.R_MB = lie::SO3d::fromMatrix(h.R(t[m]));
    z.p_MB = h.p(t[m]);
    z.cov.diagonal() << 1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4;
    problem.AddResidualBlock(new PoseFactor(z), nullptr, kf[m].R.data(), kf[m].p.data());
  }
  problem.AddResidualBlock(new ImuFactor(pim, h.g), nullptr, kf[0].R.data(), kf[0].v.data(),
                           kf[0].p.data(), kf[1].R.data(), kf[1].v.data(), kf[1].p.data(),
                           kf[0].b_g.data(), kf[0].b_a.data());
  problem.AddResidualBlock(new LegOdometryFactor(lpi), nullptr, kf[0].R.data(), kf[0].p.data(),
                           kf[1].p.data(), kf[0].b_v.data(), kf[0].b_g.data());
  for (double* b : {kf[0].b_g.data(), kf[0].b_a.data(), kf[0].b_v.data()}) {
    problem.SetParameterBlockConstant(b);
  }
  for (int m = 0; m < 2; ++m) problem.SetManifold(kf[m].R.data(), &so3);

  ceres::Solver::Options options;
  options.max_num_iterations = 50;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  INFO(summary.BriefReport());
  REQUIRE(summary.IsSolutionUsable());
  CHECK(summary.final_cost <= 1e-12);
  for (int m = 0; m < 2; ++m) {
    const double angle = lie::SO3d::logOfMatrix(h.R(t[m]).transpose() * kf[m].Rmat()).norm();
    const double dv = (Eigen::Map<const Vector3d>(kf[m].v.data()) - h.v(t[m])).norm();
    const double dp = (Eigen::Map<const Vector3d>(kf[m].p.data()) - h.p(t[m])).norm();
    INFO("keyframe " << m << ": " << angle << " rad, " << dv << " m/s, " << dp << " m off");
    CHECK(angle <= 1e-8);
    CHECK(dv <= 1e-8);
    CHECK(dp <= 1e-8);
    // The rotation stayed a rotation (Plus is R Exp(delta)).
    CHECK((kf[m].Rmat().transpose() * kf[m].Rmat() - Matrix3d::Identity()).norm() <= 1e-12);
  }
}

namespace {

// Whitened IMU and leg residuals, and the leg's raw one [m], at the true states of the simulator's
// analytic trot (turning, rolling, pitching, bobbing: a general motion), the readings sampled at
// each step's midpoint.
std::tuple<double, double, double> trotResiduals(double dt) {
  legkit::sim::Scenario sc = legkit::sim::scenarioByName("trot");
  sc.yaw_rate = 0.4;
  sc.roll_amplitude = 0.1, sc.roll_frequency = 2.0;
  sc.pitch_amplitude = 0.08, sc.pitch_frequency = 2.0;
  const legkit::sim::BaseTrajectory traj(sc);
  const Vector3d g = legkit::model::gravity();
  const double t_i = 3.0, T = 0.1;
  const int n = static_cast<int>(std::lround(T / dt));
  Preintegrator pim;
  LegPreintegrator lpi;
  const Matrix3d Sigma_v = Vector3d(0.05, 0.05, 0.1).cwiseAbs2().asDiagonal();
  for (int k = 0; k < n; ++k) {
    const legkit::sim::BaseState x = traj.at(t_i + (k + 0.5) * dt);
    pim.integrate(legkit::model::idealReading(x.R, x.a, x.w, ImuBias{}, g), dt);
    lpi.integrate(x.w, x.R.transpose() * x.v, Sigma_v, dt);
  }
  const legkit::sim::BaseState xi = traj.at(t_i), xj = traj.at(t_i + n * dt);
  const Vector3d zero = Vector3d::Zero();
  const double* x_imu[] = {xi.R.data(), xi.v.data(), xi.p.data(), xj.R.data(),
                           xj.v.data(), xj.p.data(), zero.data(), zero.data()};
  const double* x_leg[] = {xi.R.data(), xi.p.data(), xj.p.data(), zero.data(), zero.data()};
  Eigen::Matrix<double, 9, 1> r_imu;
  Vector3d r_leg;
  ImuFactor(pim, g).Evaluate(x_imu, r_imu.data(), nullptr);
  const LegOdometryFactor leg(lpi);
  leg.Evaluate(x_leg, r_leg.data(), nullptr);
  return {r_imu.norm(), r_leg.norm(), (leg.sqrtInformation().inverse() * r_leg).norm()};
}

}  // namespace

TEST_CASE("57.8 on a general motion the residuals at the truth vanish as dt^2", "[factors]") {
  // Midpoint readings make the held-input integration second-order: halving dt quarters the
  // residual; at 1 kHz it is far below one sigma. (The leg's whitening changes with dt: Sigma_v
  // is one sample's covariance, so dp's covariance T Sigma_v dt halves; its raw residual is
  // compared.)
  const auto [imu_1ms, leg_1ms, leg_raw_1ms] = trotResiduals(1e-3);
  const auto [imu_half, leg_half, leg_raw_half] = trotResiduals(0.5e-3);
  WARN("whitened residual norms at 1 ms: IMU " << imu_1ms << ", leg " << leg_1ms
                                               << "; at 0.5 ms: IMU " << imu_half << ", leg "
                                               << leg_half);
  CHECK(imu_1ms <= 0.05);
  CHECK(leg_1ms <= 0.05);
  CHECK(imu_1ms / imu_half >= 3.0);
  CHECK(leg_raw_1ms / leg_raw_half >= 3.0);
}
