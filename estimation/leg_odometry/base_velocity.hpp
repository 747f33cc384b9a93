// Base velocity from one stance foot (section 57.3, leg odometry).
//
// Derivation. The foot point in the world is d = p + R r, with r = B_p_f(q) its body-frame
// position. Differentiating, with R' = R [w_b]_x (w_b the body-frame angular rate the gyro
// measures) and r' = B_J(q) qdot (the foot's velocity relative to the body, in the body frame):
//     d' = v + R (w_b x r) + R B_J qdot.
// A foot that neither lifts nor slips has d' = 0, so
//     v = -R (w_b x r + B_J qdot).
// The chapter writes the middle term as w x (R r) with w = R w_b the world-frame rate; the two
// agree because R (w_b x r) = (R w_b) x (R r). Mixing the frames (a world-frame rate with a
// body-frame r, or a body-frame Jacobian with no R in front) is the classic bug; the turn-in-place
// check (pure rotation must give v = 0 from every foot) catches it.
//
// Nothing here knows the robot: the caller gives r and r' (from its own kinematics or a log).
#pragma once

#include <Eigen/Core>

#include "model/contact_measurement.hpp"

namespace legkit::leg_odometry {

// v = -R (w_b x r + r_dot): world-frame base velocity from one stance foot.
//   R      attitude (body to world);       w_b   body-frame angular rate [rad/s];
//   r      body-frame foot position [m];   r_dot foot velocity relative to the body, body frame,
//                                                 B_J qdot for a jointed leg [m/s].
// Throws std::invalid_argument for non-finite input or an R that is not a rotation.
Eigen::Vector3d baseVelocityFromFoot(const Eigen::Matrix3d& R, const Eigen::Vector3d& w_b,
                                     const Eigen::Vector3d& r, const Eigen::Vector3d& r_dot);

// The same from a contact measurement; its v_body (r_dot) must be present.
Eigen::Vector3d baseVelocityFromFoot(const Eigen::Matrix3d& R, const Eigen::Vector3d& w_b,
                                     const ContactMeasurement& contact);

// Noise of the inputs of one foot's velocity, as covariances of the measured quantities.
struct FootVelocityNoise {
  Eigen::Matrix3d gyro_cov = Eigen::Matrix3d::Identity() * 1e-6;   // Cov(w_b) [rad^2/s^2]
  Eigen::Matrix3d r_dot_cov = Eigen::Matrix3d::Identity() * 1e-4;  // Cov(r_dot) [m^2/s^2]
};

// First-order covariance of v from one foot, with r_cov = Cov(r):
//   dv = -R (-[r]_x dw + [w_b]_x dr + dr_dot)
//   Cov(v) = R ([r]_x Cw [r]_x^T + [w_b]_x Cr [w_b]_x^T + Cr_dot) R^T   (inputs independent).
Eigen::Matrix3d baseVelocityCovariance(const Eigen::Matrix3d& R, const Eigen::Vector3d& w_b,
                                       const Eigen::Vector3d& r, const Eigen::Matrix3d& r_cov,
                                       const FootVelocityNoise& noise);

}  // namespace legkit::leg_odometry
