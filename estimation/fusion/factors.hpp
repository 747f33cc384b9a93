// The fixed-lag smoother's factors (section 57.8): Ceres cost functions with analytic Jacobians,
// each residual whitened by the square-root information of its own covariance, r = S e with
// S^T S = Sigma^-1 (S = L^-1 for the Cholesky factor Sigma = L L^T).
//
// Parameter blocks follow fusion::Keyframe: a rotation R_WB is 9 doubles (column-major), to be
// moved by lie::ceres::SO3Manifold, R <- R Exp(delta); the other blocks are Euclidean. Each factor
// derives its Jacobians in the tangent delta (J_t) and hands Ceres the ambient ones through
// ambientJacobian. Ceres headers stay out of the filters' hot paths: only the smoother includes
// this file.
#pragma once

#include <ceres/sized_cost_function.h>
#include <Eigen/Core>

#include "estimation/fusion/leg_preintegration.hpp"
#include "estimation/fusion/pose_measurement.hpp"
#include "estimation/imu/preintegration.hpp"
#include "lie/ceres/manifolds.hpp"

namespace legkit::fusion {

// Tangent -> ambient Jacobian of a 9-number rotation block: J_a = J_t P(R)^T / 2, with
// P(R) = d vec(R Exp(delta)) / d delta at 0, SO3Manifold's PlusJacobian. P^T P = 2 I for a rotation
// matrix, so J_a P = J_t exactly: Ceres, which multiplies by P, sees the tangent Jacobian.
template <typename Derived>
Eigen::Matrix<double, Derived::RowsAtCompileTime, 9, Eigen::RowMajor> ambientJacobian(
    const Eigen::MatrixBase<Derived>& J_t, const Eigen::Matrix3d& R) {
  static_assert(Derived::ColsAtCompileTime == 3, "a rotation's tangent Jacobian has 3 columns");
  return 0.5 * J_t * lie::ceres::SO3Manifold::plusJacobian(R).transpose();
}

// IMU preintegration factor (Forster et al. 2017, eq. 45), keyframes i and j, the increments
// corrected to the bias b_i = b^0 + db by the preintegrator's Jacobians (eq. 44):
//   r_phi = Log( (dR Exp(J_R_bg db_g))^T R_i^T R_j )
//   r_v   = R_i^T (v_j - v_i - g dt_ij) - (dv + J_v_bg db_g + J_v_ba db_a)
//   r_p   = R_i^T (p_j - p_i - v_i dt_ij - g dt_ij^2 / 2) - (dp + J_p_bg db_g + J_p_ba db_a)
// whitened by the preintegrated covariance of (dphi, dv, dp) (dR_true = dR Exp(dphi)).
// Blocks: R_i 9, v_i 3, p_i 3, R_j 9, v_j 3, p_j 3, b_g_i 3, b_a_i 3.
// Throws std::invalid_argument if the covariance is not positive definite (no sample, or a
// noiseless IMU model) or g is not finite.
class ImuFactor : public ceres::SizedCostFunction<9, 9, 3, 3, 9, 3, 3, 3, 3> {
 public:
  ImuFactor(const imu::Preintegrator& pim, const Eigen::Vector3d& g);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // S, with S^T S = covariance^-1.
  const imu::Matrix9d& sqrtInformation() const { return S_; }

 private:
  imu::Preintegrator pim_;
  Eigen::Vector3d g_;
  imu::Matrix9d S_;
};

// Leg-odometry preintegration factor (VILENS: Wisth et al. 2023, the preintegrated velocity
// factor; here written on positions), keyframes i and j, with the increment corrected to the
// velocity bias b_v and gyro bias b_g of keyframe i (LegPreintegrator::corrected):
//   r = R_i^T (p_j - p_i) - (dp + J_p_bv db_v + J_p_bg db_g)
// whitened by the preintegrated covariance of dp.
// Blocks: R_i 9, p_i 3, p_j 3, b_v_i 3, b_g_i 3.
// Throws std::invalid_argument if the covariance is not positive definite (e.g. no sample).
class LegOdometryFactor : public ceres::SizedCostFunction<3, 9, 3, 3, 3, 3> {
 public:
  explicit LegOdometryFactor(const LegPreintegrator& lpi);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  const Eigen::Matrix3d& sqrtInformation() const { return S_; }

 private:
  LegPreintegrator lpi_;
  Eigen::Matrix3d S_;
};

// Exteroceptive pose factor (section 57.8), in PoseMeasurement's convention
// R_meas = Exp(dtheta) R, p_meas = p + dp:
//   r = ( Log(R_meas R^T), p_meas - p )
// whitened by z.cov. The smoother attaches it to the keyframe at the pose's stamp z.t, which is
// how the latency is absorbed. Blocks: R 9, p 3.
// Throws std::invalid_argument for an invalid pose, a non-finite pose, or a covariance that is
// not symmetric positive definite.
class PoseFactor : public ceres::SizedCostFunction<6, 9, 3> {
 public:
  explicit PoseFactor(const PoseMeasurement& z);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  const Matrix6d& sqrtInformation() const { return S_; }

 private:
  Eigen::Matrix3d R_meas_;
  Eigen::Vector3d p_meas_;
  Matrix6d S_;
};

// Random walk of a bias between keyframes i and j, dt apart, b_j = b_i + sigma_walk w,
// w ~ N(0, dt I) (sigma_walk the continuous density, e.g. ImuNoise::gyro_bias_random_walk):
//   r = (b_j - b_i) / (sigma_walk sqrt(dt)).
// Blocks: b_i 3, b_j 3. Throws std::invalid_argument unless sigma_walk > 0 and dt > 0, finite.
class BiasWalkFactor : public ceres::SizedCostFunction<3, 3, 3> {
 public:
  BiasWalkFactor(double sigma_walk, double dt);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  double inv_sigma_;  // 1 / (sigma_walk sqrt(dt))
};

}  // namespace legkit::fusion
