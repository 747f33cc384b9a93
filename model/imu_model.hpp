// The IMU sensor model of section 57.2, used to synthesise readings from a true motion:
//   gyro           w_m = w + b_g + n_g
//   accelerometer  a_m = R^T (a - g) + b_a + n_a
//   bias           b_{k+1} = b_k + sigma_b sqrt(dt) xi_k   (random walk, xi_k ~ N(0, I))
// The white noises n_g, n_a of one sample have standard deviation density / sqrt(dt)
// (ImuNoise's discretisation helpers). Header-only: Eigen and model/imu_noise.hpp only.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include "model/imu_noise.hpp"

namespace legkit::model {

// World gravity, z up (the kit's convention).
inline Eigen::Vector3d gravity() {
  return {0.0, 0.0, -9.81};
}

// The two slowly varying IMU biases, body frame.
struct ImuBias {
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();  // gyro bias [rad/s]
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();  // accelerometer bias [m/s^2]
};

// One IMU sample, body frame.
struct ImuReading {
  Eigen::Vector3d w_m = Eigen::Vector3d::Zero();  // measured rate [rad/s]
  Eigen::Vector3d a_m = Eigen::Vector3d::Zero();  // measured specific force [m/s^2]
};

// The noise-free reading of a body with attitude R (body to world), world acceleration a and
// body rate w, seen through biases b: w_m = w + b_g, a_m = R^T (a - g) + b_a.
inline ImuReading idealReading(const Eigen::Matrix3d& R, const Eigen::Vector3d& a,
                               const Eigen::Vector3d& w, const ImuBias& b,
                               const Eigen::Vector3d& g = gravity()) {
  return {w + b.b_g, R.transpose() * (a - g) + b.b_a};
}

// Synthesises one reading: the ideal reading plus white noise of the discretised densities,
// then advances `bias` by one step of its random walk (the reading uses the bias before the
// step). `gen` is the caller's seeded generator (e.g. std::mt19937_64), so runs are repeatable.
// Throws std::invalid_argument for dt <= 0 or a non-finite input.
template <typename Generator>
ImuReading synthesiseReading(const ImuNoise& noise, double dt, const Eigen::Matrix3d& R,
                             const Eigen::Vector3d& a, const Eigen::Vector3d& w, ImuBias& bias,
                             Generator& gen, const Eigen::Vector3d& g = gravity()) {
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    std::ostringstream os;
    os << "synthesiseReading: sample period dt must be positive and finite, got " << dt;
    throw std::invalid_argument(os.str());
  }
  if (!R.allFinite() || !a.allFinite() || !w.allFinite() || !bias.b_g.allFinite() ||
      !bias.b_a.allFinite() || !g.allFinite()) {
    throw std::invalid_argument("synthesiseReading: R, a, w, biases and g must be finite");
  }
  std::normal_distribution<double> unit(0.0, 1.0);
  const auto draw = [&]() { return Eigen::Vector3d(unit(gen), unit(gen), unit(gen)); };

  ImuReading m = idealReading(R, a, w, bias, g);
  m.w_m += noise.gyroSampleSigma(dt) * draw();        // n_g
  m.a_m += noise.accelSampleSigma(dt) * draw();       // n_a
  bias.b_g += noise.gyroBiasStepSigma(dt) * draw();   // b_g,k+1 = b_g,k + n_bg sqrt(dt)
  bias.b_a += noise.accelBiasStepSigma(dt) * draw();  // b_a,k+1 = b_a,k + n_ba sqrt(dt)
  return m;
}

}  // namespace legkit::model
