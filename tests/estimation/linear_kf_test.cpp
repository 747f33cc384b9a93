// The linear Kalman filter of section 57.4 and its attitude filter: F, B, Q, H, R against hand
// values, the prediction against exact kinematics, one step against the dense textbook formulas,
// the Joseph update for any gain, whole runs on simulated trots, bad input, no allocation in
// step(), and Monte Carlo NEES.
#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>
#include <atomic>
#include <cstdlib>
#include <limits>
#include <new>
#include <random>
#include <sstream>

#include "estimation/leg_odometry/base_velocity.hpp"
#include "estimation/linear_kf/linear_kf.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/consistency.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "lie/so3.hpp"
#include "sim/simulator.hpp"

// Counts every heap allocation of this program, to show that LinearKf::step makes none.
namespace {
std::atomic<long> g_allocations{0};
}
void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  return operator new(size);
}
// The nothrow forms too (Catch uses them): every form must pair with the free() below, or a
// sanitizer build reports an allocation/deallocation mismatch.
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  ++g_allocations;
  return std::malloc(size == 0 ? 1 : size);
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept {
  return operator new(size, tag);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}

using namespace legkit;
using namespace legkit::linear_kf;

namespace {

const Eigen::Matrix3d I3 = Eigen::Matrix3d::Identity();

io::Log trotLog(double duration, unsigned seed, bool noiseless,
                const model::ImuBias& bias = model::ImuBias{}) {
  sim::SimOptions options;
  options.scenario = sim::scenarioByName("trot");
  options.duration = duration;
  options.seed = seed;
  options.initial_bias = bias;
  if (noiseless) options.noiseless();
  return sim::simulate(options).log;
}

std::vector<StepInput> inputsOf(const io::Log& log, const FrontendNoise& noise = {}) {
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics(), noise);
  std::vector<StepInput> inputs;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const double dt = k == 0 ? 0.0 : log.rows[k].t - log.rows[k - 1].t;
    inputs.push_back(frontend.input(log.rows[k], dt));
  }
  return inputs;
}

double minEigenvalue(const Matrix18& P) {
  return Eigen::SelfAdjointEigenSolver<Matrix18>(P).eigenvalues().minCoeff();
}

Eigen::Vector3d normal3(std::mt19937& gen, double sigma) {
  std::normal_distribution<double> n(0.0, sigma);
  return {n(gen), n(gen), n(gen)};
}

}  // namespace

TEST_CASE("LKF: F, B and Q against hand values", "[57.4][linear_kf]") {
  const double dt = 0.002;
  const ProcessNoise noise{0.04, 0.01, 10.0};
  const ContactMask contact{true, false, false, true};  // FL and RR in stance
  const ProcessModel m = processModel(dt, contact, noise);
  // F: identity with dt I on (p, v).
  Matrix18 F = Matrix18::Identity();
  for (int a = 0; a < 3; ++a) F(a, 3 + a) = 0.002;
  CHECK(m.F == F);
  // B: dt^2/2 = 2e-6 on p, dt = 2e-3 on v, zero on the feet.
  for (int r = 0; r < kDim; ++r) {
    for (int c = 0; c < 3; ++c) {
      const double expected = r == c ? 2e-6 : r == 3 + c ? 2e-3 : 0.0;
      CHECK(m.B(r, c) == Approx(expected).margin(1e-20));
    }
  }
  // Q: sigma_a^2 = 1.6e-3 through B with Sigma_u = sigma_a^2 / dt = 0.8:
  //   pp = 0.8 * (2e-6)^2 = 3.2e-12, pv = 0.8 * 2e-6 * 2e-3 = 3.2e-9, vv = 0.8 * 4e-6 = 3.2e-6;
  // feet: stance 1e-4 * 2e-3 = 2e-7, swing 100 * 2e-3 = 0.2.
  Matrix18 Q = Matrix18::Zero();
  for (int a = 0; a < 3; ++a) {
    Q(a, a) = 3.2e-12;
    Q(a, 3 + a) = Q(3 + a, a) = 3.2e-9;
    Q(3 + a, 3 + a) = 3.2e-6;
    Q(6 + a, 6 + a) = 2e-7;    // FL stance
    Q(9 + a, 9 + a) = 0.2;     // FR swing
    Q(12 + a, 12 + a) = 0.2;   // RL swing
    Q(15 + a, 15 + a) = 2e-7;  // RR stance
  }
  CHECK((m.Q - Q).cwiseAbs().maxCoeff() < 1e-15);
  const Eigen::Matrix<double, 6, 6> BSB =
      m.B.topRows<6>() * (0.0016 / dt * I3) * m.B.topRows<6>().transpose();
  CHECK((m.Q.topLeftCorner<6, 6>() - BSB).cwiseAbs().maxCoeff() < 1e-20);
  CHECK_THROWS_AS(processModel(0.0, contact, noise), std::invalid_argument);
  CHECK_THROWS_AS(processModel(-1e-3, contact, noise), std::invalid_argument);
  CHECK_THROWS_AS(processModel(dt, contact, ProcessNoise{-1.0, 0.01, 10.0}), std::invalid_argument);
}

TEST_CASE("LKF: H and R against hand values", "[57.4][linear_kf]") {
  for (int i = 0; i < kFeet; ++i) {
    const Matrix3x18 H = footMeasurementMatrix(i);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < kDim; ++c) {
        const double expected = c == r ? -1.0 : c == 6 + 3 * i + r ? 1.0 : 0.0;
        CHECK(H(r, c) == expected);
      }
    }
  }
  CHECK_THROWS_WITH(footMeasurementMatrix(4), Catch::Contains("foot id 4"));
  CHECK_THROWS_AS(footMeasurementMatrix(-1), std::invalid_argument);
  const Matrix3x18 Hv = velocityMeasurementMatrix();
  CHECK(Hv.block<3, 3>(0, 3) == I3);
  CHECK(Hv.cwiseAbs().sum() == 3.0);

  // R = R_hat C R_hat^T + [R_hat r]_x Sigma [R_hat r]_x^T. With R_hat a quarter turn about z,
  // r = (0.2, 0, -0.3): R_hat r = (0, 0.2, -0.3).
  const Eigen::Matrix3d R_hat = lie::SO3d::Exp(Eigen::Vector3d(0, 0, M_PI / 2)).matrix();
  const Eigen::Vector3d r(0.2, 0.0, -0.3);
  const Eigen::Matrix3d C = Eigen::Vector3d(1e-4, 4e-4, 9e-4).asDiagonal();
  // No attitude error: C rotated, x and y swapped.
  const Eigen::Matrix3d R0 = footMeasurementNoise(R_hat, r, C, Eigen::Matrix3d::Zero());
  CHECK((R0 - Eigen::Matrix3d(Eigen::Vector3d(4e-4, 1e-4, 9e-4).asDiagonal())).norm() < 1e-18);
  // Attitude error about x only (variance s): theta x z = s^(1/2) (0, 0.3, 0.2) for z above:
  // the extra term is s (0, 0.3, 0.2)(0, 0.3, 0.2)^T.
  const double s = 1e-4;
  const Eigen::Matrix3d Rx =
      footMeasurementNoise(R_hat, r, C, Eigen::Vector3d(s, 0, 0).asDiagonal()) - R0;
  const Eigen::Vector3d col(0.0, 0.3, 0.2);
  CHECK((Rx - s * col * col.transpose()).norm() < 1e-18);
}

TEST_CASE("LKF: the prediction is exact for a constant acceleration", "[57.4][linear_kf]") {
  // No contacts, no rotation, the attitude filter's correction off: the held acceleration
  // integrates exactly, p = p0 + v0 t + a t^2 / 2, v = v0 + a t.
  LinearKfParams params;
  params.attitude.k_P = params.attitude.k_I = 0.0;
  LinearKf filter(params);
  const Eigen::Matrix3d R = lie::SO3d::Exp(Eigen::Vector3d(0.1, -0.2, 0.7)).matrix();
  EstimateSample x0;
  x0.q = Eigen::Quaterniond(R);
  x0.v = Eigen::Vector3d(0.5, -0.2, 0.1);
  x0.p = Eigen::Vector3d(1.0, 2.0, 0.3);
  filter.reset(x0);
  const Eigen::Vector3d a(0.3, -1.2, 2.5);  // world acceleration
  StepInput in;
  in.imu.a_m = R.transpose() * (a - model::gravity());
  const double dt = 0.001;
  const int n = 2000;
  for (int k = 0; k <= n; ++k) {
    in.t = k * dt;
    in.dt = k == 0 ? 0.0 : dt;
    filter.step(in);
  }
  const double t = n * dt;
  const EstimateSample e = filter.estimate();
  CHECK((e.p - (x0.p + x0.v * t + 0.5 * a * t * t)).norm() < 1e-11);
  CHECK((e.v - (x0.v + a * t)).norm() < 1e-12);
  CHECK(e.q.angularDistance(x0.q) < 1e-12);
  CHECK(e.t == t);
}

TEST_CASE("LKF: one step equals the dense textbook formulas", "[57.4][linear_kf]") {
  // The filter's block arithmetic against x = F x + B u, P = F P F^T + Q and, per stance foot,
  // K = P H^T S^-1, x += K (z - H x), P = (I - K H) P (I - K H)^T + K R K^T, all dense. The
  // attitude terms are off here (checked on their own above), the leg velocity on and off.
  const io::Log log = trotLog(2.5, 3, false);  // trotting from t = 1 s
  const std::vector<StepInput> inputs = inputsOf(log);
  for (bool velocity : {false, true}) {
    LinearKfParams params;
    params.model_attitude_error = false;
    params.use_leg_velocity = velocity;
    LinearKf filter(params);
    filter.reset(eval::initialState(log));
    std::size_t k = 1600;  // a touchdown: a foot in stance at k + 1 that was not at k
    const auto down = [&](std::size_t j) {
      ContactMask m{};
      for (const ContactMeasurement& c : inputs[j].stance()) m[c.foot] = true;
      return m;
    };
    while (down(k + 1) == down(k) || inputs[k + 1].num_contacts < 2) ++k;
    REQUIRE(k + 1 < inputs.size());
    for (std::size_t j = 0; j <= k; ++j) filter.step(inputs[j]);
    Vector18 x = filter.x();
    Matrix18 P = filter.P();
    const Eigen::Matrix3d R_before = filter.attitude().R().matrix();
    const StepInput& in = inputs[k + 1];
    filter.step(in);
    const Eigen::Matrix3d R_after = filter.attitude().R().matrix();

    const ProcessModel m = processModel(in.dt, down(k), params.processNoise());
    const Eigen::Vector3d u = R_before * inputs[k].imu.a_m + model::gravity();
    x = m.F * x + m.B * u;
    P = m.F * P * m.F.transpose() + m.Q;
    const auto denseUpdate = [&](const Matrix3x18& H, const Eigen::Vector3d& z,
                                 const Eigen::Matrix3d& Rn) {
      const Eigen::Matrix3d S = H * P * H.transpose() + Rn;
      const Matrix18x3 K = P * H.transpose() * S.inverse();
      x += K * (z - H * x);
      const Matrix18 A = Matrix18::Identity() - K * H;
      P = A * P * A.transpose() + K * Rn * K.transpose();
    };
    for (const ContactMeasurement& c : in.stance())
      denseUpdate(footMeasurementMatrix(c.foot), R_after * c.p_body,
                  R_after * c.cov * R_after.transpose());
    if (velocity) {
      // The mean of the per-foot velocities, each -R (w x r_i + r_dot_i), and the covariance of
      // that mean with the gyro noise common to all feet.
      const Eigen::Vector3d w = in.imu.w_m - filter.attitude().b_g();
      Eigen::Vector3d z = Eigen::Vector3d::Zero(), r_bar = Eigen::Vector3d::Zero();
      Eigen::Matrix3d Rn = Eigen::Matrix3d::Zero();
      const double n = in.num_contacts;
      const double gyro_var = std::pow(params.imu.gyro_noise_density, 2) / in.dt;
      for (const ContactMeasurement& c : in.stance()) {
        z += leg_odometry::baseVelocityFromFoot(R_after, w, c) / n;
        r_bar += c.p_body / n;
        const Eigen::Matrix3d w_x = lie::hat3(w);
        Rn += R_after *
              (w_x * c.cov * w_x.transpose() + std::pow(params.foot_velocity_sigma, 2) * I3) *
              R_after.transpose() / (n * n);
      }
      const Eigen::Matrix3d r_x = lie::hat3(r_bar);
      Rn += R_after * r_x * (gyro_var * I3) * r_x.transpose() * R_after.transpose();
      denseUpdate(velocityMeasurementMatrix(), z, Rn);
    }
    INFO("leg velocity " << velocity << ", touchdown at sample " << k + 1);
    CHECK((filter.x() - x).cwiseAbs().maxCoeff() < 1e-10);
    CHECK((filter.P() - P).cwiseAbs().maxCoeff() < 1e-10 * P.cwiseAbs().maxCoeff());
  }
}

TEST_CASE("LKF: the update is the Joseph form for any gain", "[57.4][linear_kf]") {
  // josephUpdate's expanded form P + K V^T + V K^T equals (I - K H) P (I - K H)^T + K R K^T for
  // an arbitrary (not optimal) K. An error dK in the optimal gain changes the Joseph P only to
  // second order; the short form (I - K H) P changes to first order (the chapter's pitfall).
  std::mt19937 gen(7);
  std::normal_distribution<double> n01;
  Eigen::Matrix<double, kDim, kDim> A;
  for (int r = 0; r < kDim; ++r)
    for (int c = 0; c < kDim; ++c) A(r, c) = n01(gen);
  const Matrix18 AAt = A * A.transpose() / kDim;
  const Matrix18 P0 = 0.5 * (AAt + AAt.transpose()) + Matrix18::Identity() * 0.1;
  const Matrix3x18 H = footMeasurementMatrix(2);
  const Eigen::Matrix3d Rn = Eigen::Vector3d(1e-2, 2e-2, 3e-2).asDiagonal();
  const Matrix18x3 N = P0 * H.transpose();
  const Eigen::Matrix3d S = H * N + Rn;
  const Matrix18x3 K_opt = N * S.inverse();
  Matrix18x3 dK;
  for (int r = 0; r < kDim; ++r)
    for (int c = 0; c < 3; ++c) dK(r, c) = n01(gen);
  const auto joseph = [&](const Matrix18x3& K) {
    const Matrix18 IKH = Matrix18::Identity() - K * H;
    return Matrix18(IKH * P0 * IKH.transpose() + K * Rn * K.transpose());
  };
  const auto shortForm = [&](const Matrix18x3& K) {
    return Matrix18((Matrix18::Identity() - K * H) * P0);
  };
  for (double eps : {1e-2, 1e-3}) {
    const Matrix18x3 K = K_opt + eps * dK;
    Matrix18 P = P0;
    josephUpdate(P, K, N, S);
    CHECK((P - joseph(K)).cwiseAbs().maxCoeff() < 1e-12);
    CHECK(P == P.transpose());
  }
  const Matrix18 P_opt = joseph(K_opt);
  const auto err = [&](const Matrix18& P) { return (P - P_opt).cwiseAbs().maxCoeff(); };
  // Ten times smaller gain error: the Joseph error drops 100 times, the short form's 10 times.
  const double j2 = err(joseph(K_opt + 1e-2 * dK)), j3 = err(joseph(K_opt + 1e-3 * dK));
  const double s2 = err(shortForm(K_opt + 1e-2 * dK)), s3 = err(shortForm(K_opt + 1e-3 * dK));
  CHECK(j2 / j3 == Approx(100.0).epsilon(0.05));
  CHECK(s2 / s3 == Approx(10.0).epsilon(0.05));
  CHECK(s3 > 100.0 * j3);
  // The short form is not even symmetric with a perturbed gain.
  const Matrix18 Ps = shortForm(K_opt + 1e-3 * dK);
  CHECK((Ps - Ps.transpose()).cwiseAbs().maxCoeff() > 1e-4);
}

TEST_CASE("Attitude filter: levels the tilt and learns the horizontal gyro bias",
          "[57.4][attitude]") {
  // A robot standing still with a constant gyro bias, the filter started 3 degrees off in roll
  // and pitch with zero bias: the accelerometer pulls roll and pitch back, the integral term
  // learns b_g,x and b_g,y; yaw drifts with the vertical bias, which gravity cannot see.
  AttitudeFilterParams params;
  params.k_P = 1.0;
  params.k_I = 0.2;
  AttitudeFilter filter(params);
  const Eigen::Vector3d b_g(0.01, -0.02, 0.005);
  const Eigen::Matrix3d R_true = lie::SO3d::Exp(Eigen::Vector3d(0.0, 0.0, 0.4)).matrix();
  filter.reset(
      lie::SO3d::fromMatrix(R_true * lie::SO3d::Exp(Eigen::Vector3d(0.05, -0.05, 0.0)).matrix()));
  model::ImuReading u;
  u.w_m = b_g;
  u.a_m = R_true.transpose() * -model::gravity();
  const double dt = 0.001;
  for (int k = 0; k < 60000; ++k) filter.propagate(u, dt);
  const Eigen::Vector3d up_true = R_true.row(2), up = filter.R().matrix().row(2);
  CHECK(std::acos(std::min(1.0, up.dot(up_true))) < 1e-4);  // tilt error [rad]
  CHECK(std::abs(filter.b_g().x() - b_g.x()) < 1e-4);
  CHECK(std::abs(filter.b_g().y() - b_g.y()) < 1e-4);
  CHECK(filter.b_g().z() == 0.0);  // yaw bias unobservable: never corrected
  // Covariance: symmetric positive definite, tilt bounded, yaw growing.
  const Eigen::Matrix<double, 6, 6>& P = filter.P();
  CHECK((P - P.transpose()).norm() < 1e-15);
  CHECK(Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(P).eigenvalues().minCoeff() >
        0.0);
  CHECK(P(0, 0) < 1e-4);
  CHECK(P(2, 2) > P(0, 0));
  // Trust: 1 at |a_m| = g, 0 beyond the tolerance.
  CHECK(filter.trust(Eigen::Vector3d(0, 0, 9.81)) == 1.0);
  CHECK(filter.trust(Eigen::Vector3d(0, 0, 9.81 * 1.25)) == Approx(0.5));
  CHECK(filter.trust(Eigen::Vector3d(0, 0, 9.81 * 1.6)) == 0.0);
  CHECK_THROWS_AS(AttitudeFilter(AttitudeFilterParams{-1.0}), std::invalid_argument);
}

TEST_CASE("LKF: a noiseless trot is tracked", "[57.4][linear_kf]") {
  const io::Log log = trotLog(5.0, 1, true);
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics());
  LinearKf filter;
  const eval::RunResult run = eval::runOnLog(filter, log, frontend, eval::initialState(log));
  const eval::Metrics m = eval::compare(log, run.trajectory);
  WARN("LKF noiseless 5 s trot: position RMSE "
       << m.position_rmse << " m, velocity RMSE " << m.velocity_rmse << " m/s, tilt "
       << m.tilt_rmse_deg << " deg, yaw " << m.yaw_rmse_deg << " deg");
  CHECK(m.position_rmse < 2e-3);
  CHECK(m.velocity_rmse < 5e-3);
  CHECK(m.tilt_rmse_deg < 0.1);
  CHECK(m.yaw_rmse_deg < 0.05);
}

TEST_CASE("LKF: a noisy trot, against leg odometry and dead reckoning", "[57.4][linear_kf]") {
  const io::Log log = trotLog(10.0, 2, false);
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics());
  LinearKf filter;
  const eval::RunResult run = eval::runOnLog(filter, log, frontend, eval::initialState(log));
  const eval::Metrics m = eval::compare(log, run.trajectory);
  WARN("LKF noisy 10 s trot: position RMSE "
       << m.position_rmse << " m, velocity RMSE " << m.velocity_rmse << " m/s, drift "
       << m.drift_percent << " %, tilt " << m.tilt_rmse_deg << " deg, yaw " << m.yaw_rmse_deg
       << " deg");
  CHECK(m.position_rmse < 0.02);
  CHECK(m.velocity_rmse < 0.03);
  CHECK(m.tilt_rmse_deg < 0.5);
  CHECK(m.yaw_rmse_deg < 1.0);
  REQUIRE(run.sigma.size() == log.rows.size());
  CHECK(run.nees_dof == 6);
}

TEST_CASE("LKF: P stays symmetric positive definite; covariance() reorders", "[57.4][linear_kf]") {
  const io::Log log = trotLog(3.0, 5, false);
  const std::vector<StepInput> inputs = inputsOf(log);
  LinearKf filter;
  filter.reset(eval::initialState(log));
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    filter.step(inputs[k]);
    const Matrix18& P = filter.P();
    REQUIRE(P.allFinite());
    REQUIRE((P - P.transpose()).cwiseAbs().maxCoeff() == 0.0);
    if (k % 50 != 0) continue;
    REQUIRE(minEigenvalue(P) > 0.0);
    const BaseCovariance cov = *filter.covariance();
    REQUIRE(!cov.has_attitude);
    REQUIRE(cov.P.block<3, 3>(3, 3) == P.block<3, 3>(kV, kV));
    REQUIRE(cov.P.block<3, 3>(6, 6) == P.block<3, 3>(kP, kP));
    REQUIRE(cov.P.block<3, 3>(3, 6) == P.block<3, 3>(kV, kP));
    REQUIRE(cov.P.block<3, 3>(6, 3) == P.block<3, 3>(kP, kV));
    REQUIRE(cov.P.topLeftCorner<3, 3>() == filter.attitude().attitudeCovariance());
    REQUIRE(cov.P.block<3, 6>(0, 3).cwiseAbs().maxCoeff() == 0.0);
  }
}

TEST_CASE("LKF: step() never allocates", "[57.4][linear_kf]") {
  const io::Log log = trotLog(1.0, 8, false);
  const std::vector<StepInput> inputs = inputsOf(log);
  LinearKf filter;
  filter.reset(eval::initialState(log));
  const long before = g_allocations.load();
  for (const StepInput& in : inputs) filter.step(in);
  const long after = g_allocations.load();
  CHECK(after - before == 0);
  CHECK(filter.estimate().t == log.rows.back().t);  // it did run
}

TEST_CASE("LKF: bad input throws and leaves the state untouched", "[57.4][linear_kf]") {
  const io::Log log = trotLog(1.5, 2, false);
  const std::vector<StepInput> inputs = inputsOf(log);
  LinearKf filter;
  filter.reset(eval::initialState(log));
  std::size_t k = 0;
  for (; k < 1200; ++k) filter.step(inputs[k]);
  while (inputs[k].num_contacts < 2) filter.step(inputs[k++]);
  const Vector18 x = filter.x();
  const Matrix18 P = filter.P();
  const Eigen::Matrix3d R = filter.attitude().R().matrix();
  const Eigen::Vector3d b_g = filter.attitude().b_g();
  const double nan = std::numeric_limits<double>::quiet_NaN();

  const auto rejects = [&](const std::function<void(StepInput&)>& corrupt, const char* what) {
    StepInput in = inputs[k];
    corrupt(in);
    INFO(what);
    CHECK_THROWS_AS(filter.step(in), std::invalid_argument);
    CHECK_THROWS_WITH(filter.step(in), Catch::Contains("t = "));
    CHECK(filter.x() == x);
    CHECK(filter.P() == P);
    CHECK(filter.attitude().R().matrix() == R);
    CHECK(filter.attitude().b_g() == b_g);
  };
  rejects([&](StepInput& in) { in.imu.a_m.x() = nan; }, "NaN accelerometer");
  rejects([&](StepInput& in) { in.imu.w_m.z() = std::numeric_limits<double>::infinity(); },
          "inf gyro");
  rejects([&](StepInput& in) { in.dt = -1e-3; }, "negative dt");
  rejects([&](StepInput& in) { in.dt = nan; }, "NaN dt");
  rejects([&](StepInput& in) { in.t = nan; }, "NaN t");
  rejects([&](StepInput& in) { in.contacts[0].p_body.y() = nan; }, "NaN foot position");
  rejects([&](StepInput& in) { in.contacts[1].v_body = Eigen::Vector3d(nan, 0, 0); },
          "NaN foot velocity");
  rejects([&](StepInput& in) { in.contacts[0].foot = 8; }, "foot id 8");
  rejects([&](StepInput& in) { in.contacts[0].foot = -1; }, "foot id -1");
  rejects([&](StepInput& in) { in.contacts[1].foot = in.contacts[0].foot; }, "repeated foot");
  rejects([&](StepInput& in) { in.num_contacts = 5; }, "five contacts");
  rejects([&](StepInput& in) { in.contacts[0].cov(0, 0) = -1e-4; }, "negative variance");
  rejects([&](StepInput& in) { in.contacts[0].cov(0, 1) = 1e-3; }, "asymmetric covariance");
  rejects([&](StepInput& in) { in.contacts[1].cov.setZero(); }, "zero covariance");
  rejects([&](StepInput& in) { in.contacts[1].cov(2, 2) = nan; }, "NaN covariance");
  CHECK_THROWS_WITH(
      [&] {
        StepInput in = inputs[k];
        in.contacts[0].foot = 9;
        filter.step(in);
      }(),
      Catch::Contains("foot id 9") && Catch::Contains("out of range [0, 8)"));
  // And a good sample still goes through afterwards.
  filter.step(inputs[k]);
  CHECK(filter.x() != x);
}

TEST_CASE("LKF: bad parameters are rejected", "[57.4][linear_kf]") {
  const auto rejects = [](const std::function<void(LinearKfParams&)>& bad) {
    LinearKfParams p;
    bad(p);
    CHECK_THROWS_AS(LinearKf(p), std::invalid_argument);
  };
  rejects([](LinearKfParams& p) { p.foot_stance_density = -1.0; });
  rejects([](LinearKfParams& p) { p.imu.accel_noise_density = -1.0; });
  rejects([](LinearKfParams& p) { p.sigma_position = 0.0; });
  rejects([](LinearKfParams& p) { p.attitude_correlation_time = 0.0; });
  rejects([](LinearKfParams& p) { p.gravity.x() = std::numeric_limits<double>::quiet_NaN(); });
  rejects([](LinearKfParams& p) { p.attitude.k_P = -1.0; });
}

namespace {

struct NeesResult {
  int runs = 0;
  double mean = 0.0;      // mean over rows of ANEES_k (6 dof: 6 when consistent)
  double fraction = 0.0;  // rows with ANEES_k inside the bounds
  eval::ChiSquareBounds bounds;
  Eigen::Matrix<double, 6, 1> per_axis = Eigen::Matrix<double, 6, 1>::Zero();  // e^2 / sigma^2
  std::vector<double> per_second;  // mean ANEES_k over each second of the run
};

// M runs of the trot with their own seeds; each run's initial estimate error (velocity, position,
// attitude) and gyro bias are drawn from the priors the filter is given.
NeesResult monteCarloNees(const LinearKfParams& params, const FrontendNoise& frontend_noise,
                          int runs = 20, double duration = 6.0) {
  std::vector<double> anees;
  NeesResult out;
  out.runs = runs;
  std::size_t rows = 0;
  for (int run = 0; run < runs; ++run) {
    std::mt19937 gen(2000 + run);
    model::ImuBias bias;
    bias.b_g = normal3(gen, params.attitude.sigma_gyro_bias);
    const io::Log log = trotLog(duration, 100 + run, false, bias);
    EstimateSample x0 = eval::initialState(log);
    // Truth R = Exp(theta) R_hat: R_hat = Exp(-theta) R.
    Eigen::Vector3d theta = normal3(gen, params.attitude.sigma_tilt);
    theta.z() = std::normal_distribution<double>(0.0, params.attitude.sigma_yaw)(gen);
    x0.q = Eigen::Quaterniond(lie::SO3d::Exp(-theta).matrix() * x0.q.toRotationMatrix());
    x0.v -= normal3(gen, params.sigma_velocity);
    x0.p -= normal3(gen, params.sigma_position);
    LinearKf filter(params);
    const eval::RunResult result = eval::runOnLog(
        filter, log, LogFrontend(log.layout, model::QuadrupedKinematics(), frontend_noise), x0);
    if (anees.empty()) anees.assign(result.nees.size(), 0.0);
    for (std::size_t k = 0; k < anees.size(); ++k) anees[k] += result.nees[k] / runs;
    for (std::size_t k = 0; k < log.rows.size(); ++k) {
      const io::LogRow& row = log.rows[k];
      const EstimateSample truth{row.t, row.gt_q, row.gt_v, row.gt_p};
      const Eigen::Matrix<double, 9, 1> e = eval::baseError(truth, result.trajectory[k]);
      for (int a = 0; a < 6; ++a)
        out.per_axis(a) += e(3 + a) * e(3 + a) / std::pow(result.sigma[k](3 + a), 2);
    }
    rows += log.rows.size();
  }
  out.per_axis /= static_cast<double>(rows);
  out.bounds = eval::aneesBounds(6, runs);
  int inside = 0;
  for (const double a : anees) {
    out.mean += a / anees.size();
    inside += a >= out.bounds.lower && a <= out.bounds.upper;
  }
  out.fraction = static_cast<double>(inside) / anees.size();
  const std::size_t per_s = anees.size() / static_cast<std::size_t>(duration);
  for (std::size_t b = 0; b + per_s <= anees.size(); b += per_s) {
    double m = 0.0;
    for (std::size_t k = b; k < b + per_s; ++k) m += anees[k] / per_s;
    out.per_second.push_back(m);
  }
  return out;
}

std::string describe(const NeesResult& r) {
  std::ostringstream os;
  os << "ANEES over " << r.runs << " runs: mean " << r.mean << " (6 dof), bounds ["
     << r.bounds.lower << ", " << r.bounds.upper << "], " << 100 * r.fraction
     << " % of rows inside; per axis (v, p) " << r.per_axis.transpose() << "; per second";
  for (const double m : r.per_second) os << " " << m;
  return os.str();
}

}  // namespace

// The front end's foot-point sigma set to the simulator's level (its default 5 mm is a
// contact-point uncertainty the simulated point feet do not have), the filter's defaults.
// Measured (these seeds, 6 s): mean 6.52 inside [4.58, 7.61], 38 % of rows inside; per second
// 3.9 4.4 5.3 6.8 8.1 10.7. Per axis e^2 / sigma^2: v 0.60 0.83 1.57, p 0.48 1.95 1.06.
// Consistent on average but drifting from under- to over-confident: the attitude comes from
// outside the filter and its error is a slowly varying bias (yaw a random walk), which a filter
// without attitude in its state can only count as white noise (Q and R terms with Sigma_theta).
// The cross-track position (y, at 1.95) is where it shows: yaw error times distance walked.
// Without those attitude terms, or without the acceleration compensation of the attitude
// filter, the mean leaves the bounds (measured 16.4 without compensation, pitch error times
// forward speed making a vertical velocity bias).
TEST_CASE("LKF: Monte Carlo NEES on the default trot", "[57.4][linear_kf][nees]") {
  FrontendNoise frontend;
  frontend.foot_point_sigma = 5e-4;
  const NeesResult r = monteCarloNees(LinearKfParams{}, frontend);
  WARN("LKF: " << describe(r));
  CHECK(r.mean > r.bounds.lower);
  CHECK(r.mean < r.bounds.upper);
  CHECK(r.fraction > 0.3);
  REQUIRE(r.per_second.size() == 6);
  CHECK(r.per_second.front() < r.bounds.upper);       // not over-confident while standing
  CHECK(r.per_second.back() > r.per_second.front());  // the unmodelled attitude bias grows
}

TEST_CASE("LKF: without the attitude model the filter is over-confident",
          "[57.4][linear_kf][nees]") {
  // The same runs with model_attitude_error = false and no acceleration compensation.
  FrontendNoise frontend;
  frontend.foot_point_sigma = 5e-4;
  LinearKfParams params;
  params.model_attitude_error = false;
  params.accel_compensation_time = 0.0;
  const NeesResult r = monteCarloNees(params, frontend, 10);
  WARN("LKF without attitude model: " << describe(r));
  CHECK(r.mean > 2.0 * r.bounds.upper);
}
