// Where the IMU sits on the base: its pose in the base frame, T_BI = (R_BI, p_BI).
//
// The estimators' "body" is the IMU frame: the accelerometer measures the specific force of the
// IMU's own point, so a filter that propagates that point needs no angular acceleration. The
// front end (estimation/log_frontend.hpp) moves the legs into the IMU frame (a foot at p_B in the
// base frame is at R_BI^T (p_B - p_BI) in the IMU frame, its velocity relative to the body rotates
// the same way), and the evaluation moves the estimate back to the base before comparing it with
// a base ground truth (estimation/imu_extrinsic_frames.hpp). Identity by default: base = IMU.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace legkit::model {

struct ImuExtrinsic {
  Eigen::Quaterniond q_BI = Eigen::Quaterniond::Identity();  // R_BI: IMU axes to base axes
  Eigen::Vector3d p_BI = Eigen::Vector3d::Zero();            // IMU origin in the base frame [m]

  bool isIdentity() const {
    return q_BI.coeffs() == Eigen::Quaterniond::Identity().coeffs() && p_BI.isZero(0.0);
  }
};

}  // namespace legkit::model
