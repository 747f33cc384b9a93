// Between the base frame B (the robot's, in which legs and ground truth are given) and the IMU
// frame I (the estimators' body), for an IMU mounted at T_BI = (R_BI, p_BI)
// (model/imu_extrinsic.hpp).
//
// Into the IMU frame (the front end, estimation/log_frontend.hpp), per foot:
//   p_I = R_BI^T (p_B - p_BI),   v_I = R_BI^T v_B,   Cov_I = R_BI^T Cov_B R_BI
// (v is the foot's velocity relative to the body: both frames are fixed to the same rigid body, so
// it only turns).
//
// Back to the base (the evaluation, eval/runner.hpp): with r_IB = -R_BI^T p_BI the base origin
// seen from the IMU and w the IMU-frame angular rate,
//   R_WB = R_WI R_BI^T,   p_WB = p_WI + R_WI r_IB,   v_WB = v_WI + R_WI (w x r_IB).
// In BaseCovariance's convention (R = Exp(dtheta) R_hat, world-frame errors) the attitude error is
// the same for both frames and, to first order,
//   dv_B = dv_I - [R_WI (w x r_IB)]_x dtheta,   dp_B = dp_I - [R_WI r_IB]_x dtheta,
// so P_B = J P_I J^T with that Jacobian J (the rate w is taken as exact).
//
// The accelerometer's lever arm needs no term in the filters: the accelerometer measures the
// specific force of the IMU's own point, and the filters propagate exactly that point (their
// position and velocity are the IMU's), so the centripetal and angular-acceleration terms
// dw x r + w x (w x r) are never subtracted; they appear only when the base's motion is rebuilt
// from the IMU's, above, and in imuReadingAt() below, which makes an offset IMU's readings.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "estimation/estimate.hpp"
#include "estimation/estimator.hpp"
#include "lie/so3.hpp"
#include "model/imu_extrinsic.hpp"
#include "model/imu_model.hpp"

namespace legkit {

// R_BI^T (p_B - p_BI): a point of the base frame seen from the IMU [m].
inline Eigen::Vector3d pointInImu(const model::ImuExtrinsic& e, const Eigen::Vector3d& p_B) {
  return e.q_BI.conjugate() * (p_B - e.p_BI);
}

// R_BI^T x_B: a free vector (a foot's velocity relative to the body, a rate) seen from the IMU.
inline Eigen::Vector3d vectorInImu(const model::ImuExtrinsic& e, const Eigen::Vector3d& x_B) {
  return e.q_BI.conjugate() * x_B;
}

// R_BI^T Cov_B R_BI: a covariance of a base-frame point or vector seen from the IMU.
inline Eigen::Matrix3d covarianceInImu(const model::ImuExtrinsic& e, const Eigen::Matrix3d& C_B) {
  const Eigen::Matrix3d R_BI = e.q_BI.toRotationMatrix();
  return R_BI.transpose() * C_B * R_BI;
}

// r_IB = -R_BI^T p_BI: the base origin seen from the IMU [m].
inline Eigen::Vector3d baseOriginInImu(const model::ImuExtrinsic& e) {
  return -(e.q_BI.conjugate() * e.p_BI);
}

// The base's state from the IMU's state x_I (R_WI, IMU point's world velocity and position) and
// the IMU-frame rate w_I (file comment).
inline EstimateSample baseFromImu(const model::ImuExtrinsic& e, const EstimateSample& x_I,
                                  const Eigen::Vector3d& w_I) {
  const Eigen::Vector3d r_IB = baseOriginInImu(e);
  EstimateSample x_B;
  x_B.t = x_I.t;
  x_B.q = (x_I.q * e.q_BI.conjugate()).normalized();  // R_WB = R_WI R_BI^T
  x_B.v = x_I.v + x_I.q * w_I.cross(r_IB);            // v_WB = v_WI + R_WI (w x r_IB)
  x_B.p = x_I.p + x_I.q * r_IB;                       // p_WB = p_WI + R_WI r_IB
  return x_B;
}

// The IMU's state from the base's state x_B and the base-frame rate w_B (the inverse of
// baseFromImu): R_WI = R_WB R_BI, p_WI = p_WB + R_WB p_BI, v_WI = v_WB + R_WB (w_B x p_BI).
inline EstimateSample imuFromBase(const model::ImuExtrinsic& e, const EstimateSample& x_B,
                                  const Eigen::Vector3d& w_B) {
  EstimateSample x_I;
  x_I.t = x_B.t;
  x_I.q = (x_B.q * e.q_BI).normalized();
  x_I.v = x_B.v + x_B.q * w_B.cross(e.p_BI);
  x_I.p = x_B.p + x_B.q * e.p_BI;
  return x_I;
}

// The covariance of baseFromImu(e, x_I, w_I) from the IMU state's, P_B = J P_I J^T (file
// comment). Without attitude (has_attitude false) the (dv, dp) block is passed on unchanged: the
// attitude is an input there and its error is not in P.
inline BaseCovariance baseCovarianceFromImu(const model::ImuExtrinsic& e, const EstimateSample& x_I,
                                            const Eigen::Vector3d& w_I, const BaseCovariance& P_I) {
  if (!P_I.has_attitude) return P_I;
  const Eigen::Vector3d r_IB = baseOriginInImu(e);
  Eigen::Matrix<double, 9, 9> J = Eigen::Matrix<double, 9, 9>::Identity();
  J.block<3, 3>(3, 0) = -lie::SO3d::hat(x_I.q * w_I.cross(r_IB));  // d v_B / d theta
  J.block<3, 3>(6, 0) = -lie::SO3d::hat(x_I.q * r_IB);             // d p_B / d theta
  BaseCovariance P_B = P_I;
  P_B.P = J * P_I.P * J.transpose();
  return P_B;
}

// What an IMU at T_BI measures on a base moving with base-frame rate w_B, angular acceleration
// dw_B and base-frame specific force f_B = R_WB^T (a_B - g) of the base origin, noise-free:
//   w_I = R_BI^T w_B,   a_I = R_BI^T (f_B + dw_B x p_BI + w_B x (w_B x p_BI))
// (the rigid-body acceleration of the point p_BI). For making an offset IMU's log from a base's.
inline model::ImuReading imuReadingAt(const model::ImuExtrinsic& e, const Eigen::Vector3d& w_B,
                                      const Eigen::Vector3d& dw_B, const Eigen::Vector3d& f_B) {
  const Eigen::Vector3d& r = e.p_BI;
  return {vectorInImu(e, w_B), vectorInImu(e, f_B + dw_B.cross(r) + w_B.cross(w_B.cross(r)))};
}

}  // namespace legkit
