// Stationary initialisation (section 57.9): a simulated stand with a known gyro bias and tilt is
// recovered within what the window's noise justifies; a trotting robot never looks still; the
// search gives up after max_wait; add() never allocates; the filters take the result. (This
// program counts allocations, so the gated filters' no-allocation check lives here too.)
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "allocation_counter.hpp"
#include "estimation/engineering/stationary_init.hpp"
#include "estimation/invariant/eskf.hpp"
#include "estimation/invariant/invariant_ekf.hpp"
#include "estimation/invariant/tsif.hpp"
#include "estimation/linear_kf/linear_kf.hpp"
#include "estimation/log_frontend.hpp"
#include "lie/so3.hpp"
#include "model/imu_noise.hpp"
#include "sim/simulator.hpp"

using namespace legkit;
using engineering::StationaryInitialiser;
using engineering::StationaryInitParams;

namespace {

constexpr double kRate = 1000.0;  // [Hz]

// A robot standing still with attitude R, gyro bias b_g and accelerometer bias b_a, Go2 noise.
struct Stand {
  Eigen::Matrix3d R;
  Eigen::Vector3d b_g, b_a;
  model::ImuNoise noise = model::ImuNoise::go2();
  std::mt19937 gen{7};

  model::ImuReading sample() {
    std::normal_distribution<double> n(0.0, 1.0);
    const double dt = 1.0 / kRate;
    model::ImuReading u;
    u.w_m = b_g + noise.gyroSampleSigma(dt) * Eigen::Vector3d(n(gen), n(gen), n(gen));
    u.a_m = R.transpose() * (-model::gravity()) + b_a +
            noise.accelSampleSigma(dt) * Eigen::Vector3d(n(gen), n(gen), n(gen));
    return u;
  }
};

Stand tiltedStand() {
  Stand s;
  s.R = (Eigen::AngleAxisd(0.08, Eigen::Vector3d::UnitY()) *  // pitch 4.6 deg
         Eigen::AngleAxisd(-0.05, Eigen::Vector3d::UnitX()))  // roll -2.9 deg
            .toRotationMatrix();
  s.b_g = Eigen::Vector3d(0.01, -0.02, 0.005);
  s.b_a.setZero();
  return s;
}

// Roll and pitch of R (yaw-free): the world z axis seen in the body frame.
Eigen::Vector2d rollPitch(const Eigen::Matrix3d& R) {
  const Eigen::Vector3d up = R.transpose() * Eigen::Vector3d::UnitZ();
  return {std::atan2(up.y(), up.z()), std::atan2(-up.x(), std::hypot(up.y(), up.z()))};
}

}  // namespace

TEST_CASE("stationary init: a stand's gyro bias and tilt, within the window's noise",
          "[57.9][stationary]") {
  Stand stand = tiltedStand();
  const StationaryInitParams params;  // 2 s window
  StationaryInitialiser init(params);
  double t = 0.0;
  while (!init.add(t, stand.sample())) t += 1.0 / kRate;
  REQUIRE(init.ready());
  CHECK_FALSE(init.gaveUp());
  CHECK(t == Approx(params.duration).margin(0.15));  // found with the first full window

  const InitialState s = init.result();
  // The mean of N = 2000 samples: b_g error sigma = density / sqrt(T) = 0.004 / sqrt(2)
  // = 2.8e-3 rad/s per axis; 4 sigma.
  const double sigma_bg = stand.noise.gyro_noise_density / std::sqrt(params.duration);
  CHECK((s.b_g - stand.b_g).cwiseAbs().maxCoeff() < 4.0 * sigma_bg);
  CHECK(s.b_a.isZero());
  // Tilt: the accel mean's error sigma = 0.04 / sqrt(2) / 9.81 = 2.9e-3 rad from noise alone;
  // sigma_tilt also carries the 0.02 m/s^2 bias prior: sqrt(0.028^2 + 0.02^2) / 9.81 = 3.5e-3.
  const double sigma_noise = stand.noise.accel_noise_density / std::sqrt(params.duration) / 9.81;
  CHECK(s.sigma_tilt == Approx(std::hypot(sigma_noise * 9.81, 0.02) / 9.81).epsilon(0.1));
  const Eigen::Matrix3d R_hat = s.x.q.toRotationMatrix();
  CHECK((rollPitch(R_hat) - rollPitch(stand.R)).cwiseAbs().maxCoeff() < 4.0 * sigma_noise);
  // Yaw 0, at rest, at the origin.
  CHECK(std::abs(std::atan2(R_hat(1, 0), R_hat(0, 0))) < 1e-12);
  CHECK(s.x.v.isZero());
  CHECK(s.x.p.isZero());
}

TEST_CASE("stationary init: an accelerometer bias reads as tilt unless it is given",
          "[57.9][stationary]") {
  Stand stand = tiltedStand();
  stand.b_a = Eigen::Vector3d(0.15, 0.0, 0.0);  // 0.15 m/s^2 along x: 15 mrad of pitch
  StationaryInitialiser init(StationaryInitParams{});
  for (double t = 0.0; !init.add(t, stand.sample()); t += 1.0 / kRate) {
  }
  const double pitch_error =
      rollPitch(init.result().x.q.toRotationMatrix())(1) - rollPitch(stand.R)(1);
  CHECK(std::abs(pitch_error + 0.15 / 9.81) < 0.006);  // b / g, less the noise
  const InitialState known = init.result(stand.b_a, 0.001);
  CHECK(std::abs(rollPitch(known.x.q.toRotationMatrix())(1) - rollPitch(stand.R)(1)) < 0.012);
  CHECK(known.b_a == stand.b_a);
  CHECK(known.sigma_tilt < init.result().sigma_tilt);
}

TEST_CASE("stationary init: a trotting robot never looks still; the search gives up",
          "[57.9][stationary]") {
  sim::SimOptions options;
  options.scenario = sim::scenarioByName("trot");
  options.duration = 12.0;
  const io::Log log = sim::simulate(options).log;
  StationaryInitParams params;
  params.max_wait = 10.0;
  StationaryInitialiser init(params);
  bool still = false;
  double gave_up_at = -1.0;
  for (const io::LogRow& row : log.rows) {
    model::ImuReading u;
    u.w_m = row.gyro;
    u.a_m = row.acc;
    still = init.add(row.t, u) || still;
    if (init.gaveUp() && gave_up_at < 0.0) gave_up_at = row.t;
  }
  CHECK_FALSE(still);
  CHECK_FALSE(init.ready());
  CHECK(init.gaveUp());
  CHECK(gave_up_at - log.rows.front().t == Approx(10.0).margin(0.002));
  CHECK_THROWS_AS(init.result(), std::logic_error);
}

TEST_CASE("stationary init: add() never allocates; bad input", "[57.9][stationary]") {
  Stand stand = tiltedStand();
  StationaryInitialiser init(StationaryInitParams{});
  const long before = test::allocationCount();
  for (int k = 0; k < 3000; ++k) init.add(k / kRate, stand.sample());
  CHECK(test::allocationCount() == before);
  CHECK(init.ready());
  CHECK_THROWS_AS(StationaryInitialiser(StationaryInitParams{}, Eigen::Vector3d(0, 9.81, 0)),
                  std::invalid_argument);
  StationaryInitParams bad;
  bad.duration = 0.0;
  CHECK_THROWS_WITH(StationaryInitialiser{bad}, Catch::Contains("duration"));
  StationaryInitialiser fresh(StationaryInitParams{});
  fresh.add(1.0, stand.sample());
  CHECK_THROWS_AS(fresh.add(0.5, stand.sample()), std::invalid_argument);
}

TEST_CASE("stationary init: every filter starts from the result", "[57.9][stationary]") {
  InitialState s;
  s.x.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()));
  s.b_g = Eigen::Vector3d(0.01, -0.02, 0.005);
  s.b_a = Eigen::Vector3d(0.1, 0.0, -0.05);
  s.sigma_tilt = 0.002;

  invariant::Eskf eskf;
  eskf.initialise(s);
  CHECK(eskf.state().b_g == s.b_g);
  CHECK(eskf.state().b_a == s.b_a);
  invariant::InvariantEkf inekf;
  inekf.initialise(s);
  CHECK(inekf.b_g() == s.b_g);
  CHECK(inekf.b_a() == s.b_a);
  invariant::Tsif tsif;
  tsif.initialise(s);
  CHECK(tsif.state().b_a == s.b_a);
  linear_kf::LinearKf lkf;
  lkf.initialise(s);
  CHECK(lkf.attitude().b_g() == s.b_g);
  CHECK(lkf.params().b_a == s.b_a);
  CHECK(lkf.attitude().attitudeCovariance()(0, 0) == Approx(s.sigma_tilt * s.sigma_tilt));
  // The world-frame attitude covariance each reports: roll and pitch sigma_tilt, yaw the prior.
  for (const Estimator* e : std::initializer_list<const Estimator*>{&eskf, &inekf, &tsif}) {
    INFO(e->name());
    const Eigen::Matrix3d P = e->covariance()->P.topLeftCorner<3, 3>();
    CHECK(P(0, 0) == Approx(4e-6).epsilon(1e-9));
    CHECK(P(1, 1) == Approx(4e-6).epsilon(1e-9));
    CHECK(P(2, 2) == Approx(1e-4).epsilon(1e-9));
    CHECK(std::abs(P(0, 1)) < 1e-15);
  }
  InitialState bad = s;
  bad.sigma_tilt = -1.0;
  CHECK_THROWS_WITH(eskf.initialise(bad), Catch::Contains("sigma_tilt"));
}

TEST_CASE("gating: a filter with the gate on never allocates in step()", "[57.9][gating]") {
  sim::SimOptions options;
  options.scenario = sim::scenarioByName("trot");
  options.duration = 1.0;
  const io::Log log = sim::simulate(options).log;
  std::vector<StepInput> in =
      LogFrontend(log.layout, model::QuadrupedKinematics(), FrontendNoise{}).inputs(log);
  for (StepInput& s : in)  // every tenth sample's first foot 1 m off: gated, then re-placed
    if (s.num_contacts > 0 && static_cast<int>(s.t * 1000) % 10 == 0) s.contacts[0].p_body.x() += 1;
  engineering::GatingParams gating;
  gating.enabled = true;
  invariant::EskfParams eskf;
  eskf.gating = gating;
  invariant::InvariantEkfParams inekf;
  inekf.gating = gating;
  invariant::TsifParams tsif;
  tsif.gating = gating;
  linear_kf::LinearKfParams lkf;
  lkf.gating = gating;
  invariant::Eskf a(eskf);
  invariant::InvariantEkf b(inekf);
  invariant::Tsif c(tsif);
  linear_kf::LinearKf d(lkf);
  for (Estimator* e : std::initializer_list<Estimator*>{&a, &b, &c, &d}) {
    INFO(e->name());
    e->reset(EstimateSample{});
    for (std::size_t k = 0; k < 100; ++k) e->step(in[k]);  // the InEKF sizes its P once
    const long before = test::allocationCount();
    for (std::size_t k = 100; k < in.size(); ++k) e->step(in[k]);
    CHECK(test::allocationCount() == before);
    CHECK(e->health()[Fault::kGated] > 0);
  }
}
