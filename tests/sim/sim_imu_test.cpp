// The IMU readings are those of the ground-truth motion: without noise, integrating them
// recovers the true trajectory; with noise, what is added has the statistics of the densities.
// The same seed gives the same log, bit for bit.
#include <catch2/catch.hpp>
#include <cmath>

#include "lie/so3.hpp"
#include "sim_test_support.hpp"

using namespace legkit;

TEST_CASE("Noise-free readings integrate back to the true trajectory", "[57.3][sim]") {
  for (const char* name : {"trot", "turn", "bound", "stand"}) {
    INFO("scenario " << name);
    const sim::SimResult run = sim::simulate(sim::test::noiselessRun(name, 4.0));
    const auto& rows = run.log.rows;
    const Eigen::Vector3d g = model::gravity();
    // Second-order integration (trapezoid on rates and accelerations) with the exact step.
    Eigen::Matrix3d R = rows[0].gt_q.toRotationMatrix();
    Eigen::Vector3d v = rows[0].gt_v, p = rows[0].gt_p;
    double attitude_error = 0.0, velocity_error = 0.0, position_error = 0.0;
    for (std::size_t k = 0; k + 1 < rows.size(); ++k) {
      const double dt = rows[k + 1].t - rows[k].t;
      const Eigen::Matrix3d R_next =
          R * lie::SO3d::Exp(0.5 * (rows[k].gyro + rows[k + 1].gyro) * dt).matrix();
      // a = R a_m + g (the accelerometer model solved for the world acceleration)
      const Eigen::Vector3d a = R * rows[k].acc + g;
      const Eigen::Vector3d a_next = R_next * rows[k + 1].acc + g;
      const Eigen::Vector3d v_next = v + 0.5 * (a + a_next) * dt;
      p += 0.5 * (v + v_next) * dt + (a - a_next) * dt * dt / 12.0;
      v = v_next;
      R = R_next;
      const io::LogRow& truth = rows[k + 1];
      attitude_error = std::max(
          attitude_error,
          lie::SO3d::fromMatrix(truth.gt_q.toRotationMatrix().transpose() * R, 1e-6).Log().norm());
      velocity_error = std::max(velocity_error, (v - truth.gt_v).norm());
      position_error = std::max(position_error, (p - truth.gt_p).norm());
    }
    CHECK(attitude_error < 1e-6);  // [rad] after 4 s
    CHECK(velocity_error < 1e-4);  // [m/s]
    CHECK(position_error < 1e-4);  // [m]
  }
}

namespace {

struct Stats {
  double mean = 0.0;
  double sigma = 0.0;
  double lag1 = 0.0;  // lag-1 autocorrelation
  int n = 0;
};

Stats statistics(const std::vector<double>& x) {
  Stats s;
  s.n = static_cast<int>(x.size());
  for (double v : x) s.mean += v;
  s.mean /= s.n;
  double var = 0.0, cov = 0.0;
  for (int i = 0; i < s.n; ++i) {
    var += (x[i] - s.mean) * (x[i] - s.mean);
    if (i > 0) cov += (x[i] - s.mean) * (x[i - 1] - s.mean);
  }
  s.sigma = std::sqrt(var / (s.n - 1));
  s.lag1 = cov / var;
  return s;
}

// White noise of standard deviation sigma: mean, spread and lag-1 correlation within the
// sampling error of n samples (4 standard errors; 3 % on sigma for n >= 12000).
void checkWhite(const std::vector<double>& x, double sigma) {
  const Stats s = statistics(x);
  INFO("mean " << s.mean << " sigma " << s.sigma << " (expected " << sigma << ") lag1 " << s.lag1);
  CHECK(std::abs(s.mean) < 4.0 * sigma / std::sqrt(s.n));
  CHECK(s.sigma == Approx(sigma).epsilon(0.03));
  CHECK(std::abs(s.lag1) < 4.0 / std::sqrt(s.n));
}

}  // namespace

TEST_CASE("Sensor noise has the statistics of the Go2 densities", "[57.3][sim]") {
  sim::SimOptions noisy;
  noisy.duration = 5.0;
  noisy.seed = 7;
  noisy.initial_bias.b_g = Eigen::Vector3d(0.01, -0.02, 0.005);
  noisy.initial_bias.b_a = Eigen::Vector3d(0.05, 0.02, -0.1);
  sim::SimOptions clean = noisy;
  clean.noiseless();
  const sim::SimResult a = sim::simulate(noisy);
  const sim::SimResult b = sim::simulate(clean);
  REQUIRE(a.log.rows.size() == b.log.rows.size());
  const double dt = 1.0 / noisy.rate;
  const model::ImuNoise& n = noisy.imu_noise;

  // reading - ideal reading = bias + white noise; the true biases come with the run.
  std::vector<double> gyro_white, acc_white, gyro_walk, acc_walk, angle, rate;
  for (std::size_t k = 0; k < a.log.rows.size(); ++k) {
    const io::LogRow& x = a.log.rows[k];
    const io::LogRow& y = b.log.rows[k];
    const Eigen::Vector3d eg = x.gyro - y.gyro - a.bias[k].b_g;
    const Eigen::Vector3d ea = x.acc - y.acc - a.bias[k].b_a;
    for (int i = 0; i < 3; ++i) {
      gyro_white.push_back(eg(i));
      acc_white.push_back(ea(i));
      if (k > 0) {
        gyro_walk.push_back(a.bias[k].b_g(i) - a.bias[k - 1].b_g(i));
        acc_walk.push_back(a.bias[k].b_a(i) - a.bias[k - 1].b_a(i));
      }
    }
    for (int j = 0; j < io::kNumJoints; ++j) {
      angle.push_back(x.q(j) - y.q(j));
      rate.push_back(x.dq(j) - y.dq(j));
    }
    CHECK(x.gt_p == y.gt_p);  // the truth does not depend on the noise
  }
  CHECK(a.bias[0].b_g == noisy.initial_bias.b_g);
  checkWhite(gyro_white, n.gyroSampleSigma(dt));
  checkWhite(acc_white, n.accelSampleSigma(dt));
  checkWhite(gyro_walk, n.gyroBiasStepSigma(dt));
  checkWhite(acc_walk, n.accelBiasStepSigma(dt));
  checkWhite(angle, noisy.encoder_angle_sigma);
  checkWhite(rate, noisy.encoder_rate_sigma);
}

TEST_CASE("The same seed gives the same log; another seed another noise", "[57.3][sim]") {
  sim::SimOptions options;
  options.duration = 2.0;
  options.faults.dropout_probability = 0.01;
  const sim::SimResult a = sim::simulate(options);
  const sim::SimResult b = sim::simulate(options);
  REQUIRE(a.log.rows.size() == b.log.rows.size());
  for (std::size_t k = 0; k < a.log.rows.size(); ++k) {
    REQUIRE(io::exactlyEqual(a.log.rows[k], b.log.rows[k]));
  }
  options.seed = 2;
  const sim::SimResult c = sim::simulate(options);
  CHECK(c.log.rows[0].gyro != a.log.rows[0].gyro);
  CHECK(c.log.rows[0].gt_p == a.log.rows[0].gt_p);
}
