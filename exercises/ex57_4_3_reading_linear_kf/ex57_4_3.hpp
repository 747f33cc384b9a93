// Exercise 57.4.3: reading the kit's linear KF (estimation/linear_kf/linear_kf.cpp). Each function
// below is one of its non-obvious choices, to be re-derived and written by you.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "model/contact_measurement.hpp"

namespace ex57_4_3 {

// State x = [p, v, d_FL, d_FR, d_RL, d_RR] (18 numbers).
using Matrix18 = Eigen::Matrix<double, 18, 18>;
using Matrix18x3 = Eigen::Matrix<double, 18, 3>;

// 1. The accelerometer's process noise on one axis of (p, v), the 2 x 2 block the kit adds to P
//    per step for a white-noise density sigma_a sampled at dt and held over the step.
Eigen::Matrix2d navigationNoisePerAxis(double dt, double accel_density);

// 2. F P F^T for the filter's F (identity, dt I on (p, v)), computed with block operations on P
//    (the kit never forms F). The result must be exactly symmetric when P is.
Matrix18 predictCovariance(const Matrix18& P, double dt);

// 3. The Joseph update (I - K H) P (I - K H)^T + K Rn K^T for the measurement of foot i
//    (H = [-I 0 ... I at d_i ... 0]) and ANY gain K, computed as the kit does it: with
//    N = P H^T and S = H N + Rn, as P + K V^T + V K^T, V = K S / 2 - N.
Matrix18 josephUpdate(const Matrix18& P, const Matrix18x3& K, int foot, const Eigen::Matrix3d& Rn);

// 4. The leg-odometry velocity measurement: the mean of the stance feet's base velocities
//    v_i = -R (w_b x r_i + r_dot_i), computed as the kit does, as the velocity of one virtual foot
//    at the centroid of the stance feet. Every contact carries v_body (r_dot_i).
Eigen::Vector3d centroidVelocity(const Eigen::Matrix3d& R, const Eigen::Vector3d& w_b,
                                 const std::vector<legkit::ContactMeasurement>& stance);

}  // namespace ex57_4_3
