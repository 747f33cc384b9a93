#include "estimation/engineering/stationary_init.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "lie/so3.hpp"

namespace legkit::engineering {

namespace {
void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("StationaryInitialiser: ") + what);
}
}  // namespace

void StationaryInitialiser::Moments::add(const Eigen::Matrix<double, 6, 1>& x) {
  n += 1.0;  // Welford
  const Eigen::Matrix<double, 6, 1> d = x - mean;
  mean += d / n;
  m2 += d.cwiseProduct(x - mean);
}

void StationaryInitialiser::Moments::merge(const Moments& o) {
  if (o.n == 0.0) return;
  const double total = n + o.n;
  const Eigen::Matrix<double, 6, 1> d = o.mean - mean;
  mean += d * (o.n / total);
  m2 += o.m2 + d.cwiseProduct(d) * (n * o.n / total);
  n = total;
}

StationaryInitialiser::StationaryInitialiser(const StationaryInitParams& params,
                                             Eigen::Vector3d gravity)
    : params_(params), gravity_(gravity) {
  require(params.duration > 0.0 && std::isfinite(params.duration),
          "duration must be positive and finite");
  require(params.gyro_std_max >= 0.0 && params.accel_std_max >= 0.0,
          "gyro_std_max and accel_std_max must be non-negative");
  require(params.max_wait >= 0.0, "max_wait must be non-negative");
  require(params.accel_bias_sigma >= 0.0 && std::isfinite(params.accel_bias_sigma),
          "accel_bias_sigma must be finite and non-negative");
  require(gravity.allFinite() && gravity.z() < 0.0 && gravity.head<2>().isZero(0.0),
          "gravity must be finite and along -z (world z up)");
  reset();
}

void StationaryInitialiser::reset() {
  blocks_.fill(Moments{});
  complete_ = next_ = 0;
  current_ = Moments{};
  block_start_ = last_t_ = first_t_ = 0.0;
  started_ = ready_ = gave_up_ = false;
  window_ = Moments{};
  std_w_.setZero();
  std_a_.setZero();
}

void StationaryInitialiser::closeBlock() {
  blocks_[next_] = current_;
  next_ = (next_ + 1) % kBlocks;
  if (complete_ < kBlocks) ++complete_;
  current_ = Moments{};
}

bool StationaryInitialiser::add(double t, const model::ImuReading& imu) {
  if (ready_ || gave_up_) return ready_;
  if (!std::isfinite(t) || (started_ && t < last_t_))
    throw std::invalid_argument("StationaryInitialiser::add: time " + std::to_string(t) +
                                " is not finite or before the previous sample");
  const double block = params_.duration / kBlocks;
  if (!started_) {
    started_ = true;
    first_t_ = block_start_ = t;
  } else if (t - last_t_ > block) {  // a gap: the window is not contiguous, start over
    complete_ = next_ = 0;
    current_ = Moments{};
    block_start_ = t;
  } else if (t - block_start_ >= block) {
    closeBlock();
    block_start_ += block * std::floor((t - block_start_) / block);
  }
  last_t_ = t;
  Eigen::Matrix<double, 6, 1> x;
  x << imu.w_m, imu.a_m;
  if (x.allFinite()) current_.add(x);  // a non-finite reading is not a still one: skipped

  if (complete_ == kBlocks) {
    Moments w, means;  // the window's samples, and its block means
    for (const Moments& b : blocks_) {
      w.merge(b);
      if (b.n > 0.0) means.add(b.mean);
    }
    const Eigen::Matrix<double, 6, 1> sd = (means.m2 / std::max(means.n - 1.0, 1.0)).cwiseSqrt();
    if ((sd.head<3>().array() < params_.gyro_std_max).all() &&
        (sd.tail<3>().array() < params_.accel_std_max).all()) {
      window_ = w;
      std_w_ = sd.head<3>();
      std_a_ = sd.tail<3>();
      ready_ = true;
      return true;
    }
  }
  if (t - first_t_ >= params_.max_wait) gave_up_ = true;
  return false;
}

InitialState StationaryInitialiser::result() const {
  return result(Eigen::Vector3d::Zero(), params_.accel_bias_sigma);
}

InitialState StationaryInitialiser::result(const Eigen::Vector3d& b_a, double sigma_b_a) const {
  if (!ready_) throw std::logic_error("StationaryInitialiser::result: no still window yet");
  require(b_a.allFinite() && sigma_b_a >= 0.0 && std::isfinite(sigma_b_a),
          "result: b_a must be finite and sigma_b_a finite and non-negative");
  const Eigen::Vector3d a = window_.mean.tail<3>() - b_a;  // R^T (-g): the body's "up" times |g|
  const double roll = std::atan2(a.y(), a.z());
  const double pitch = std::atan2(-a.x(), std::hypot(a.y(), a.z()));
  InitialState s;
  s.x.t = last_t_;
  s.x.q = Eigen::Quaterniond(Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));  // yaw 0
  s.b_g = window_.mean.head<3>();
  s.b_a = b_a;
  // Standard error of the mean horizontal specific force, and the bias not told from tilt.
  const Eigen::Vector3d var_a = window_.m2.tail<3>() / std::max(window_.n - 1.0, 1.0);
  const double s_mean = std::sqrt(var_a.head<2>().maxCoeff() / window_.n);
  s.sigma_tilt = std::hypot(s_mean, sigma_b_a) / gravity_.norm();
  if (!(s.sigma_tilt > 0.0)) s.sigma_tilt = 1e-9;  // noiseless readings and an exact bias
  return s;
}

}  // namespace legkit::engineering
