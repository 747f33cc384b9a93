// Leg-odometry preintegration between two keyframes i and j (section 57.8; VILENS, Wisth et al.
// 2023): the body-frame base velocity the stance legs measure at each IMU sample, v_k, rotated
// into the frame of keyframe i by the gyro and summed into a displacement,
//   dp_ij = sum_k dR_ik Gamma_1(w_k dt_k) (v_k - b_v) dt_k,   dR_i,k+1 = dR_ik Exp(w_k dt_k),
// with w_k = w_m,k - b_g the bias-corrected rate. Gamma_1 ~ I gives the chapter's
// sum dR_ik (v_k - b_v) dt; keeping it makes each step exact for a rate and a body velocity
// held over the sample (as imu::Preintegrator keeps its Gammas). Like IMU preintegration, the
// increment depends on neither keyframe's state, so the smoother moves R_i, p_i, p_j freely:
//   R_i^T (p_j - p_i) = dp_ij + noise.
//
// Biases: b_v is VILENS's velocity bias (body frame, it absorbs leg-length error and foot roll);
// dp is linear in it, so J_p_bv makes the correction exact. The gyro bias b_g enters through the
// rotations dR_ik; J_p_bg corrects it to first order. Both are kept so that the smoother's gyro
// bias moves the leg increment and the IMU increments consistently (at 0.01 rad/s and 1 m/s over
// 0.1 s, b_g shifts dp by about 5e-5 m, a tenth of a typical sigma of dp).
//
// Covariance: the error state (dphi, dp), dR_true = dR Exp(dphi), dp_true = dp + ddp, driven by
// the gyro's white noise (ImuNoise::gyro_noise_density, sigma_g^2/dt per sample) and the legs'
// per-sample velocity covariance Sigma_v,k (white, independent between samples: correlated leg
// errors are what b_v is for). Sigma_v is one sample's covariance: a continuous density q
// [m/s/sqrt(Hz)] gives Sigma_v = q^2/dt, and then dp's covariance does not depend on the rate.
// covariance() is the dp block; the correlation of dphi with the IMU factor's rotation is not
// carried (the two factors are treated as independent).
//
// Fixed-size members only: integrate() does not allocate.
#pragma once

#include <Eigen/Core>

#include "lie/so3.hpp"
#include "model/imu_noise.hpp"

namespace legkit::fusion {

class LegPreintegrator {
 public:
  // An empty interval, linearised at gyro bias b_g0 and velocity bias b_v0; the rotation's noise
  // from noise.gyro_noise_density. Throws std::invalid_argument for a non-finite bias.
  explicit LegPreintegrator(const Eigen::Vector3d& b_g0 = Eigen::Vector3d::Zero(),
                            const Eigen::Vector3d& b_v0 = Eigen::Vector3d::Zero(),
                            const model::ImuNoise& noise = model::ImuNoise::go2());

  // Adds one sample held over dt: gyro reading w_m [rad/s], the legs' body-frame base velocity
  // v [m/s] with its covariance Sigma_v [m^2/s^2]. Throws std::invalid_argument for dt <= 0, a
  // non-finite value, or a Sigma_v that is not symmetric with a non-negative diagonal (the
  // preintegrator is left unchanged).
  void integrate(const Eigen::Vector3d& w_m, const Eigen::Vector3d& v,
                 const Eigen::Matrix3d& Sigma_v, double dt);

  double dt_ij() const { return dt_ij_; }
  const lie::SO3d& dR() const { return dR_; }                      // dR_ij at b_g0
  const Eigen::Vector3d& dp() const { return dp_; }                // dp_ij at (b_g0, b_v0)
  const Eigen::Matrix3d& covariance() const { return Sigma_dp_; }  // of dp [m^2]
  const Eigen::Vector3d& linearisationGyroBias() const { return b_g0_; }
  const Eigen::Vector3d& linearisationVelocityBias() const { return b_v0_; }

  // d(dp)/d(b_v) (exact: dp is linear in b_v) and d(dp)/d(b_g) at b_g0.
  const Eigen::Matrix3d& J_p_bv() const { return J_p_bv_; }
  const Eigen::Matrix3d& J_p_bg() const { return J_p_bg_; }

  // dp for biases (b_v, b_g) without re-integrating: dp + J_p_bv db_v + J_p_bg db_g.
  Eigen::Vector3d corrected(const Eigen::Vector3d& b_v, const Eigen::Vector3d& b_g) const {
    return dp_ + J_p_bv_ * (b_v - b_v0_) + J_p_bg_ * (b_g - b_g0_);
  }

 private:
  using Matrix6d = Eigen::Matrix<double, 6, 6>;

  Eigen::Vector3d b_g0_, b_v0_;
  model::ImuNoise noise_;
  double dt_ij_ = 0.0;
  lie::SO3d dR_;
  Eigen::Vector3d dp_ = Eigen::Vector3d::Zero();
  Matrix6d Sigma_ = Matrix6d::Zero();  // of (dphi, dp)
  Eigen::Matrix3d Sigma_dp_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d J_R_bg_ = Eigen::Matrix3d::Zero();  // d(dphi)/d(b_g), as imu::Preintegrator's
  Eigen::Matrix3d J_p_bv_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d J_p_bg_ = Eigen::Matrix3d::Zero();
};

}  // namespace legkit::fusion
