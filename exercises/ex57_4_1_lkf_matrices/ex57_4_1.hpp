// Exercise 57.4.1: the matrices of the linear Kalman filter of section 57.4, written out.
#pragma once

#include <Eigen/Core>
#include <array>

namespace ex57_4_1 {

// State x = [p, v, d_FL, d_FR, d_RL, d_RR] (18 numbers, world frame).
constexpr int kDim = 18;
using Matrix18 = Eigen::Matrix<double, kDim, kDim>;
using Stance = std::array<bool, 4>;  // FL FR RL RR, true: in stance

// Continuous-time noise densities.
struct Densities {
  double accel = 0.04;         // sigma_a, accelerometer white noise [m/s^2/sqrt(Hz)]
  double foot_stance = 0.001;  // sigma_d of a stance foot's random walk [m/sqrt(s)]
  double foot_swing = 10.0;    // sigma_d of a swing foot's random walk [m/sqrt(s)]
};

// x+ = F x + B u, u the world acceleration held over dt.
Matrix18 F(double dt);
Eigen::Matrix<double, kDim, 3> B(double dt);
// Q over one step: the accelerometer noise as a sampled white noise held over dt (covariance
// sigma_a^2 / dt per axis) entering through B, and each foot's random walk, sigma_d^2 dt per
// axis with the stance or swing density.
Matrix18 Q(double dt, const Stance& stance, const Densities& densities);
// The stacked measurement matrix of the stance feet, 3 rows per stance foot in the order
// FL, FR, RL, RR: foot i measures z_i = d_i - p.
Eigen::MatrixXd H(const Stance& stance);
// The stacked measurement noise of the stance feet, same order. Every foot's measurement carries
// the same attitude error theta (world frame, R = Exp(theta) R_hat, covariance Sigma_theta), so
// R is NOT block-diagonal: with z_i = R_hat r_i (r_i the body-frame foot position, C_i its
// covariance), block (i, j) is
//   R_ij = delta_ij R_hat C_i R_hat^T + [z_i]_x Sigma_theta [z_j]_x^T.
Eigen::MatrixXd R(const Stance& stance, const Eigen::Matrix3d& R_hat,
                  const std::array<Eigen::Vector3d, 4>& r, const std::array<Eigen::Matrix3d, 4>& C,
                  const Eigen::Matrix3d& Sigma_theta);

}  // namespace ex57_4_1
