// On-manifold IMU preintegration between two keyframes i and j (Forster et al. 2015/2017,
// section 57.2). With the bias-corrected rate w_k = w_m,k - b_g^0 and specific force
// a_k = a_m,k - b_a^0 held over each sample, the increments are accumulated from
// dR = I, dv = 0, dp = 0 as
//   dR <- dR Exp(w_k dt)
//   dv <- dv + dR Gamma_1(w_k dt) a_k dt
//   dp <- dp + dv dt + dR Gamma_2(w_k dt) a_k dt^2
// (dR, dv on the right-hand sides are the values before the update). The chapter's recursion is
// the same with Gamma_1 ~ I and Gamma_2 ~ I/2; keeping the Gammas makes each step exact for
// constant input, so the keyframe constraint
//   R_j = R_i dR,  v_j = v_i + g dt_ij + R_i dv,  p_j = p_i + v_i dt_ij + g dt_ij^2/2 + R_i dp
// reproduces step-by-step dead reckoning to rounding. Neither R_i, v_i, p_i nor g enter the
// increments, which is what lets a smoother move keyframe states without re-integrating.
//
// Errors are ordered (dphi, dv, dp), with dR_true = dR Exp(dphi); their covariance is
// propagated from the continuous densities (one sample of white noise has variance
// density^2 / dt). The bias Jacobians give the first-order correction for b = b^0 + db:
//   dR(b) ~ dR Exp(J_R_bg db_g),  dv(b) ~ dv + J_v_bg db_g + J_v_ba db_a,  dp likewise.
#pragma once

#include <Eigen/Core>

#include "estimation/imu/nav_state.hpp"
#include "lie/so3.hpp"
#include "model/imu_model.hpp"
#include "model/imu_noise.hpp"

namespace legkit::imu {

using Matrix9d = Eigen::Matrix<double, 9, 9>;

// Increments (dR, dv, dp) over dt_ij, e.g. after a bias correction.
struct PreintegratedDelta {
  lie::SO3d dR;
  Eigen::Vector3d dv = Eigen::Vector3d::Zero();
  Eigen::Vector3d dp = Eigen::Vector3d::Zero();
};

class Preintegrator {
 public:
  // Starts an empty interval, linearised at bias b0, noise from the densities of `noise`.
  explicit Preintegrator(const model::ImuBias& b0 = {},
                         const model::ImuNoise& noise = model::ImuNoise::go2());

  // Adds one IMU sample held over dt. Throws std::invalid_argument for dt <= 0 or a NaN
  // reading (the preintegrator is left unchanged).
  void integrate(const model::ImuReading& m, double dt);

  double dt_ij() const { return dt_ij_; }
  const lie::SO3d& dR() const { return delta_.dR; }
  const Eigen::Vector3d& dv() const { return delta_.dv; }
  const Eigen::Vector3d& dp() const { return delta_.dp; }
  const PreintegratedDelta& delta() const { return delta_; }
  const model::ImuBias& linearisationBias() const { return b0_; }

  // 9x9 covariance of (dphi, dv, dp) from the white noise of the samples integrated so far.
  const Matrix9d& covariance() const { return Sigma_; }

  // The five bias Jacobians of the increments at b0.
  const Eigen::Matrix3d& J_R_bg() const { return J_R_bg_; }
  const Eigen::Matrix3d& J_v_bg() const { return J_v_bg_; }
  const Eigen::Matrix3d& J_v_ba() const { return J_v_ba_; }
  const Eigen::Matrix3d& J_p_bg() const { return J_p_bg_; }
  const Eigen::Matrix3d& J_p_ba() const { return J_p_ba_; }

  // First-order bias correction: the increments for bias b without re-integrating.
  PreintegratedDelta corrected(const model::ImuBias& b) const;

  // State at keyframe j from the state at i, with the increments corrected to bias b.
  NavState predict(const NavState& x_i, const model::ImuBias& b,
                   const Eigen::Vector3d& g = model::gravity()) const;

 private:
  model::ImuBias b0_;
  model::ImuNoise noise_;
  double dt_ij_ = 0.0;
  PreintegratedDelta delta_;
  Matrix9d Sigma_ = Matrix9d::Zero();
  Eigen::Matrix3d J_R_bg_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d J_v_bg_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d J_v_ba_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d J_p_bg_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d J_p_ba_ = Eigen::Matrix3d::Zero();
};

}  // namespace legkit::imu
