// The state that the ESKF and the TSIF of section 57.5 both estimate, its error (tangent) vector,
// and what the two filters compute from it in the same way: the strapdown step and the stance
// foot seen from the body. Each filter's own file pair keeps what it teaches (the ESKF's Phi and
// Joseph update, the TSIF's residuals and two-state solve).
//
// State x = (R, v, p, d_1..d_4, b_g, b_a): attitude (body to world), world velocity and position,
// the four feet in the world, gyro and accelerometer biases. Error vector, 27 entries,
//   dx = (dtheta, dv, dp, dd_1..dd_4, db_g, db_a),   R = R_hat Exp(dtheta)
// (a local, body-frame attitude error; every other block additive).
//
// IMU noise contract of both filters (model::ImuNoise): a bias random walk of zero is accepted and
// means a constant bias, whose only uncertainty is the prior's (checkFilterParams,
// filter_params.hpp).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>

#include "lie/imu_dynamics.hpp"
#include "lie/so3.hpp"
#include "model/imu_model.hpp"
#include "model/imu_noise.hpp"

namespace legkit::invariant::nominal {

constexpr int kFeet = 4;                 // d_1..d_4 (quadruped: FL FR RL RR)
constexpr int kDim = 9 + 3 * kFeet + 6;  // 27: the error vector
// Offsets of the blocks in the error vector.
constexpr int kTheta = 0, kV = 3, kP = 6, kD = 9, kBg = 9 + 3 * kFeet, kBa = kBg + 3;
constexpr int footIndex(int i) {
  return kD + 3 * i;
}
// Flat feet (FilterParams::flat_feet): a humanoid's two soles, each foot with its position d_i
// and its rotation R_F,i, whose error dphi_i takes the blocks of a quadruped's feet 3 and 4.
// Structural, not tuned: two feet with rotations fill the 12 numbers of four point feet, so the
// error vector stays kDim long (a third foot is refused a slot: FootSlots).
constexpr int kFlatFeet = 2;
constexpr int rotationIndex(int i) {
  return footIndex(kFlatFeet + i);
}
// A flat foot's rotation before its first touchdown (the foot turns freely): its prior at reset
// [rad], 1 rad (57 deg) per axis saying "unknown", as foot_init_sigma's 1 m does for a foot's
// position. It is never used as information: the first touchdown places the sole from its
// measurement (R_F = R Z) and replaces its rows of P, so no result depends on it (the iCub and
// biped runs place every sole that way).
constexpr double kFootRotationPrior = 1.0;

using Vector27 = Eigen::Matrix<double, kDim, 1>;
using Matrix27 = Eigen::Matrix<double, kDim, kDim>;
using Matrix39 = Eigen::Matrix<double, 3, 9>;

struct State {
  lie::SO3d R;                                    // body to world
  Eigen::Vector3d v = Eigen::Vector3d::Zero();    // world velocity [m/s]
  Eigen::Vector3d p = Eigen::Vector3d::Zero();    // world position [m]
  std::array<Eigen::Vector3d, kFeet> d{};         // world foot positions [m]
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();  // gyro bias [rad/s]
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();  // accelerometer bias [m/s^2]

  // x (+) dx: R Exp(dtheta), the rest added (the ESKF's injection, the TSIF's Gauss-Newton step).
  State plus(const Vector27& dx) const {
    State x = *this;
    x.R = R * lie::SO3d::Exp(dx.segment<3>(kTheta));  // R = R_hat Exp(dtheta)
    x.v += dx.segment<3>(kV);
    x.p += dx.segment<3>(kP);
    for (int i = 0; i < kFeet; ++i) x.d[i] += dx.segment<3>(footIndex(i));
    x.b_g += dx.segment<3>(kBg);
    x.b_a += dx.segment<3>(kBa);
    return x;
  }
  // x (-) y: the dx with y (+) dx = x (Log(R_y^T R_x) for the attitude).
  Vector27 minus(const State& y) const {
    Vector27 dx;
    dx.segment<3>(kTheta) = R.rminus(y.R);  // Log(R_y^T R)
    dx.segment<3>(kV) = v - y.v;
    dx.segment<3>(kP) = p - y.p;
    for (int i = 0; i < kFeet; ++i) dx.segment<3>(footIndex(i)) = d[i] - y.d[i];
    dx.segment<3>(kBg) = b_g - y.b_g;
    dx.segment<3>(kBa) = b_a - y.b_a;
    return dx;
  }
};

// The strapdown step over dt with the IMU sample u held constant, w = w_m - b_g, f = a_m - b_a,
// integrated exactly for constant input (lie/imu_dynamics.hpp):
//   R+ = R Exp(w dt),  v+ = v + R Gamma_1(w dt) f dt + g dt,
//   p+ = p + v dt + R Gamma_2(w dt) f dt^2 + g dt^2 / 2,   d, b_g, b_a unchanged.
inline State propagate(const State& x, const model::ImuReading& u, double dt,
                       const Eigen::Vector3d& g = model::gravity()) {
  const Eigen::Vector3d phi = (u.w_m - x.b_g) * dt;  // rotation over dt, bias-corrected
  const Eigen::Vector3d f = u.a_m - x.b_a;           // specific force, bias-corrected
  const Eigen::Matrix3d& R = x.R.matrix();
  State next = x;
  // R+ = R Exp(phi), re-normalised through the quaternion so that rounding never accumulates.
  next.R = lie::SO3d::fromQuaternion(Eigen::Quaterniond(R * lie::SO3d::Exp(phi).matrix()));
  next.v = x.v + R * (lie::Gamma<1>(phi) * f) * dt + g * dt;
  next.p = x.p + x.v * dt + R * (lie::Gamma<2>(phi) * f) * (dt * dt) + 0.5 * g * (dt * dt);
  return next;
}

// h_i(x) = R^T (d_i - p), the stance foot i in the body frame (what the leg kinematics measure),
// and its 3 x 9 Jacobian over (dtheta, dp, dd_i), zero on every other block of the error:
// (R Exp(dtheta))^T y = R^T y + [R^T y]_x dtheta.
inline Eigen::Vector3d footInBody(const State& x, int i, Matrix39* H = nullptr) {
  const Eigen::Matrix3d Rt = x.R.matrix().transpose();
  const Eigen::Vector3d h = Rt * (x.d[i] - x.p);
  if (H) {
    H->block<3, 3>(0, 0) = lie::hat3(h);  // dtheta
    H->block<3, 3>(0, 3) = -Rt;           // dp
    H->block<3, 3>(0, 6) = Rt;            // dd_i
  }
  return h;
}

// A flat foot's sole seen from the body, h = R^T R_F (R_F = R_F,hat Exp(dphi), local), against
// its measurement Z = R_BF (57.5, "Flat feet"): r = Log(h_hat^T Z) = dphi_i - h_hat^T dtheta + n
// and its 3 x 6 Jacobian H = [-h_hat^T (dtheta), I (dphi_i)].
inline Eigen::Vector3d soleResidual(const lie::SO3d& R, const lie::SO3d& R_F,
                                    const Eigen::Matrix3d& Z, Eigen::Matrix<double, 3, 6>* H) {
  const Eigen::Matrix3d h = R.matrix().transpose() * R_F.matrix();
  *H << -h.transpose(), Eigen::Matrix3d::Identity();
  return lie::SO3d::fromQuaternion(Eigen::Quaterniond(h.transpose() * Z)).Log();
}

}  // namespace legkit::invariant::nominal
