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

// Offsets in the 27-vector of the five navigation blocks (dtheta, dv, dp, db_g, db_a), the
// columns of the IMU residual's Jacobians.
constexpr std::array<int, 5> kNav = {kTheta, kV, kP, kBg, kBa};

// H(rows a, cols b) += M, M 15 x 15 over navigation blocks.
void addNavBlock(Matrix27& H, const Matrix15& M) {
  for (int a = 0; a < 5; ++a)
    for (int b = 0; b < 5; ++b) H.block<3, 3>(kNav[a], kNav[b]) += M.block<3, 3>(3 * a, 3 * b);
}

void addNavVector(Vector27& g, const Vector15& m) {
  for (int a = 0; a < 5; ++a) g.segment<3>(kNav[a]) += m.segment<3>(3 * a);
}

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

Matrix15 imuWeight(const model::ImuNoise& noise, double dt) {
  const Matrix3 I = Matrix3::Identity();
  const double var_g = noise.gyro_noise_density * noise.gyro_noise_density;
  const double var_a = noise.accel_noise_density * noise.accel_noise_density;
  const double var_bg = noise.gyro_bias_random_walk * noise.gyro_bias_random_walk;
  const double var_ba = noise.accel_bias_random_walk * noise.accel_bias_random_walk;
  Matrix15 W = Matrix15::Zero();
  W.block<3, 3>(0, 0) = I / (var_g * dt);
  // Inverse of sigma_a^2 [[dt, dt^2/2], [dt^2/2, dt^3/3]] per axis.
  W.block<3, 3>(3, 3) = 4.0 / (var_a * dt) * I;
  W.block<3, 3>(3, 6) = -6.0 / (var_a * dt * dt) * I;
  W.block<3, 3>(6, 3) = W.block<3, 3>(3, 6);
  W.block<3, 3>(6, 6) = 12.0 / (var_a * dt * dt * dt) * I;
  // A zero random walk (a constant bias) weighs its residual zero: the step shares one bias
  // between the two states instead (shareBias), which is the infinite weight taken exactly.
  W.block<3, 3>(9, 9) = var_bg > 0.0 ? Matrix3(I / (var_bg * dt)) : Matrix3::Zero();
  W.block<3, 3>(12, 12) = var_ba > 0.0 ? Matrix3(I / (var_ba * dt)) : Matrix3::Zero();
  return W;
}

Vector3 kinematicsResidual(const State& x, int i, const Vector3& p_body, Matrix39* J_x) {
  return nominal::footInBody(x, i, J_x) - p_body;  // R^T (d_i - p) - p_body
}

}  // namespace tsif

using namespace tsif;

namespace {

void requirePositive(double value, const char* what) {
  if (value > 0.0 && std::isfinite(value)) return;
  std::ostringstream os;
  os << "Tsif: " << what << " must be positive and finite, got " << value;
  throw std::invalid_argument(os.str());
}

// Marginalises the 3 x 3 block at f (a foot, or a flat foot's sole) out of the information Lambda
// (Schur complement) and leaves it with no information at all: the foot forgets where it was, and
// only the kinematics residual of the touchdown step decides where it is now. (A weak prior on the
// new foot would be information the robot does not have: its mean comes from the estimate, so each
// touchdown would add a little to the unobservable position.)
void forgetBlock(Matrix27& Lambda, int f) {
  const Eigen::Matrix<double, kDim, 3> B = Lambda.middleCols<3>(f);
  const Eigen::LLT<Eigen::Matrix3d> llt(Lambda.block<3, 3>(f, f));
  Lambda.noalias() -= B * llt.solve(B.transpose());
  Lambda.middleRows<3>(f).setZero();
  Lambda.middleCols<3>(f).setZero();
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

// A bias with zero random walk is constant, b_{k+1} = b_k: an infinite weight on r_b that the
// normal equations cannot hold. Instead the pair shares one bias. The substitution
// dx0_b = dx1_b (H' = T^T H T) folds x_k's bias rows and columns (its prior, the IMU residual's
// dependence on it) into x_{k+1}'s, and leaves x_k's bias block an identity with a zero
// right-hand side, so that the elimination of x_k below is unchanged.
void shareBias(int b, Matrix27& H11, Matrix27& H12, Matrix27& H22, Vector27& b1, Vector27& b2) {
  const Eigen::Matrix<double, 3, kDim> row = H12.middleRows<3>(b);  // x_k's bias, x_{k+1}
  H22.middleRows<3>(b) += row;
  H22.middleCols<3>(b) += row.transpose();
  H22.block<3, 3>(b, b) += H11.block<3, 3>(b, b);
  H12.middleCols<3>(b) += H11.middleCols<3>(b);
  b2.segment<3>(b) += b1.segment<3>(b);
  H11.middleRows<3>(b).setZero();
  H11.middleCols<3>(b).setZero();
  H11.block<3, 3>(b, b).setIdentity();
  H12.middleRows<3>(b).setZero();
  b1.segment<3>(b).setZero();
}

// The marginal information of x_{k+1} given the prior on x_k (information H_prior, already in
// x_k's linearisation) and the residuals between the two states, in covariance form (Woodbury):
//   J_1^T (Q + J_0 P_0 J_0^T)^-1 J_1,   P_0 = H_prior^-1,   Q = W^-1.
// Equal to the Schur complement of the normal equations in exact arithmetic; here no term of
// 1e14 (the IMU's weight on position) is subtracted from another to leave a remainder of order 1
// (the information on an unobservable position after minutes). A foot that touched down (no
// information on x_k) has no between-residual that says anything: its rows are left out.
Matrix27 betweenMarginal(const Matrix27& H_prior, const ImuResidual& e, const model::ImuNoise& n,
                         double dt, const std::array<double, kFeet>& foot_variance_density,
                         const std::array<bool, kFeet>& forgotten, Matrix27* P_pred = nullptr) {
  const Matrix3 I = Matrix3::Identity();
  Matrix27 Lambda = H_prior;
  for (int i = 0; i < kFeet; ++i)
    if (forgotten[i]) Lambda.block<3, 3>(footIndex(i), footIndex(i)) = I;
  const Matrix27 P0 = Lambda.llt().solve(Matrix27::Identity());
  // M = J_0 P_0 J_0^T. J_0 is -I on every row but the 9 of (r_R, r_v, r_p) (the ESKF's Phi): the
  // rest of P_0 is kept as it is, and only those rows, T = J_0(nav rows) P_0, are products.
  Eigen::Matrix<double, 9, kDim> T = Eigen::Matrix<double, 9, kDim>::Zero();
  for (int b = 0; b < 5; ++b)
    T.noalias() += e.J_x0.block<9, 3>(0, 3 * b).lazyProduct(P0.middleRows<3>(kNav[b]));
  Eigen::Matrix<double, 9, 9> TJt = Eigen::Matrix<double, 9, 9>::Zero();  // J_0 P_0 J_0^T, nav
  for (int b = 0; b < 5; ++b)
    TJt.noalias() += T.middleCols<3>(kNav[b]).lazyProduct(e.J_x0.block<9, 3>(0, 3 * b).transpose());
  Matrix27 M = P0;
  M.topRows<9>() = -T;  // J_0(nav rows) P_0 (-I)^T on the columns of the other blocks
  M.leftCols<9>() = -T.transpose();
  M.topLeftCorner<9, 9>() = TJt;
  // + Q, the noise of the IMU and feet residuals over dt (file comment).
  const double var_a = n.accel_noise_density * n.accel_noise_density;
  M.block<3, 3>(kTheta, kTheta) += n.gyro_noise_density * n.gyro_noise_density * dt * I;
  M.block<3, 3>(kV, kV) += var_a * dt * I;
  M.block<3, 3>(kV, kP) += var_a * dt * dt / 2.0 * I;
  M.block<3, 3>(kP, kV) += var_a * dt * dt / 2.0 * I;
  M.block<3, 3>(kP, kP) += var_a * dt * dt * dt / 3.0 * I;
  M.block<3, 3>(kBg, kBg) += n.gyro_bias_random_walk * n.gyro_bias_random_walk * dt * I;
  M.block<3, 3>(kBa, kBa) += n.accel_bias_random_walk * n.accel_bias_random_walk * dt * I;
  for (int i = 0; i < kFeet; ++i)
    M.block<3, 3>(footIndex(i), footIndex(i)) += foot_variance_density[i] * dt * I;
  for (int i = 0; i < kFeet; ++i) {
    if (!forgotten[i]) continue;
    M.middleRows<3>(footIndex(i)).setZero();
    M.middleCols<3>(footIndex(i)).setZero();
    M.block<3, 3>(footIndex(i), footIndex(i)) = I;
  }
  Matrix27 Minv = M.llt().solve(Matrix27::Identity());
  for (int i = 0; i < kFeet; ++i) {
    if (!forgotten[i]) continue;
    Minv.middleRows<3>(footIndex(i)).setZero();
    Minv.middleCols<3>(footIndex(i)).setZero();
  }
  // J_1^T M^-1 J_1: J_1 is the identity but for its attitude block A1 = JrInv(r_R).
  const Matrix3 A1 = e.J_x1.topLeftCorner<3, 3>();
  if (P_pred) {  // its inverse J_1^-1 M J_1^-T, an identity block on a forgotten foot
    const Matrix3 A1_inv = A1.inverse();
    *P_pred = M;
    P_pred->leftCols<3>() = P_pred->leftCols<3>().lazyProduct(A1_inv.transpose()).eval();
    P_pred->topRows<3>() = A1_inv.lazyProduct(P_pred->topRows<3>()).eval();
  }
  Minv.leftCols<3>() = Minv.leftCols<3>().lazyProduct(A1).eval();
  Minv.topRows<3>() = A1.transpose().lazyProduct(Minv.topRows<3>()).eval();
  return Minv;
}

// Cov^-1 of a kinematics residual (a stance foot's position, or its sole's rotation). The
// variance floor keeps the normal equations factorisable for any admitted covariance (1e-30 m^2
// would weigh 1e30 against a prior of ~1e4).
Eigen::Matrix3d weightOf(const Eigen::Matrix3d& cov) {
  const Eigen::Matrix3d floored = cov + kMinFootVariance * Eigen::Matrix3d::Identity();
  return floored.llt().solve(Eigen::Matrix3d::Identity());
}

// Adds a 3-dimensional residual r with Jacobian J over the error blocks at `blocks` and weight W
// to the normal equations H dx = -g: J^T W J and J^T W r.
template <int Blocks>
void addResidual(const std::array<int, Blocks>& blocks,
                 const Eigen::Matrix<double, 3, 3 * Blocks>& J, const Eigen::Vector3d& r,
                 const Eigen::Matrix3d& W, Matrix27& H, Vector27& g) {
  const Eigen::Matrix<double, 3 * Blocks, 3> JtW = J.transpose() * W;
  const Eigen::Matrix<double, 3 * Blocks, 3 * Blocks> M = JtW * J;
  const Eigen::Matrix<double, 3 * Blocks, 1> m = JtW * r;
  for (int a = 0; a < Blocks; ++a) {
    g.template segment<3>(blocks[a]) += m.template segment<3>(3 * a);
    for (int b = 0; b < Blocks; ++b)
      H.template block<3, 3>(blocks[a], blocks[b]) += M.template block<3, 3>(3 * a, 3 * b);
  }
}

// Adds the kinematics residual of stance foot i at x, weight W, over (dtheta, dp, dd_i).
void addKinematics(const State& x, int i, const ContactMeasurement& c, const Eigen::Matrix3d& W,
                   Matrix27& H, Vector27& g) {
  Matrix39 J;
  const Eigen::Vector3d r = kinematicsResidual(x, i, c.p_body, &J);
  addResidual<3>({kTheta, kP, footIndex(i)}, J, r, W, H, g);
}

// Adds flat foot i's sole residual at (x, R_F), weight W, over (dtheta, dphi_i): with the ESKF's
// r = Log(h_hat^T Z) = dphi_i - h_hat^T dtheta + n and H = [-h_hat^T, I] (soleResidual), the
// TSIF's h (-) z is Log(Z^T h) = -r + H dx (file comment, "Flat feet").
void addSole(const State& x, const lie::SO3d& R_F, int i, const ContactMeasurement& c,
             const Eigen::Matrix3d& W, Matrix27& H, Vector27& g) {
  Eigen::Matrix<double, 3, 6> J;
  const Eigen::Vector3d r = soleResidual(x.R, R_F, *c.R_body, &J);
  addResidual<2>({kTheta, rotationIndex(i)}, J, -r, W, H, g);
}

}  // namespace

Tsif::Tsif(const TsifParams& params)
    : params_(params),
      gate_(params.gating, "Tsif"),
      heading_(params.heading_turn_rate, params.heading_turn_time),
      slots_(params.flat_feet ? kFlatFeet : kFeet) {
  // White noise weighs the IMU residual by its inverse: it must be positive. A zero random walk
  // is a constant bias (shareBias).
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
  Vector27 information;
  const auto set = [&](int offset, double sigma) {
    information.segment<3>(offset).setConstant(1.0 / (sigma * sigma));
  };
  set(kTheta, params_.sigma_attitude);
  set(kV, params_.sigma_velocity);
  set(kP, params_.sigma_position);
  for (int i = 0; i < kFeet; ++i) set(footIndex(i), params_.foot_init_sigma);
  for (int i = 0; params_.flat_feet && i < kFlatFeet; ++i)
    set(rotationIndex(i), kFootRotationPrior);
  set(kBg, params_.sigma_gyro_bias);
  set(kBa, params_.sigma_accel_bias);
  Lambda_ = information.asDiagonal();
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
  // dtheta = R_hat^T dtheta_w, as information: R_hat^T diag(1 / sigma^2) R_hat.
  const Eigen::Vector3d information(1.0 / (s.sigma_tilt * s.sigma_tilt),
                                    1.0 / (s.sigma_tilt * s.sigma_tilt),
                                    1.0 / (params_.sigma_attitude * params_.sigma_attitude));
  const Eigen::Matrix3d& R = x_.R.matrix();
  Lambda_.block<3, 3>(kTheta, kTheta) = R.transpose() * information.asDiagonal() * R;
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
    // No pair to solve yet. A foot that touches down is forgotten and placed at its kinematics,
    // d = p + R p_body, whose residual, zero at that mean, is then all its information (the
    // ESKF's initialisation of a foot, in information form).
    for (int i = 0; i < kFeet; ++i) {
      if (contact[i] && !in_contact_[i]) {
        placeFoot(i, *contact[i], Lambda_, x_, foot_R_);
        Vector27 g = Vector27::Zero();  // zero: the residuals vanish at the new foot and sole
        addKinematics(x_, i, *contact[i], weightOf(contact[i]->cov), Lambda_, g);
        if (rotation_held_[i])
          addSole(x_, foot_R_[i], i, *contact[i], weightOf(contact[i]->rot_cov), Lambda_, g);
      }
      holdContact(i, contact[i]);
    }
    Lambda_ = 0.5 * (Lambda_ + Lambda_.transpose()).eval();
    finishStep(in, imu_admitted);
    return;
  }

  pending_dt_ = 0.0;
  // The pair (x0, x1) = (x_k, x_{k+1}); x1 starts at the IMU prediction of x0.
  State x0 = x_;
  Soles R_F0 = foot_R_;  // flat feet: the soles of x0 and x1
  Matrix27 Lambda0 = Lambda_;
  State x1 = nominal::propagate(x0, previous_, dt, params_.gravity);
  heading_.add(yawRate(x1.R.matrix(), previous_.w_m, x1.b_g), dt, in.slip);
  const double alpha = params_.feet_correct_yaw ? 0.0 : heading_.alpha();  // heading_rule.hpp
  Soles R_F1 = R_F0;
  // The four blocks after p (feet, or with flat feet two feet and their soles) placed at this step,
  // with no information on x0.
  std::array<bool, kFeet> forgotten{};
  // Touchdown: the foot (and its sole) is forgotten and placed at this sample's kinematics (in both
  // states; the stance residual ties them, the kinematics residual gives it all its information).
  const auto touchDown = [&](int i) {
    placeFoot(i, *contact[i], Lambda0, x1, R_F1);
    x0.d[i] = x1.d[i];
    forgotten[i] = true;
    if (!rotation_held_[i]) return;  // held only by a flat foot, i < kFlatFeet
    R_F0[i] = R_F1[i];
    forgotten[kFlatFeet + i] = true;
  };
  for (int i = 0; i < kFeet; ++i)
    if (contact[i] && !in_contact_[i]) touchDown(i);

  // Weights of this step.
  const Matrix15 W_imu = imuWeight(params_.imu, dt);
  // sigma_d^2 of the foot residual d_{k+1} - d_k [m^2/s]: the swing density, or for a stance foot
  // the soft one of its contact probability p_c (Q_f of 57.6; p_c = 1: the stance density).
  std::array<double, kFeet> foot_variance_density{};
  std::array<double, kFeet> w_c{};  // its weight: w_c I = (sigma_d^2 dt)^-1 I
  const double sw = params_.foot_swing_density;
  for (int i = 0; i < kFeet; ++i) {
    foot_variance_density[i] = contact[i]
                                   ? contact::softFootNoiseDensity(contact[i]->probability,
                                                                   params_.foot_stance_density, sw)
                                   : sw * sw;
    w_c[i] = 1.0 / (foot_variance_density[i] * dt);
  }
  // Flat feet: a sole's Log(R_F,k^T R_F,k+1) [rad^2/s] in the blocks of feet 3 and 4, of the
  // contact at k as the ESKF's (where touchdown settling ends p_c goes from 0 to 1 at k+1).
  const auto isSole = [&](int j) { return params_.flat_feet && j >= kFlatFeet; };
  for (int i = 0; params_.flat_feet && i < kFlatFeet; ++i) {
    const double sw_F = params_.foot_rotation_swing_density;
    foot_variance_density[kFlatFeet + i] =
        in_contact_[i] ? contact::softFootNoiseDensity(probability_[i],
                                                       params_.foot_rotation_stance_density, sw_F)
                       : sw_F * sw_F;
    w_c[kFlatFeet + i] = 1.0 / (foot_variance_density[kFlatFeet + i] * dt);
  }
  std::array<bool, kFeet> kinematics{};  // stance feet whose kinematics residual is used
  for (int i = 0; i < kFeet; ++i) kinematics[i] = contact[i] != nullptr;
  if (gate_.enabled()) {
    // The gate (file comment): residuals at the prediction against J P_pred J^T + Cov.
    Matrix27 Lambda_pred =
        betweenMarginal(Lambda0, imuResidual(x0, x1, previous_, dt, params_.gravity), params_.imu,
                        dt, foot_variance_density, forgotten);
    for (int j = 0; j < kFeet; ++j)  // a forgotten foot has no information: decoupled here
      if (forgotten[j]) Lambda_pred.block<3, 3>(footIndex(j), footIndex(j)).setIdentity();
    const Eigen::LLT<Matrix27> llt_pred(Lambda_pred);
    for (int i = 0; i < kFeet; ++i) {
      if (!contact[i] || forgotten[i] || llt_pred.info() != Eigen::Success) continue;
      Matrix39 J;
      const Eigen::Vector3d r = kinematicsResidual(x1, i, contact[i]->p_body, &J);
      Eigen::Matrix<double, kDim, 9> E =
          Eigen::Matrix<double, kDim, 9>::Zero();  // (dtheta, dp, dd_i)
      const std::array<int, 3> blocks = {kTheta, kP, footIndex(i)};
      for (int a = 0; a < 3; ++a) E.block<3, 3>(blocks[a], 3 * a).setIdentity();
      const Eigen::Matrix<double, 9, 9> P_sub = E.transpose() * llt_pred.solve(E);
      const Eigen::Matrix3d S = J * P_sub * J.transpose() + contact[i]->cov +
                                kMinFootVariance * Eigen::Matrix3d::Identity();
      const Eigen::LLT<Eigen::Matrix3d> llt(S);
      if (llt.info() != Eigen::Success) continue;
      const double d2 = llt.matrixL().solve(r).squaredNorm();  // r^T S^-1 r
      const engineering::FootGate::Decision decision = gate_.decide(i, d2, in.t);
      if (decision == engineering::FootGate::Decision::kUse) continue;
      health_.record(Fault::kGated, in.t);
      if (decision == engineering::FootGate::Decision::kGate) {
        kinematics[i] = false;
      } else {  // gated too long: placed anew, as at a touchdown
        touchDown(i);
      }
    }
  }
  for (int i = 0; i < kFeet; ++i)
    if (!contact[i]) gate_.clear(i);  // lifted off: its gate clock stops
  const State prior = x0;
  std::array<Eigen::Matrix3d, kFeet> W_kin{};  // Cov_i^-1 of the kinematics of stance feet
  for (int i = 0; i < kFeet; ++i)
    if (kinematics[i]) W_kin[i] = weightOf(contact[i]->cov);
  // Flat feet: the soles whose residual is used (with their foot's kinematics), rot_cov^-1.
  std::array<bool, kFeet> sole_used{};
  std::array<Eigen::Matrix3d, kFeet> W_sole{};
  for (int i = 0; params_.flat_feet && i < kFlatFeet; ++i) {
    sole_used[i] = kinematics[i] && rotation_held_[i] && contact[i]->R_body.has_value();
    if (sole_used[i]) W_sole[i] = weightOf(contact[i]->rot_cov);
  }

  // The linearisation of the last iteration, from which the new information is formed.
  Matrix27 H_prior;  // the prior's information in x0's tangent
  ImuResidual e;     // the IMU residual and its Jacobians
  Matrix27 H_kin;    // the kinematics residuals' information on x1 (the feet's, and their soles')
  Vector27 dx1_last = Vector27::Zero();  // the step of x1
  bool feet_used = false;                // a kinematics residual is in the problem
  for (int i = 0; i < kFeet; ++i) feet_used = feet_used || kinematics[i];
  State x1_linearised = x1;      // where the last iteration linearised (H_kin's point)
  Soles R_F1_linearised = R_F1;  // and its soles
  for (int iteration = 0; iteration < params_.iterations; ++iteration) {
    // Normal equations [H11 H12; H12^T H22] [dx0; dx1] = -[b1; b2].
    Matrix27 H11, H12, H22;
    Vector27 b1, b2;
    H12.setZero();
    H22.setZero();
    b2.setZero();

    // Prior: r0 = x0 (-) prior, Jacobian identity except JrInv(r0_theta) on the attitude.
    const Vector27 r0 = x0.minus(prior);
    const Eigen::Matrix3d A = lie::SO3d::JrInv(r0.segment<3>(kTheta));
    H11 = Lambda0;
    H11.leftCols<3>() = H11.leftCols<3>().lazyProduct(A).eval();
    H11.topRows<3>() = A.transpose().lazyProduct(H11.topRows<3>()).eval();
    b1 = Lambda0 * r0;
    b1.head<3>() = (A.transpose() * b1.head<3>()).eval();
    H_prior = H11;

    // IMU between x0 and x1.
    e = imuResidual(x0, x1, previous_, dt, params_.gravity);
    // J_x1 is the identity but for its attitude block A1 = JrInv(r_R), and W_imu does not couple
    // r_R with the other rows: the products with J_x1 are W_imu with A1 applied to the attitude.
    const Matrix15 WJ0 = W_imu.lazyProduct(e.J_x0);
    const Eigen::Matrix3d A1 = e.J_x1.topLeftCorner<3, 3>();
    Matrix15 H12_nav = WJ0.transpose();  // J_x0^T W J_x1
    H12_nav.leftCols<3>() = H12_nav.leftCols<3>().lazyProduct(A1).eval();
    Matrix15 H22_nav = W_imu;  // J_x1^T W J_x1
    H22_nav.topLeftCorner<3, 3>() = A1.transpose() * W_imu.topLeftCorner<3, 3>() * A1;
    tsif::Vector15 b2_nav = W_imu * e.r;  // J_x1^T W r
    b2_nav.head<3>() = (A1.transpose() * b2_nav.head<3>()).eval();
    addNavBlock(H11, e.J_x0.transpose().lazyProduct(WJ0));
    addNavBlock(H12, H12_nav);
    addNavBlock(H22, H22_nav);
    addNavVector(b1, WJ0.transpose() * e.r);
    addNavVector(b2, b2_nav);

    // Feet: r = d_{i,k+1} - d_{i,k} (a sole's Log(R_F,k^T R_F,k+1)), Jacobians -I and I.
    for (int j = 0; j < kFeet; ++j) {
      const int f = footIndex(j);
      const Eigen::Vector3d r = isSole(j) ? R_F1[j - kFlatFeet].rminus(R_F0[j - kFlatFeet])
                                          : Eigen::Vector3d(x1.d[j] - x0.d[j]);
      H11.block<3, 3>(f, f).diagonal().array() += w_c[j];
      H22.block<3, 3>(f, f).diagonal().array() += w_c[j];
      H12.block<3, 3>(f, f).diagonal().array() -= w_c[j];
      b1.segment<3>(f) -= w_c[j] * r;
      b2.segment<3>(f) += w_c[j] * r;
    }

    // Kinematics of the stance feet at k+1, over (dtheta, dp, dd_i) of x1, and their soles over
    // (dtheta, dphi_i).
    H_kin.setZero();
    for (int i = 0; i < kFeet; ++i) {
      if (kinematics[i]) addKinematics(x1, i, *contact[i], W_kin[i], H_kin, b2);
      if (sole_used[i]) addSole(x1, R_F1[i], i, *contact[i], W_sole[i], H_kin, b2);
    }
    H22 += H_kin;

    if (params_.imu.gyro_bias_random_walk == 0.0) shareBias(kBg, H11, H12, H22, b1, b2);
    if (params_.imu.accel_bias_random_walk == 0.0) shareBias(kBa, H11, H12, H22, b1, b2);

    // Eliminate x0 with H11 = L L^T: Y = L^-1 H12, z = L^-1 b1, and the reduced (marginal)
    // information S = H22 - H12^T H11^-1 H12 = H22 - Y^T Y, which gives the step of x1.
    const Eigen::LLT<Matrix27> llt11(H11);
    Matrix27 Y = H12;
    llt11.matrixL().solveInPlace(Y);
    Vector27 z = b1;
    llt11.matrixL().solveInPlace(z);
    Matrix27 S = H22;
    S.selfadjointView<Eigen::Lower>().rankUpdate(Y.transpose(), -1.0);
    S = S.selfadjointView<Eigen::Lower>();
    const Eigen::LLT<Matrix27> llt22(S);
    if (llt11.info() != Eigen::Success || llt22.info() != Eigen::Success) {
      // The contract's failed update: the step is not taken; the filter restarts from its
      // estimate before it, and the sample counts as a first sample.
      health_.record(Fault::kUpdateFailed, in.t);
      restart(estimate());
      finishStep(in, imu_admitted);
      return;
    }
    const Vector27 b = b2 - Y.transpose() * z;  // b2 - H21 H11^-1 b1
    Vector27 dx1 = -llt22.solve(b);             // S dx1 = -b
    if (alpha > 0.0 && feet_used) {
      // The heading rule: dx1 <- (I - alpha E) dx1, the feet's and the soles' step alike.
      const Heading h = heading(x1, R_F1, params_.flat_feet);
      dx1 -= alpha * h.V * (h.B.transpose() * dx1);
    }
    Vector27 dx0 = -(z + Y * dx1);  // H11 dx0 = -(b1 + H12 dx1)
    llt11.matrixU().solveInPlace(dx0);
    // A shared (constant) bias moves in both states.
    if (params_.imu.gyro_bias_random_walk == 0.0) dx0.segment<3>(kBg) = dx1.segment<3>(kBg);
    if (params_.imu.accel_bias_random_walk == 0.0) dx0.segment<3>(kBa) = dx1.segment<3>(kBa);
    x0 = plus(x0, dx0, params_.flat_feet, R_F0);
    x1_linearised = x1;
    R_F1_linearised = R_F1;
    x1 = plus(x1, dx1, params_.flat_feet, R_F1);
    dx1_last = dx1;
    ++last_iterations_;
    last_step_norm2_ = dx1.dot(S.selfadjointView<Eigen::Lower>() * dx1);
    if (last_step_norm2_ < params_.step_tolerance) break;
  }

  x1.R = lie::SO3d::fromQuaternion(x1.R.quaternion());  // remove rounding drift
  x_ = x1;
  foot_R_ = R_F1;
  // The new information: S again, but in covariance form (betweenMarginal), where rounding does
  // not eat the small information of the unobservable states.
  Matrix27 P_pred;  // its inverse, the covariance of the IMU prediction
  Lambda_ = betweenMarginal(H_prior, e, params_.imu, dt, foot_variance_density, forgotten, &P_pred);
  if (alpha > 0.0 && feet_used) {
    // The heading rule's covariance, P+ = P_opt + alpha^2 V C V^T (eskf.hpp: P - Q + E Q E^T, with
    // Q = P_pred - P_opt and E = V B^T), C = B^T Q B the 2 x 2 that the feet took from the
    // heading, in information form by the inversion lemma: Lambda+ = Lambda_opt - Lambda_opt V
    // C (I + V^T Lambda_opt V C)^-1 V^T Lambda_opt. A forgotten foot (no information yet) is
    // decoupled from the heading: an identity block stands in for it in P_pred.
    const Heading h = heading(x1_linearised, R_F1_linearised, params_.flat_feet);
    const Matrix27 Lambda_opt = Lambda_ + H_kin;
    // Lambda_pred^-1 B = P_pred B: betweenMarginal's M gives it without a factorisation.
    const Eigen::Matrix<double, kDim, 2> PB_pred = P_pred.lazyProduct(h.B);
    const Eigen::Matrix<double, kDim, 2> PB_opt = Lambda_opt.llt().solve(h.B);
    Eigen::Matrix2d C = h.B.transpose() * (PB_pred - PB_opt);
    C = (0.5 * alpha * alpha) * (C + C.transpose()).eval();  // alpha^2 C: K' = (I - alpha E) K
    const Eigen::Matrix<double, kDim, 2> LV = Lambda_opt.lazyProduct(h.V);
    const Eigen::Matrix2d inner = Eigen::Matrix2d::Identity() + h.V.transpose() * LV * C;
    const Eigen::Matrix<double, kDim, 2> LVK = LV * (C * inner.inverse());
    Lambda_ = Lambda_opt - LVK.lazyProduct(LV.transpose());
  } else {
    Lambda_ += H_kin;
  }
  // That information is in the tangent at x1 before its step; moved to the tangent at x1 (+) dx1
  // (the ESKF's reset): dtheta+ = G dtheta, G = I - [dtheta1 / 2]_x, so Lambda <- G^-T Lambda G^-1
  // (and so on each flat foot's sole, G = I - [dphi1 / 2]_x).
  const auto moveTangent = [&](int at) {
    const Eigen::Matrix3d G_inv =
        (Eigen::Matrix3d::Identity() - lie::hat3(Eigen::Vector3d(0.5 * dx1_last.segment<3>(at))))
            .inverse();
    Lambda_.middleCols<3>(at) = Lambda_.middleCols<3>(at).lazyProduct(G_inv).eval();
    Lambda_.middleRows<3>(at) = G_inv.transpose().lazyProduct(Lambda_.middleRows<3>(at)).eval();
  };
  moveTangent(kTheta);
  for (int i = 0; params_.flat_feet && i < kFlatFeet; ++i) moveTangent(rotationIndex(i));
  Lambda_ = 0.5 * (Lambda_ + Lambda_.transpose()).eval();
  for (int i = 0; i < kFeet; ++i) holdContact(i, contact[i]);
  finishStep(in, imu_admitted);
}

void Tsif::placeFoot(int i, const ContactMeasurement& c, Matrix27& Lambda, State& x, Soles& R_F) {
  forgetBlock(Lambda, footIndex(i));
  x.d[i] = x.p + x.R * c.p_body;                                  // d = p + R p_body
  rotation_held_[i] = params_.flat_feet && c.R_body.has_value();  // flat: i < kFlatFeet
  if (!rotation_held_[i]) return;
  forgetBlock(Lambda, rotationIndex(i));
  R_F[i] = lie::SO3d::fromQuaternion(Eigen::Quaterniond(x.R.matrix() * *c.R_body));  // R_F = R Z
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
  if (!guard_.check(estimate(), Lambda_, params_.limits)) recover(in.t);
}

EstimateSample Tsif::estimate() const {
  return {t_, x_.R.quaternion(), x_.v, x_.p};
}

std::optional<BaseCovariance> Tsif::covariance() const {
  // P = Lambda^-1, of which only the first 9 columns are needed.
  const Eigen::Matrix<double, kDim, 9> E = Eigen::Matrix<double, kDim, 9>::Identity();
  const Eigen::Matrix<double, 9, 9> P_local = Lambda_.llt().solve(E).topRows<9>();
  // dtheta_w = R_hat dtheta (local to world), v and p unchanged.
  Eigen::Matrix<double, 9, 9> T = Eigen::Matrix<double, 9, 9>::Identity();
  T.topLeftCorner<3, 3>() = x_.R.matrix();
  BaseCovariance cov;
  cov.P = T * P_local * T.transpose();
  cov.P = 0.5 * (cov.P + cov.P.transpose()).eval();
  return cov;
}

}  // namespace legkit::invariant
