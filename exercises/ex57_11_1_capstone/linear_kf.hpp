// Capstone 57.11.1, piece 1: the 18-state linear Kalman filter of section 57.4.
//   x = [p, v, d_FL, d_FR, d_RL, d_RR]   base position, base velocity, the four feet (world frame)
#pragma once

#include <Eigen/Core>
#include <array>

namespace ex57_11 {

constexpr int kFeet = 4;
constexpr int kStates = 6 + 3 * kFeet;  // 18
using Vector18 = Eigen::Matrix<double, kStates, 1>;
using Matrix18 = Eigen::Matrix<double, kStates, kStates>;
using Matrix3x18 = Eigen::Matrix<double, 3, kStates>;
using Stance = std::array<bool, kFeet>;  // true: the foot is on the ground

struct KfNoise {
  double accel_density = 0.04;         // sigma_a, accelerometer white noise [m/s^2/sqrt(Hz)]
  double foot_stance_density = 0.001;  // sigma_d of a stance foot's random walk [m/sqrt(s)]
  double foot_swing_density = 10.0;    // sigma_d of a swing foot [m/sqrt(s)]
  double foot_position_sigma = 0.01;   // R of a foot measurement, per axis [m]
  double velocity_sigma = 0.05;        // R of the legs' fused velocity, per axis [m/s]
};

class LinearKf {
 public:
  explicit LinearKf(const KfNoise& noise = {});

  void reset(const Vector18& x0, const Matrix18& P0);

  // Prediction over dt > 0 with the world acceleration a_w held (eq. x+ = F x + B u):
  //   p += v dt + a_w dt^2 / 2,  v += a_w dt,  feet unchanged;
  //   P = F P F^T + Q,  Q = B (sigma_a^2 / dt) B^T on (p, v) with B = [dt^2/2 I; dt I]
  //   plus sigma_d^2 dt I on each foot (the stance or the swing density by `stance`).
  void predict(double dt, const Eigen::Vector3d& a_w, const Stance& stance);

  // One measurement z = H x + n, n ~ N(0, R), in Joseph form:
  //   S = H P H^T + R, K = P H^T S^-1, x += K (z - H x),
  //   P = (I - K H) P (I - K H)^T + K R K^T.
  void update(const Eigen::Vector3d& z, const Matrix3x18& H, const Eigen::Matrix3d& R);

  // A stance foot i seen by the legs: z = R_hat r_i = d_i - p (H = [-I 0 .. I at d_i ..]),
  // R = foot_position_sigma^2 I.
  void updateFoot(int i, const Eigen::Vector3d& z);
  // The legs' fused base velocity: z = v (H = [0 I 0 ...]), R = velocity_sigma^2 I.
  void updateVelocity(const Eigen::Vector3d& v);

  const Vector18& x() const { return x_; }
  const Matrix18& P() const { return P_; }

 private:
  KfNoise noise_;
  Vector18 x_ = Vector18::Zero();
  Matrix18 P_ = Matrix18::Identity();
};

}  // namespace ex57_11
