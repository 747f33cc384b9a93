// The attitude source of the linear Kalman filter (section 57.4): a complementary filter on SO(3)
// in the style of Mahony, Hamel and Pflimlin (2008), with gyro-bias estimation.
//
// The linear KF keeps attitude out of its state, so something else has to supply R_hat. The
// gyro alone integrates well over short times but drifts; the accelerometer alone knows "up"
// (when the body is not accelerating much) but is noisy. A complementary filter blends the two:
// it integrates the gyro and steers the result slowly toward the accelerometer's gravity
// direction.
//
//   prediction   R_{k+1} = R_k Exp((w_m - b_g + k_P c e) dt)                (gyro + correction)
//   bias         b_g,k+1 = b_g,k - k_I c e dt                                 (integral action)
//   error        e = a_hat x u_hat,  a_hat = a_m / |a_m|  (measured up, body frame),
//                                    u_hat = R_k^T e_z    (predicted up, body frame)
//   trust        c = max(0, 1 - | |a_m| / g - 1 | / accel_tolerance)
//
// e is the rotation (body frame) that would turn the predicted up direction onto the measured
// one; k_P sets the bandwidth of the tilt correction (frequencies below k_P come from the
// accelerometer, above from the gyro) and k_I makes the loop integrate away a constant gyro bias.
// When |a_m| is far from g the body is accelerating and a_m is not a clean gravity reading, so the
// gains are scaled down by c (to zero beyond the tolerance). Gravity fixes roll and pitch only:
// yaw and the vertical gyro bias are not corrected (their error grows), which is one of the
// reasons the chapter later puts attitude into the filter (57.5).
//
// Uncertainty. A complementary filter is not a Kalman filter, but its error obeys a linear
// equation all the same, which the filter propagates so that the linear KF can account for the
// attitude error it is given. With the world-frame error R = Exp(theta) R_hat and the bias error
// db = b_g - b_g_hat, to first order (Pi = I - e_z e_z^T keeps the horizontal part):
//   e             = R_hat^T Pi theta + (direction noise of a_hat)
//   d(theta)/dt   = -k_P c Pi theta - R_hat db - R_hat n_g - k_P c R_hat n_e
//   d(db)/dt      =  k_I c R_hat^T Pi theta + k_I c n_e + n_bg
// where n_g is the gyro's white noise, n_bg its bias random walk and n_e the direction noise of
// the accelerometer (density sigma_a / |a_m| across the measured direction). The 6 x 6 covariance
// of (theta, db) is propagated with the first-order transition I + A dt of this equation. The
// robot's own horizontal accelerations also tilt a_hat; that error is not white and not in the
// model (the trust factor and a small k_P keep it small).
#pragma once

#include <Eigen/Core>

#include "lie/so3.hpp"
#include "model/imu_model.hpp"
#include "model/imu_noise.hpp"

namespace legkit::linear_kf {

struct AttitudeFilterParams {
  // Tilt-correction bandwidth [rad/s]. About sigma_g / (sigma_a / g), the crossover at which the
  // gyro's integrated noise and the accelerometer's direction noise are equal (~1 for Go2).
  double k_P = 1.0;
  double k_I = 0.05;             // integral (gyro-bias) gain [1/s^2]
  double accel_tolerance = 0.5;  // trust reaches zero when | |a_m|/g - 1 | reaches this [-]
  model::ImuNoise imu = model::ImuNoise::go2();  // densities for the error covariance
  double gravity_norm = 9.81;                    // |g| [m/s^2]
  // Prior standard deviations at reset (per axis).
  double sigma_tilt = 0.005;       // roll, pitch [rad]
  double sigma_yaw = 0.005;        // [rad]
  double sigma_gyro_bias = 0.002;  // [rad/s]
};

class AttitudeFilter {
 public:
  // Throws std::invalid_argument for a negative gain, density or prior, or a non-positive
  // tolerance or gravity norm.
  explicit AttitudeFilter(const AttitudeFilterParams& params = {});

  // Starts from R0 and bias b_g0, with the covariance of the Params priors.
  void reset(const lie::SO3d& R0, const Eigen::Vector3d& b_g0 = Eigen::Vector3d::Zero());

  // One step over dt > 0 with the IMU sample u held constant (the equations above). a_w is the
  // body's own world-frame acceleration when another source knows it (zero: assume none); the
  // gravity reading is then a_m - R_hat^T a_w instead of a_m. The caller checks its input (the
  // linear KF does); dt = 0 leaves the filter unchanged.
  void propagate(const model::ImuReading& u, double dt,
                 const Eigen::Vector3d& a_w = Eigen::Vector3d::Zero());

  // The trust factor c for a gravity reading s (a_m, or a_m - R_hat^T a_w), 0..1.
  double trust(const Eigen::Vector3d& s) const;

  const lie::SO3d& R() const { return R_; }
  const Eigen::Vector3d& b_g() const { return b_g_; }
  // Covariance of (theta, db), theta in the world frame: R = Exp(theta) R_hat.
  const Eigen::Matrix<double, 6, 6>& P() const { return P_; }
  // Its attitude block (3 x 3, world frame).
  Eigen::Matrix3d attitudeCovariance() const { return P_.topLeftCorner<3, 3>(); }
  const AttitudeFilterParams& params() const { return params_; }

 private:
  AttitudeFilterParams params_;
  lie::SO3d R_;
  Eigen::Vector3d b_g_ = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 6, 6> P_ = Eigen::Matrix<double, 6, 6>::Identity();
  int steps_since_normalisation_ = 0;
};

}  // namespace legkit::linear_kf
