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
using Matrix9 = Eigen::Matrix<double, 9, 9>;
using Matrix9x6 = Eigen::Matrix<double, 9, 6>;
using Matrix9x27 = Eigen::Matrix<double, 9, kDim>;

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

// P <- G P G^T for a G that is the identity but on the navigation rows (dtheta, dv, dp), which
// are `nav` over (dtheta, dv, dp) and `bias` over (db_g, db_a): the ESKF's Phi, the TSIF's
// -J_1^-1 J_0. Only the rows and columns (dtheta, dv, dp) change. Returns G's navigation rows
// times the P before (9 x 27), the TSIF's covariance of its two states. (lazyProduct: an inner
// dimension of 3 to 9, where Eigen's blocked GEMM spends more time packing than multiplying.)
inline Matrix9x27 transformNavigation(Matrix27& P, const Matrix9& nav, const Matrix9x6& bias) {
  Matrix9x27 M;
  M.noalias() = nav.lazyProduct(P.topRows<9>());
  M.noalias() += bias.lazyProduct(P.middleRows<6>(kBg));
  Matrix9 M_nav;
  M_nav.noalias() = M.leftCols<9>() * nav.transpose();
  M_nav.noalias() += M.middleCols<6>(kBg) * bias.transpose();
  P.topRows<9>() = M;
  P.leftCols<9>() = M.transpose();
  P.topLeftCorner<9, 9>() = 0.5 * (M_nav + M_nav.transpose());
  return M;
}

// After a step dx is injected, a local rotation error (the attitude at kTheta, or a flat foot's
// sole) is re-expressed around the new estimate: P <- G P G^T, G = I - [dphi / 2]_x on its rows.
inline void resetRotation(Matrix27& P, int at, const Eigen::Vector3d& dphi) {
  const Eigen::Matrix3d G = Eigen::Matrix3d::Identity() - lie::hat3(Eigen::Vector3d(0.5 * dphi));
  Eigen::Matrix<double, 3, kDim> rows;
  rows.noalias() = G * P.middleRows<3>(at);
  Eigen::Matrix3d P_tt;
  P_tt.noalias() = rows.middleCols<3>(at) * G.transpose();
  P.middleRows<3>(at) = rows;
  P.middleCols<3>(at) = rows.transpose();
  P.block<3, 3>(at, at) = 0.5 * (P_tt + P_tt.transpose());
}

// The (dtheta_w, dv, dp) block of P in the kit's convention (BaseCovariance): the local attitude
// error mapped to the world frame, dtheta_w = R_hat dtheta.
inline Matrix9 worldBaseBlock(const Matrix27& P, const lie::SO3d& R_hat) {
  const Eigen::Matrix3d& R = R_hat.matrix();
  Matrix9 B = P.topLeftCorner<9, 9>();
  B.topRows<3>() = (R * B.topRows<3>()).eval();
  B.leftCols<3>() = (B.leftCols<3>() * R.transpose()).eval();
  return B;
}

// Foot i touches down and is placed at its kinematics z_i (body frame, covariance cov):
// d_i = p + R z_i, and its rows of P those of dd_i = J_theta dtheta + dp + R n with
// J_theta = -R [z_i]_x: the state's uncertainty, copied, plus the measurement's.
inline void placeFoot(State& x, Matrix27& P, int i, const Eigen::Vector3d& z,
                      const Eigen::Matrix3d& cov) {
  const int d = footIndex(i);
  const Eigen::Matrix3d& R = x.R.matrix();
  x.d[i] = x.p + R * z;
  const Eigen::Matrix3d J_theta = -R * lie::hat3(z);
  Eigen::Matrix<double, 3, kDim> M;  // the new rows of P: J P over (dtheta, dp)
  M.noalias() = J_theta * P.middleRows<3>(kTheta);
  M += P.middleRows<3>(kP);
  Eigen::Matrix3d P_dd = M.middleCols<3>(kP) + R * cov * R.transpose();
  P_dd.noalias() += M.middleCols<3>(kTheta) * J_theta.transpose();
  P.middleRows<3>(d) = M;
  P.middleCols<3>(d) = M.transpose();
  P.block<3, 3>(d, d) = 0.5 * (P_dd + P_dd.transpose());
}

// Flat foot i's sole at its touchdown, measured as Z = R_BF (covariance rot_cov): R_F = R Z, and
// its rows of P those of dphi_i = Z^T dtheta - n (57.5, "Flat feet"). Returns R_F.
inline lie::SO3d placeSole(const lie::SO3d& R, Matrix27& P, int i, const Eigen::Matrix3d& Z,
                           const Eigen::Matrix3d& rot_cov) {
  const int f = rotationIndex(i);
  Eigen::Matrix<double, 3, kDim> N;
  N.noalias() = Z.transpose() * P.middleRows<3>(kTheta);
  Eigen::Matrix3d P_ff = rot_cov;
  P_ff.noalias() += N.middleCols<3>(kTheta) * Z;
  P.middleRows<3>(f) = N;
  P.middleCols<3>(f) = N.transpose();
  P.block<3, 3>(f, f) = 0.5 * (P_ff + P_ff.transpose());
  return lie::SO3d::fromQuaternion(Eigen::Quaterniond(R.matrix() * Z));
}

}  // namespace legkit::invariant::nominal
