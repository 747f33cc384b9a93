#include "estimation/linear_kf/attitude_filter.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace legkit::linear_kf {
namespace {

// Renormalise R every this many steps: each Exp product adds rounding of order 1e-16.
constexpr int kNormalisationPeriod = 256;

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("AttitudeFilter: ") + what);
}

}  // namespace

AttitudeFilter::AttitudeFilter(const AttitudeFilterParams& params) : params_(params) {
  const AttitudeFilterParams& p = params;
  require(p.k_P >= 0.0 && p.k_I >= 0.0, "gains k_P and k_I must be non-negative");
  require(p.accel_tolerance > 0.0, "accel_tolerance must be positive");
  require(p.gravity_norm > 0.0 && std::isfinite(p.gravity_norm), "gravity_norm must be positive");
  require(p.imu.gyro_noise_density >= 0.0 && p.imu.accel_noise_density >= 0.0 &&
              p.imu.gyro_bias_random_walk >= 0.0,
          "IMU noise densities must be non-negative");
  require(p.sigma_tilt >= 0.0 && p.sigma_yaw >= 0.0 && p.sigma_gyro_bias >= 0.0,
          "prior sigmas must be non-negative");
  reset(lie::SO3d());
}

void AttitudeFilter::reset(const lie::SO3d& R0, const Eigen::Vector3d& b_g0) {
  R_ = R0;
  b_g_ = b_g0;
  P_.setZero();
  P_.diagonal() << params_.sigma_tilt * params_.sigma_tilt, params_.sigma_tilt * params_.sigma_tilt,
      params_.sigma_yaw * params_.sigma_yaw,
      Eigen::Vector3d::Constant(params_.sigma_gyro_bias * params_.sigma_gyro_bias);
  steps_since_normalisation_ = 0;
}

double AttitudeFilter::trust(const Eigen::Vector3d& s) const {
  // c = max(0, 1 - | |s|/g - 1 | / tolerance)
  const double deviation = std::abs(s.norm() / params_.gravity_norm - 1.0);
  return std::max(0.0, 1.0 - deviation / params_.accel_tolerance);
}

void AttitudeFilter::propagate(const model::ImuReading& u, double dt, const Eigen::Vector3d& a_w) {
  if (!(dt > 0.0)) return;
  const Eigen::Matrix3d& R = R_.matrix();
  const Eigen::Vector3d s = u.a_m - R.transpose() * a_w;  // gravity reading
  const double c = trust(s);
  const double a_norm = s.norm();
  const Eigen::Vector3d a_hat = c > 0.0 ? Eigen::Vector3d(s / a_norm) : Eigen::Vector3d::Zero();
  const Eigen::Vector3d u_hat = R.row(2).transpose();  // R^T e_z, predicted up (body)
  const Eigen::Vector3d e = a_hat.cross(u_hat);        // e = a_hat x u_hat
  const double kPc = params_.k_P * c, kIc = params_.k_I * c;

  // Covariance of (theta, db) with Phi = I + A dt (file comment), before R and b_g move.
  const Eigen::Matrix3d Pi = Eigen::Vector3d(1.0, 1.0, 0.0).asDiagonal();  // I - e_z e_z^T
  Eigen::Matrix<double, 6, 6> Phi = Eigen::Matrix<double, 6, 6>::Identity();
  Phi.topLeftCorner<3, 3>() -= kPc * dt * Pi;  // d(theta)/dt = -k_P c Pi theta ...
  Phi.topRightCorner<3, 3>() = -R * dt;        //               - R_hat db
  Phi.bottomLeftCorner<3, 3>() = kIc * dt * R.transpose() * Pi;  // d(db)/dt = k_I c R^T Pi theta
  const double sg2 = params_.imu.gyro_noise_density * params_.imu.gyro_noise_density;
  const double sbg2 = params_.imu.gyro_bias_random_walk * params_.imu.gyro_bias_random_walk;
  Eigen::Matrix<double, 6, 6> Q = Eigen::Matrix<double, 6, 6>::Zero();
  Q.topLeftCorner<3, 3>().diagonal().setConstant(sg2 * dt);       // R n_g, isotropic
  Q.bottomRightCorner<3, 3>().diagonal().setConstant(sbg2 * dt);  // n_bg
  if (c > 0.0) {
    // Direction noise n_e of a_hat, across the measured direction, entering through
    // G = [-k_P c R; k_I c I].
    const double se = params_.imu.accel_noise_density / a_norm;
    const Eigen::Matrix3d Pe =
        se * se * dt * (Eigen::Matrix3d::Identity() - a_hat * a_hat.transpose());
    Eigen::Matrix<double, 6, 3> G;
    G.topRows<3>() = -kPc * R;
    G.bottomRows<3>() = kIc * Eigen::Matrix3d::Identity();
    Q.noalias() += G * Pe * G.transpose();
  }
  const Eigen::Matrix<double, 6, 6> P = Phi * P_ * Phi.transpose() + Q;
  P_ = 0.5 * (P + P.transpose());

  // R_{k+1} = R_k Exp((w_m - b_g + k_P c e) dt),  b_g,k+1 = b_g,k - k_I c e dt
  R_ = R_ * lie::SO3d::Exp((u.w_m - b_g_ + kPc * e) * dt);
  b_g_ -= kIc * e * dt;
  if (++steps_since_normalisation_ == kNormalisationPeriod) {
    R_ = lie::SO3d::fromQuaternion(R_.quaternion());
    steps_since_normalisation_ = 0;
  }
}

}  // namespace legkit::linear_kf
