#include "estimation/invariant/tsif.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "estimation/contact/soft_contact.hpp"
#include "lie/imu_dynamics.hpp"

namespace legkit::invariant {

namespace tsif {

namespace {

using Matrix3 = Eigen::Matrix3d;
using Vector3 = Eigen::Vector3d;

}  // namespace

ImuResidual imuResidual(const State& x0, const State& x1, const model::ImuReading& u, double dt,
                        const Vector3& g) {
  const Vector3 phi = (u.w_m - x0.b_g) * dt;  // rotation over dt, bias-corrected
  const Vector3 f = u.a_m - x0.b_a;           // specific force, bias-corrected
  const lie::AngleSeries<double> c(phi.squaredNorm());
  const Matrix3 Gamma1 = lie::Gamma<1>(phi);
  const Matrix3 Gamma2 = lie::Gamma<2>(phi);
  const Matrix3& R0 = x0.R.matrix();
  const Vector3 dv = Gamma1 * f * dt;       // body-frame velocity increment
  const Vector3 dp = Gamma2 * f * dt * dt;  // body-frame position increment

  // E = Exp(phi)^T R_k^T R_{k+1}: identity for the exact motion.
  const lie::SO3d E = lie::SO3d::Exp(phi).inverse() * x0.R.inverse() * x1.R;
  ImuResidual res;
  res.r.segment<3>(0) = E.Log();                                                // r_R
  res.r.segment<3>(3) = x1.v - x0.v - g * dt - R0 * dv;                         // r_v
  res.r.segment<3>(6) = x1.p - x0.p - x0.v * dt - 0.5 * g * dt * dt - R0 * dp;  // r_p
  res.r.segment<3>(9) = x1.b_g - x0.b_g;                                        // r_bg
  res.r.segment<3>(12) = x1.b_a - x0.b_a;                                       // r_ba

  const Matrix3 I = Matrix3::Identity();
  const Matrix3 JrInv = lie::SO3d::JrInv(res.r.segment<3>(0));
  res.J_x0.setZero();
  res.J_x1.setZero();
  // r_R: R_k Exp(d) gives Exp(-R_{k+1}^T R_k d) on the right of E; the gyro bias moves phi by
  // -dt db_g, i.e. Exp(phi)^T by Exp(Jr(phi) dt db_g) on the left.
  res.J_x0.block<3, 3>(0, 0) = -JrInv * x1.R.matrix().transpose() * R0;
  res.J_x0.block<3, 3>(0, 9) = JrInv * E.matrix().transpose() * lie::SO3d::Jr(phi) * dt;
  res.J_x1.block<3, 3>(0, 0) = JrInv;
  // r_v: R_k Exp(d) y = R_k y - R_k [y]_x d.
  res.J_x0.block<3, 3>(3, 0) = R0 * lie::hat3(dv);
  res.J_x0.block<3, 3>(3, 3) = -I;
  res.J_x0.block<3, 3>(3, 9) = R0 * lie::imu::dGammaTimesVector<1>(phi, f, c) * (dt * dt);
  res.J_x0.block<3, 3>(3, 12) = R0 * Gamma1 * dt;
  res.J_x1.block<3, 3>(3, 3) = I;
  // r_p
  res.J_x0.block<3, 3>(6, 0) = R0 * lie::hat3(dp);
  res.J_x0.block<3, 3>(6, 3) = -dt * I;
  res.J_x0.block<3, 3>(6, 6) = -I;
  res.J_x0.block<3, 3>(6, 9) = R0 * lie::imu::dGammaTimesVector<2>(phi, f, c) * (dt * dt * dt);
  res.J_x0.block<3, 3>(6, 12) = R0 * Gamma2 * (dt * dt);
  res.J_x1.block<3, 3>(6, 6) = I;
  // biases
  res.J_x0.block<3, 3>(9, 9) = -I;
  res.J_x0.block<3, 3>(12, 12) = -I;
  res.J_x1.block<3, 3>(9, 9) = I;
  res.J_x1.block<3, 3>(12, 12) = I;
  return res;
}

Matrix15 imuNoise(const model::ImuNoise& noise, double dt) {
  const Matrix3 I = Matrix3::Identity();
  const double var_a = noise.accel_noise_density * noise.accel_noise_density;
  Matrix15 Q = Matrix15::Zero();
  Q.block<3, 3>(0, 0) = noise.gyro_noise_density * noise.gyro_noise_density * dt * I;
  // sigma_a^2 [[dt, dt^2/2], [dt^2/2, dt^3/3]] per axis: white acceleration integrated once, twice.
  Q.block<3, 3>(3, 3) = var_a * dt * I;
  Q.block<3, 3>(3, 6) = Q.block<3, 3>(6, 3) = var_a * dt * dt / 2.0 * I;
  Q.block<3, 3>(6, 6) = var_a * dt * dt * dt / 3.0 * I;
  // A zero random walk (a constant bias) is a zero block: the two states share one bias.
  Q.block<3, 3>(9, 9) = noise.gyro_bias_random_walk * noise.gyro_bias_random_walk * dt * I;
  Q.block<3, 3>(12, 12) = noise.accel_bias_random_walk * noise.accel_bias_random_walk * dt * I;
  return Q;
}

Vector3 kinematicsResidual(const State& x, int i, const Vector3& p_body, Matrix39* J_x) {
  return nominal::footInBody(x, i, J_x) - p_body;  // R^T (d_i - p) - p_body
}

}  // namespace tsif

using namespace tsif;

namespace {

using Matrix9x15 = Eigen::Matrix<double, 9, 15>;
// The kinematics rows of a step, stacked: four feet of three rows, or two flat feet with a
// position and a sole each. Rows of feet not in stance are padding (zero Jacobian, unit noise).
constexpr int kRows = 12;
using Vector12 = Eigen::Matrix<double, kRows, 1>;
using Matrix12 = Eigen::Matrix<double, kRows, kRows>;
using Matrix27x12 = Eigen::Matrix<double, kDim, kRows>;

void requirePositive(double value, const char* what) {
  if (value > 0.0 && std::isfinite(value)) return;
  std::ostringstream os;
  os << "Tsif: " << what << " must be positive and finite, got " << value;
  throw std::invalid_argument(os.str());
}

// The heading rule (eskf.hpp's "Heading" paragraph) at x: E = V B^T. B's columns pick the
// heading psi = up^T dtheta (up = R^T e_z, the vertical in the local error) and the gyro bias
// along up; V's are the turn of the robot about its base (up on the attitude, e_z x v on the
// velocity, e_z x (d_i - p) on the feet, R_F^T e_z on a flat foot's sole R_F) and up on the gyro
// bias.
struct Heading {
  Eigen::Matrix<double, kDim, 2> B = Eigen::Matrix<double, kDim, 2>::Zero();
  Eigen::Matrix<double, kDim, 2> V = Eigen::Matrix<double, kDim, 2>::Zero();
};
Heading heading(const State& x, const Soles& R_F, bool flat_feet) {
  const Eigen::Vector3d up = x.R.matrix().row(2).transpose();
  const auto turned = [](const Eigen::Vector3d& a) { return Eigen::Vector3d(-a.y(), a.x(), 0.0); };
  Heading h;
  h.B.col(0).segment<3>(kTheta) = h.V.col(0).segment<3>(kTheta) = up;
  h.V.col(0).segment<3>(kV) = turned(x.v);
  for (int i = 0; i < (flat_feet ? kFlatFeet : kFeet); ++i)
    h.V.col(0).segment<3>(footIndex(i)) = turned(x.d[i] - x.p);
  for (int i = 0; flat_feet && i < kFlatFeet; ++i)
    h.V.col(0).segment<3>(rotationIndex(i)) = R_F[i].matrix().row(2).transpose();  // R_F^T e_z
  h.B.col(1).segment<3>(kBg) = h.V.col(1).segment<3>(kBg) = up;
  return h;
}

// x (+) dx (State::plus); with flat feet the soles turn, R_F <- R_F Exp(dphi_i) as the attitude,
// and their blocks stay out of the (unused) feet 3 and 4 (the ESKF's injection).
State plus(const State& x, const Vector27& dx, bool flat_feet, Soles& R_F) {
  if (!flat_feet) return x.plus(dx);
  Vector27 dx_points = dx;
  for (int i = 0; i < kFlatFeet; ++i) {
    R_F[i] = lie::SO3d::fromQuaternion(Eigen::Quaterniond(
        R_F[i].matrix() * lie::SO3d::Exp(dx.segment<3>(rotationIndex(i))).matrix()));
    dx_points.segment<3>(rotationIndex(i)).setZero();
  }
  return x.plus(dx_points);
}

// x (-) y with flat feet's soles, Log(R_F,y^T R_F,x), in the blocks of feet 3 and 4.
Vector27 minus(const State& x, const Soles& R_Fx, const State& y, const Soles& R_Fy,
               bool flat_feet) {
  Vector27 dx = x.minus(y);
  for (int i = 0; flat_feet && i < kFlatFeet; ++i)
    dx.segment<3>(rotationIndex(i)) = R_Fx[i].rminus(R_Fy[i]);
  return dx;
}

// (dtheta, dv, dp, db_g, db_a) of a 27-vector, in the order of the IMU residual's rows.
tsif::Vector15 navigation(const Vector27& x) {
  tsif::Vector15 n;
  n << x.head<9>(), x.tail<6>();
  return n;
}

// One 3-row kinematics residual r (at the linearisation point) with Jacobian blocks J over the
// error blocks at cols (2 or 3 of them) and noise R: a foot's position or a flat foot's sole.
struct KinematicsRow {
  std::array<int, 3> cols{};
  std::array<Eigen::Matrix3d, 3> J;
  int blocks = 0;
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d times(const Vector27& dx) const {  // J dx
    Eigen::Vector3d y = Eigen::Vector3d::Zero();
    for (Eigen::Index k = 0; k < blocks; ++k) y.noalias() += J[k] * dx.segment<3>(cols[k]);
    return y;
  }
  // J P J^T + R, the residual's covariance under the state's P.
  Eigen::Matrix3d covariance(const Matrix27& P) const {
    Eigen::Matrix3d S = R;
    for (Eigen::Index k = 0; k < blocks; ++k)
      for (Eigen::Index l = 0; l < blocks; ++l)
        S.noalias() += J[k] * P.block<3, 3>(cols[k], cols[l]) * J[l].transpose();
    return S;
  }
};

// Stance foot i's kinematics at x, R^T (d_i - p) - p_body over (dtheta, dp, dd_i), noise Cov_i
// with the variance floor.
KinematicsRow footRow(const State& x, int i, const ContactMeasurement& c) {
  KinematicsRow row;
  Matrix39 J;
  row.r = kinematicsResidual(x, i, c.p_body, &J);
  row.cols = {kTheta, kP, footIndex(i)};
  row.blocks = 3;
  for (Eigen::Index k = 0; k < 3; ++k) row.J[k] = J.middleCols<3>(3 * k);
  row.R = c.cov + kMinFootVariance * Eigen::Matrix3d::Identity();
  return row;
}

// The stacked kinematics of a step: P H^T, S = H P H^T + R and its factor, over kRows rows.
struct Stack {
  std::array<KinematicsRow, kRows / 3> rows;
  int used = 0;   // rows[0..used) are residuals, the rest padding
  Matrix27x12 N;  // P_pred H^T
  Eigen::LLT<Matrix12> llt;

  // A H^T, for A 27 x 27 (zero on the padding).
  Matrix27x12 timesHt(const Matrix27& A) const {
    Matrix27x12 AHt = Matrix27x12::Zero();
    for (Eigen::Index a = 0; a < used; ++a) {
      const KinematicsRow& row = rows[a];
      for (Eigen::Index k = 0; k < row.blocks; ++k)
        AHt.middleCols<3>(3 * a).noalias() +=
            A.middleCols<3>(row.cols[k]).lazyProduct(row.J[k].transpose());
    }
    return AHt;
  }
  // K R, R the rows' block-diagonal noise.
  Matrix27x12 timesR(const Matrix27x12& K) const {
    Matrix27x12 KR = Matrix27x12::Zero();
    for (Eigen::Index a = 0; a < used; ++a)
      KR.middleCols<3>(3 * a).noalias() = K.middleCols<3>(3 * a).lazyProduct(rows[a].R);
    return KR;
  }
  // N and S from the predicted covariance; false when S does not factorise.
  bool factorise(const Matrix27& P) {
    N = timesHt(P);
    Matrix12 S = Matrix12::Identity();  // padding: unit noise, no Jacobian
    for (Eigen::Index a = 0; a < used; ++a) {
      const KinematicsRow& row = rows[a];
      for (Eigen::Index b = 0; b <= a; ++b) {
        Eigen::Matrix3d S_ab = Eigen::Matrix3d::Zero();
        for (Eigen::Index k = 0; k < row.blocks; ++k)
          S_ab.noalias() += row.J[k] * N.block<3, 3>(row.cols[k], 3 * b);
        if (a == b) S_ab += row.R;
        S.block<3, 3>(3 * a, 3 * b) = S_ab;
        S.block<3, 3>(3 * b, 3 * a) = S_ab.transpose();
      }
    }
    llt.compute(S);
    return llt.info() == Eigen::Success;
  }
  // The innovation nu = -(r + H mu) of the rows against the predicted step mu.
  Vector12 innovation(const Vector27& mu) const {
    Vector12 nu = Vector12::Zero();
    for (Eigen::Index a = 0; a < used; ++a) nu.segment<3>(3 * a) = -(rows[a].r + rows[a].times(mu));
    return nu;
  }
  // sum_a (H_a dx)^T R_a^-1 (H_a dx): the rows' share of dx^T S dx.
  double weightedNorm2(const Vector27& dx) const {
    double n2 = 0.0;
    for (Eigen::Index a = 0; a < used; ++a)
      n2 += Eigen::LLT<Eigen::Matrix3d>(rows[a].R).matrixL().solve(rows[a].times(dx)).squaredNorm();
    return n2;
  }
};

}  // namespace

Tsif::Tsif(const TsifParams& params)
    : params_(params),
      gate_(params.gating, "Tsif"),
      heading_(params.heading_turn_rate, params.heading_turn_time),
      slots_(params.flat_feet ? kFlatFeet : kFeet) {
  // White noise weighs the IMU residual by its inverse: it must be positive. A zero random walk
  // is a constant bias.
  checkFilterParams(params, "Tsif", true);
  requirePositive(params.foot_init_sigma, "foot_init_sigma");
  if (params.iterations < 1) {
    throw std::invalid_argument("Tsif: iterations must be at least 1, got " +
                                std::to_string(params.iterations));
  }
  if (!(params.step_tolerance >= 0.0)) {
    throw std::invalid_argument("Tsif: step_tolerance must be non-negative, got " +
                                std::to_string(params.step_tolerance));
  }
  reset(EstimateSample{});
}

void Tsif::reset(const EstimateSample& x0) {
  x_ = State{};
  x_.R = lie::SO3d::fromQuaternion(x0.q);
  x_.v = x0.v;
  x_.p = x0.p;
  for (Eigen::Vector3d& d : x_.d) d = x0.p;  // unknown until the foot touches down
  Vector27 variance;
  const auto set = [&](int offset, double sigma) {
    variance.segment<3>(offset).setConstant(sigma * sigma);
  };
  set(kTheta, params_.sigma_attitude);
  set(kV, params_.sigma_velocity);
  set(kP, params_.sigma_position);
  for (int i = 0; i < kFeet; ++i) set(footIndex(i), params_.foot_init_sigma);
  for (int i = 0; params_.flat_feet && i < kFlatFeet; ++i)
    set(rotationIndex(i), kFootRotationPrior);
  set(kBg, params_.sigma_gyro_bias);
  set(kBa, params_.sigma_accel_bias);
  P_ = variance.asDiagonal();
  in_contact_.fill(false);
  probability_.fill(0.0);
  foot_R_.fill(lie::SO3d{});
  rotation_held_.fill(false);
  t_ = x0.t;
  has_previous_ = false;
  pending_dt_ = 0.0;
  slots_.reset();
  gate_.reset();
  heading_.reset();
  startHealth(x0);
}

void Tsif::initialise(const InitialState& s) {
  checkInitialState(s, name());
  reset(s.x);
  x_.b_g = s.b_g;
  x_.b_a = s.b_a;
  if (std::isnan(s.sigma_tilt)) return;
  // World-frame prior diag(sigma_tilt^2, sigma_tilt^2, sigma_yaw^2) in the local error
  // dtheta = R_hat^T dtheta_w: R_hat^T diag(sigma^2) R_hat.
  const Eigen::Vector3d variance(s.sigma_tilt * s.sigma_tilt, s.sigma_tilt * s.sigma_tilt,
                                 params_.sigma_attitude * params_.sigma_attitude);
  const Eigen::Matrix3d& R = x_.R.matrix();
  P_.block<3, 3>(kTheta, kTheta) = R.transpose() * variance.asDiagonal() * R;
}

void Tsif::step(const StepInput& raw) {
  InputCopies copies;
  const auto [in, imu_admitted] = admit(raw, has_previous_, params_.limits, "Tsif", copies, slots_);
  last_iterations_ = 0;  // a step without a pair to solve takes none
  last_step_norm2_ = 0.0;
  std::array<const ContactMeasurement*, kFeet> contact{};  // the stance feet at k+1
  for (const ContactMeasurement& c : in.stance()) contact[c.foot] = &c;

  // Intervals shorter than kMinDt are carried over to the next step: the IMU residual of a pair
  // weighs ~1/dt, and at dt = 1e-12 s it would swamp the prior beyond double precision.
  const double dt = in.dt + pending_dt_;
  if (!has_previous_ || dt < kMinDt) {
    pending_dt_ = has_previous_ ? dt : 0.0;
    // No pair to solve yet: a foot that touches down is placed at its kinematics.
    for (int i = 0; i < kFeet; ++i) {
      if (contact[i] && !in_contact_[i]) placeFoot(i, *contact[i], x_, foot_R_);
      holdContact(i, contact[i]);
    }
    finishStep(in, imu_admitted);
    return;
  }

  pending_dt_ = 0.0;
  // The pair (x0, x1) = (x_k, x_{k+1}); x1 starts at the IMU prediction of x0.
  const State prior = x_;
  const Soles R_F_prior = foot_R_;
  State x0 = x_;
  Soles R_F0 = foot_R_, R_F1 = foot_R_;  // flat feet: the soles of x0 and x1
  State x1 = nominal::propagate(x0, previous_, dt, params_.gravity);
  heading_.add(yawRate(x1.R.matrix(), previous_.w_m, x1.b_g), dt, in.slip);
  const double alpha = params_.feet_correct_yaw ? 0.0 : heading_.alpha();  // heading_rule.hpp

  // A foot that touches down is placed after the solve (file comment, "Contacts").
  std::array<bool, kFeet> place{};
  for (int i = 0; i < kFeet; ++i) place[i] = contact[i] && !in_contact_[i];
  // sigma_d^2 of the foot residual d_{k+1} - d_k [m^2/s]: the swing density, or for a stance foot
  // the soft one of its contact probability p_c (Q_f of 57.6; p_c = 1: the stance density).
  std::array<double, kFeet> foot_variance_density{};
  const double sw = params_.foot_swing_density;
  for (int i = 0; i < kFeet; ++i) {
    foot_variance_density[i] = contact[i]
                                   ? contact::softFootNoiseDensity(contact[i]->probability,
                                                                   params_.foot_stance_density, sw)
                                   : sw * sw;
  }
  // Flat feet: a sole's Log(R_F,k^T R_F,k+1) [rad^2/s] in the blocks of feet 3 and 4, of the
  // contact at k as the ESKF's (where touchdown settling ends p_c goes from 0 to 1 at k+1).
  for (int i = 0; params_.flat_feet && i < kFlatFeet; ++i) {
    const double sw_F = params_.foot_rotation_swing_density;
    foot_variance_density[kFlatFeet + i] =
        in_contact_[i] ? contact::softFootNoiseDensity(probability_[i],
                                                       params_.foot_rotation_stance_density, sw_F)
                       : sw_F * sw_F;
  }
  const auto isSole = [&](int j) { return params_.flat_feet && j >= kFlatFeet; };
  std::array<bool, kFeet> kinematics{};  // stance feet whose kinematics residual is used
  for (int i = 0; i < kFeet; ++i) kinematics[i] = contact[i] && !place[i];
  const Eigen::Matrix3d floor = kMinFootVariance * Eigen::Matrix3d::Identity();

  Matrix27 P1;  // the covariance of the prediction of x1 at the last linearisation
  Stack stack;  // and its kinematics rows
  Vector27 dx1_last = Vector27::Zero();
  State x1_linearised = x1;      // where the last iteration linearised
  Soles R_F1_linearised = R_F1;  // and its soles
  bool feet_used = false;
  for (int iteration = 0; iteration < params_.iterations; ++iteration) {
    // The prior on x0, delta0 = (x0 (+) dx0) (-) prior = e0 + A dx0 ~ N(0, P_), with A =
    // JrInv(e0_theta) on the attitude (the soles' blocks: I, exact at the first iteration).
    const Vector27 e0 = minus(x0, R_F0, prior, R_F_prior, params_.flat_feet);
    const Eigen::Matrix3d A_inv = lie::SO3d::Jr(Eigen::Vector3d(e0.segment<3>(kTheta)));
    // The residuals between the two states, r_b + J0 dx0 + J1 dx1 = -n, n ~ N(0, Q): the IMU's,
    // and each foot's d_{k+1} - d_k (a sole's Log(R_F,k^T R_F,k+1)) with Jacobians -I and I.
    const ImuResidual e = imuResidual(x0, x1, previous_, dt, params_.gravity);
    const Eigen::Matrix3d A1_inv = e.J_x1.topLeftCorner<3, 3>().inverse();  // J1 = diag(A1, I)
    // So dx1 = mu + G delta0 + J1^-1 n: G = -J1^-1 J0 A^-1 is the identity but on the navigation
    // rows (the ESKF's Phi at the first iteration), mu = -(G e0 + J1^-1 r_b).
    Matrix9x15 G = -e.J_x0.topRows<9>();
    G.topRows<3>() = (A1_inv * G.topRows<3>()).eval();
    G.leftCols<3>() = (G.leftCols<3>() * A_inv).eval();
    P1 = P_;
    const Matrix9x27 GP0 = transformNavigation(P1, G.leftCols<9>(), G.rightCols<6>());
    // + J1^-1 Q J1^-T (imuNoise; the feet's random walks).
    const Matrix15 Q = imuNoise(params_.imu, dt);
    P1.block<3, 3>(kTheta, kTheta) += A1_inv * Q.topLeftCorner<3, 3>() * A1_inv.transpose();
    P1.block<6, 6>(kV, kV) += Q.block<6, 6>(3, 3);
    P1.block<6, 6>(kBg, kBg) += Q.bottomRightCorner<6, 6>();
    for (int j = 0; j < kFeet; ++j)
      P1.block<3, 3>(footIndex(j), footIndex(j)).diagonal().array() +=
          foot_variance_density[j] * dt;
    Vector27 mu = e0;
    mu.head<9>() = G * navigation(e0);
    mu.head<3>() += A1_inv * e.r.head<3>();
    mu.segment<6>(kV) += e.r.segment<6>(3);
    mu.tail<6>() += e.r.tail<6>();
    for (int j = 0; j < kFeet; ++j) {
      mu.segment<3>(footIndex(j)) += isSole(j) ? R_F1[j - kFlatFeet].rminus(R_F0[j - kFlatFeet])
                                               : Eigen::Vector3d(x1.d[j] - x0.d[j]);
    }
    mu = -mu;

    if (iteration == 0 && gate_.enabled()) {
      // The gate (file comment): residuals at the prediction against J P_pred J^T + Cov.
      for (int i = 0; i < kFeet; ++i) {
        if (!kinematics[i]) continue;
        const KinematicsRow row = footRow(x1, i, *contact[i]);
        const Eigen::LLT<Eigen::Matrix3d> llt(row.covariance(P1));
        if (llt.info() != Eigen::Success) continue;
        const double d2 = llt.matrixL().solve(row.r).squaredNorm();  // r^T S^-1 r
        const engineering::FootGate::Decision decision = gate_.decide(i, d2, in.t);
        if (decision == engineering::FootGate::Decision::kUse) continue;
        health_.record(Fault::kGated, in.t);
        kinematics[i] = false;  // gated; gated too long: placed anew, as at a touchdown
        place[i] = decision != engineering::FootGate::Decision::kGate;
      }
    }

    // The kinematics of the stance feet at x1, over (dtheta, dp, dd_i), and their soles' over
    // (dtheta, dphi_i): r + H dx1 = n, n ~ N(0, Cov_i).
    stack.used = 0;
    for (int i = 0; i < kFeet; ++i) {
      if (!kinematics[i]) continue;
      stack.rows[stack.used++] = footRow(x1, i, *contact[i]);
      if (!(i < kFlatFeet && rotation_held_[i] && contact[i]->R_body)) continue;
      // The sole: the TSIF's h (-) z is Log(Z^T h) = -r + H dx, r and H of soleResidual.
      KinematicsRow& sole = stack.rows[stack.used++];
      Eigen::Matrix<double, 3, 6> H;
      sole.r = -soleResidual(x1.R, R_F1[i], *contact[i]->R_body, &H);
      sole.cols = {kTheta, rotationIndex(i), 0};
      sole.blocks = 2;
      sole.J[0] = H.leftCols<3>();
      sole.J[1] = H.rightCols<3>();
      sole.R = contact[i]->rot_cov + floor;
    }
    feet_used = stack.used > 0;
    // dx1 = mu + K nu with K = P1 H^T S^-1: the solve of the pair's normal equations for x1.
    if (!stack.factorise(P1)) return failedUpdate(in, imu_admitted);
    Vector27 dx1 = mu;
    if (feet_used) dx1.noalias() += stack.N * stack.llt.solve(stack.innovation(mu));
    if (alpha > 0.0 && feet_used) {
      // The heading rule: dx1 <- (I - alpha E) dx1, the feet's and the soles' step alike.
      const Heading h = heading(x1, R_F1, params_.flat_feet);
      dx1 -= alpha * h.V * (h.B.transpose() * dx1);
    }
    x1_linearised = x1;
    R_F1_linearised = R_F1;
    x1 = plus(x1, dx1, params_.flat_feet, R_F1);
    dx1_last = dx1;
    ++last_iterations_;
    // x0's step and the stopping test need P1^-1; the last allowed iteration needs neither.
    if (iteration + 1 == params_.iterations) break;
    const Eigen::LLT<Matrix27> llt1(P1);
    if (llt1.info() != Eigen::Success) return failedUpdate(in, imu_admitted);
    // dx1^T S dx1 with S = P1^-1 + H^T Cov^-1 H, the information of x1 given both residuals.
    last_step_norm2_ = llt1.matrixL().solve(dx1).squaredNorm() + stack.weightedNorm2(dx1);
    if (last_step_norm2_ < params_.step_tolerance) break;
    // x0's step given x1's: delta0 = P_ G^T P1^-1 (dx1 - mu), then dx0 = A^-1 (delta0 - e0).
    Vector27 w = llt1.solve(Vector27(dx1 - mu));
    const Eigen::Matrix<double, 9, 1> w_nav = w.head<9>();
    w.head<9>().setZero();
    Vector27 dx0 = P_ * w - e0;
    dx0.noalias() += GP0.transpose() * w_nav;
    dx0.head<3>() = (A_inv * dx0.head<3>()).eval();
    x0 = plus(x0, dx0, params_.flat_feet, R_F0);
  }

  x1.R = lie::SO3d::fromQuaternion(x1.R.quaternion());  // remove rounding drift
  // The covariance of x1 at the last linearisation, with that update's gain K = N S^-1 and the
  // heading rule's K' = (I - alpha E) K (the step took the same share): the Joseph form, as the
  // ESKF's, P = (I - K' H) P1 (I - K' H)^T + K' R K'^T = A + (K' R - A H^T) K'^T with
  // A = P1 - K' N^T. (P1 - K S K^T, a quarter of the cost, amplified rounding: the same iCub run
  // in the Python module and in `legkit run` drifted 2e-9 m apart within 6 s, where the two agree
  // to the last digit with this form; tests/python/test_estimators.py.)
  P_ = P1;
  if (feet_used) {
    Matrix27x12 K = stack.llt.solve(stack.N.transpose()).transpose();
    if (alpha > 0.0) {
      const Heading h = heading(x1_linearised, R_F1_linearised, params_.flat_feet);
      K -= alpha * h.V * (h.B.transpose() * K);
    }
    Matrix27 A = P1;
    A.noalias() -= K.lazyProduct(stack.N.transpose());
    const Matrix27x12 B = stack.timesR(K) - stack.timesHt(A);
    A.noalias() += B.lazyProduct(K.transpose());
    P_ = 0.5 * (A + A.transpose());
  }
  // The covariance is in the tangent at x1 before its step; moved to the tangent at x1 (+) dx1.
  resetRotation(P_, kTheta, dx1_last.segment<3>(kTheta));
  for (int i = 0; params_.flat_feet && i < kFlatFeet; ++i)
    resetRotation(P_, rotationIndex(i), dx1_last.segment<3>(rotationIndex(i)));
  x_ = x1;
  foot_R_ = R_F1;
  for (int i = 0; i < kFeet; ++i) {
    if (place[i]) placeFoot(i, *contact[i], x_, foot_R_);
    if (!contact[i]) gate_.clear(i);  // lifted off: its gate clock stops
    holdContact(i, contact[i]);
  }
  finishStep(in, imu_admitted);
}

void Tsif::placeFoot(int i, const ContactMeasurement& c, State& x, Soles& R_F) {
  tsif::placeFoot(x, P_, i, c.p_body, c.cov);                     // d = p + R p_body
  rotation_held_[i] = params_.flat_feet && c.R_body.has_value();  // flat: i < kFlatFeet
  if (rotation_held_[i]) R_F[i] = tsif::placeSole(x.R, P_, i, *c.R_body, c.rot_cov);  // R Z
}

void Tsif::failedUpdate(const StepInput& in, bool imu_admitted) {
  health_.record(Fault::kUpdateFailed, in.t);
  restart(estimate());
  finishStep(in, imu_admitted);
}

void Tsif::holdContact(int i, const ContactMeasurement* c) {
  in_contact_[i] = c != nullptr;
  probability_[i] = c ? c->probability : 0.0;
}

void Tsif::finishStep(const StepInput& in, bool imu_admitted) {
  if (imu_admitted) {
    previous_ = in.imu;
    has_previous_ = true;
  }
  t_ = in.t;
  if (!guard_.check(estimate(), P_, params_.limits)) recover(in.t);
}

EstimateSample Tsif::estimate() const {
  return {t_, x_.R.quaternion(), x_.v, x_.p};
}

std::optional<BaseCovariance> Tsif::covariance() const {
  BaseCovariance cov;
  cov.P = worldBaseBlock(P_, x_.R);
  return cov;
}

Matrix27 Tsif::information() const {
  return P_.llt().solve(Matrix27::Identity());
}

}  // namespace legkit::invariant
