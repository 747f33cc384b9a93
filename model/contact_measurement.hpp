// The one thing every estimator learns from a leg: where a foot is, seen from the body.
// It does not assume any particular robot: a quadruped, a biped or a user's own machine fills it
// from its own kinematics (or a log's body-frame foot columns).
#pragma once

#include <Eigen/Core>
#include <optional>

namespace legkit {

struct ContactMeasurement {
  int foot = 0;                           // foot id (quadruped: 0 FL, 1 FR, 2 RL, 3 RR)
  Eigen::Vector3d p_body;                 // foot position in the body (IMU) frame [m]
  Eigen::Matrix3d cov;                    // its 3x3 covariance [m^2]
  std::optional<Eigen::Vector3d> v_body;  // optional foot velocity relative to the body [m/s]
  // p_c, the probability that this foot is on the ground, in [0, 1] (section 57.6). The filters
  // give a stance foot the process noise density of contact::softFootNoiseDensity (eq. Q_f of
  // 57.6) between their stance and swing densities; 1 (a hard contact) leaves them unchanged.
  double probability = 1.0;
  // A flat foot's orientation, R_BF (foot frame to body frame), when the kinematics give it and
  // the settings ask for it (feet.flat; section 57.5, flat feet): Z = R_BF,true Exp(n),
  // n ~ N(0, rot_cov), a rotation error in the foot's own frame [rad^2].
  std::optional<Eigen::Matrix3d> R_body{};
  Eigen::Matrix3d rot_cov = Eigen::Matrix3d::Zero();
};

}  // namespace legkit
