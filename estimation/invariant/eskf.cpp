#include "estimation/invariant/eskf.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "estimation/contact/soft_contact.hpp"
#include "lie/imu_dynamics.hpp"

namespace legkit::invariant {

namespace eskf {

namespace {
using Matrix3 = Eigen::Matrix3d;
using Vector3 = Eigen::Vector3d;
}  // namespace

Matrix27 errorDynamics(const State& x, const model::ImuReading& u) {
  const Vector3 w = u.w_m - x.b_g;
  const Vector3 f = u.a_m - x.b_a;
  const Matrix3& R = x.R.matrix();
  Matrix27 F = Matrix27::Zero();
  F.block<3, 3>(kTheta, kTheta) = -lie::hat3(w);      // d(dtheta)/dt = -[w]_x dtheta
  F.block<3, 3>(kTheta, kBg) = -Matrix3::Identity();  //              - db_g
  F.block<3, 3>(kV, kTheta) = -R * lie::hat3(f);      // d(dv)/dt = -R_hat [f]_x dtheta
  F.block<3, 3>(kV, kBa) = -R;                        //          - R_hat db_a
  F.block<3, 3>(kP, kV) = Matrix3::Identity();        // d(dp)/dt = dv
  return F;
}

Matrix27 Transition::matrix() const {
  Matrix27 Phi = Matrix27::Identity();
  Phi.topLeftCorner<9, 9>() = nav;
  Phi.block<9, 6>(0, kBg) = bias;
  return Phi;
}

Transition transition(const State& x, const model::ImuReading& u, double dt) {
  const Vector3 phi = (u.w_m - x.b_g) * dt;
  const Vector3 f = u.a_m - x.b_a;
  const lie::AngleSeries<double> c(phi.squaredNorm());
  const Matrix3 Gamma1 = lie::Gamma<1>(phi);
  const Matrix3 Gamma2 = lie::Gamma<2>(phi);
  const Matrix3& R = x.R.matrix();
  const Matrix3 I = Matrix3::Identity();
  const double dt2 = dt * dt;

  Transition T;
  T.nav.setIdentity();
  // R Exp(dtheta) Exp(phi) = R Exp(phi) Exp(Exp(phi)^T dtheta).
  T.nav.block<3, 3>(kTheta, kTheta) = lie::SO3d::Exp(phi).matrix().transpose();
  // R Exp(dtheta) y = R y - R [y]_x dtheta, for y the body-frame increments of v and p.
  T.nav.block<3, 3>(kV, kTheta) = -R * lie::hat3(Vector3(Gamma1 * f * dt));
  T.nav.block<3, 3>(kP, kTheta) = -R * lie::hat3(Vector3(Gamma2 * f * dt2));
  T.nav.block<3, 3>(kP, kV) = dt * I;
  // db_g moves phi by -db_g dt: Exp(phi - d dt) = Exp(phi) Exp(-Jr(phi) d dt), and the
  // increments by their derivatives in phi; db_a enters the increments linearly.
  T.bias.block<3, 3>(kTheta, 0) = -lie::SO3d::Jr(phi) * dt;
  T.bias.block<3, 3>(kTheta, 3).setZero();
  T.bias.block<3, 3>(kV, 0) = -R * lie::imu::dGammaTimesVector<1>(phi, f, c) * dt2;
  T.bias.block<3, 3>(kV, 3) = -R * Gamma1 * dt;
  T.bias.block<3, 3>(kP, 0) = -R * lie::imu::dGammaTimesVector<2>(phi, f, c) * (dt2 * dt);
  T.bias.block<3, 3>(kP, 3) = -R * Gamma2 * dt2;
  return T;
}

}  // namespace eskf

using eskf::kBa;
using eskf::kBg;
using eskf::kDim;
using eskf::kFeet;
using eskf::kFlatFeet;
using eskf::kFootRotationPrior;
using eskf::kP;
using eskf::kTheta;
using eskf::kV;
using eskf::Matrix27;
using eskf::rotationIndex;
using eskf::Vector27;

namespace {

using Matrix3 = Eigen::Matrix3d;
using Vector3 = Eigen::Vector3d;
using Matrix27x3 = Eigen::Matrix<double, kDim, 3>;

void requireParam(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("Eskf: ") + what);
}

}  // namespace

Eskf::Eskf(const EskfParams& params)
    : params_(params),
      gate_(params.gating, "Eskf"),
      heading_(params.heading_turn_rate, params.heading_turn_time),
      pose_gate_(fusion::poseGateThreshold(params.gating)),
      slots_(params.flat_feet ? kFlatFeet : kFeet) {
  checkFilterParams(params, "Eskf", false);  // zero densities: exact legs, constant bias
  requireParam(params.foot_init_sigma > 0.0 && std::isfinite(params.foot_init_sigma),
               "foot_init_sigma must be positive and finite");
  reset(EstimateSample{});
}

void Eskf::reset(const EstimateSample& x0) {
  x_ = eskf::State{};
  x_.R = lie::SO3d::fromQuaternion(x0.q);
  x_.v = x0.v;
  x_.p = x0.p;
  for (Vector3& d : x_.d) d = x0.p;  // unknown until touchdown
  const auto variance = [](double sigma) { return sigma * sigma; };
  Vector27 diag;
  diag.segment<3>(kTheta).setConstant(variance(params_.sigma_attitude));
  diag.segment<3>(kV).setConstant(variance(params_.sigma_velocity));
  diag.segment<3>(kP).setConstant(variance(params_.sigma_position));
  diag.segment<3 * kFeet>(eskf::kD).setConstant(variance(params_.foot_init_sigma));
  if (params_.flat_feet) {
    diag.segment<3 * kFlatFeet>(rotationIndex(0)).setConstant(variance(kFootRotationPrior));
  }
  diag.segment<3>(kBg).setConstant(variance(params_.sigma_gyro_bias));
  diag.segment<3>(kBa).setConstant(variance(params_.sigma_accel_bias));
  P_ = diag.asDiagonal();
  in_contact_.fill(false);
  probability_.fill(0.0);
  foot_R_.fill(lie::SO3d{});
  rotation_held_.fill(false);
  slots_.reset();
  gate_.reset();
  heading_.reset();
  nis_windows_.reset();
  startHealth(x0);
  t_ = x0.t;
  previous_ = model::ImuReading{};
  has_previous_ = false;
}

void Eskf::initialise(const InitialState& s) {
  checkInitialState(s, name());
  reset(s.x);
  x_.b_g = s.b_g;
  x_.b_a = s.b_a;
  if (std::isnan(s.sigma_tilt)) return;
  // World-frame prior diag(sigma_tilt^2, sigma_tilt^2, sigma_yaw^2), in the local error:
  // dtheta = R_hat^T dtheta_w (covariance() inverts this).
  const Vector3 sigma2(s.sigma_tilt * s.sigma_tilt, s.sigma_tilt * s.sigma_tilt,
                       params_.sigma_attitude * params_.sigma_attitude);
  const Matrix3& R = x_.R.matrix();
  P_.block<3, 3>(kTheta, kTheta) = R.transpose() * sigma2.asDiagonal() * R;
}

void Eskf::predict(double dt) {
  const eskf::Transition Phi = eskf::transition(x_, previous_, dt);
  eskf::transformNavigation(P_, Phi.nav, Phi.bias);  // P <- Phi P Phi^T

  // P <- P + Q (file comment).
  const model::ImuNoise& n = params_.imu;
  const double var_a = n.accel_noise_density * n.accel_noise_density;
  const auto addDiagonal = [&](int at, double variance) {
    P_.block<3, 3>(at, at).diagonal().array() += variance;
  };
  addDiagonal(kTheta, n.gyro_noise_density * n.gyro_noise_density * dt);
  addDiagonal(kV, var_a * dt);
  addDiagonal(kP, var_a * dt * dt * dt / 3.0);
  P_.block<3, 3>(kV, kP).diagonal().array() += var_a * dt * dt / 2.0;
  P_.block<3, 3>(kP, kV).diagonal().array() += var_a * dt * dt / 2.0;
  const double sw = params_.foot_swing_density;
  const auto footDensity = [&](int i, double stance, double swing) {
    // sigma^2: the swing density, or in contact the soft one of p_c (Q_f of 57.6)
    return in_contact_[i] ? contact::softFootNoiseDensity(probability_[i], stance, swing)
                          : swing * swing;
  };
  for (int i = 0; i < numPointFeet(); ++i) {
    addDiagonal(eskf::footIndex(i), footDensity(i, params_.foot_stance_density, sw) * dt);
  }
  for (int i = 0; params_.flat_feet && i < kFlatFeet; ++i) {
    addDiagonal(rotationIndex(i), footDensity(i, params_.foot_rotation_stance_density,
                                              params_.foot_rotation_swing_density) *
                                      dt);
  }
  addDiagonal(kBg, n.gyro_bias_random_walk * n.gyro_bias_random_walk * dt);
  addDiagonal(kBa, n.accel_bias_random_walk * n.accel_bias_random_walk * dt);

  x_ = eskf::propagate(x_, previous_, dt, params_.gravity);
}

Eskf::Update Eskf::updateFoot(int i, const ContactMeasurement& c, double t, Vector27& dx) {
  eskf::Matrix39 H;  // h_i = R^T (d_i - p) over (dtheta, dp, dd_i)
  const Vector3 h = eskf::footInBody(x_, i, &H);
  return correct<3>(i, {kTheta, kP, eskf::footIndex(i)}, H, c.p_body - h, c.cov, t,
                    Measured::kPosition, c.probability, dx);
}

Eskf::Update Eskf::updateFootRotation(int i, const ContactMeasurement& c, double t, Vector27& dx) {
  // h = R^T R_F; r = Log(h_hat^T Z) = dphi_i - h_hat^T dtheta + n (file comment, "Flat feet").
  Eigen::Matrix<double, 3, 6> H;  // over (dtheta, dphi_i)
  const Vector3 r = eskf::soleResidual(x_.R, foot_R_[i], *c.R_body, &H);
  return correct<2>(i, {kTheta, rotationIndex(i)}, H, r, c.rot_cov, t, Measured::kRotation,
                    c.probability, dx);
}

template <int Blocks>
Eskf::Update Eskf::correct(int i, const std::array<int, Blocks>& cols,
                           const Eigen::Matrix<double, 3, 3 * Blocks>& H, const Vector3& residual,
                           const Matrix3& cov, double t, Measured measured, double probability,
                           Vector27& dx) {
  const bool position = measured == Measured::kPosition;
  const auto Hblock = [&](int k) { return H.template block<3, 3>(0, 3 * k); };

  // P H^T (27 x 3) from H's non-zero blocks.
  Matrix27x3 PHt = Matrix27x3::Zero();
  for (int k = 0; k < Blocks; ++k)
    PHt.noalias() += P_.middleCols<3>(cols[k]).lazyProduct(Hblock(k).transpose());
  Matrix3 S = cov;  // S = H P H^T + Cov
  for (int k = 0; k < Blocks; ++k) S.noalias() += Hblock(k) * PHt.middleRows<3>(cols[k]);
  // K = P H^T S^-1 through S = L L^T; a failed factorisation skips the update (the contract).
  const Eigen::LLT<Matrix3> llt(S);
  if (llt.info() != Eigen::Success) return Update::kFailed;

  // Innovation against the error mean accumulated so far: z - h(x_hat) - H dx.
  Vector3 r = residual;
  for (int k = 0; k < Blocks; ++k) r.noalias() -= Hblock(k) * dx.segment<3>(cols[k]);
  if (position && gate_.enabled()) {
    // d^2 = r^T S^-1 r = |L^-1 r|^2 against the chi-square gate (57.9)
    const double d2 = llt.matrixL().solve(r).squaredNorm();
    const engineering::FootGate::Decision decision = gate_.decide(i, d2, t);
    if (decision == engineering::FootGate::Decision::kGate) return Update::kGated;
    if (decision == engineering::FootGate::Decision::kReinitialise) return Update::kReinitialise;
  }
  if (position && probability >= kNisMinProbability) nis_windows_.add(i, r, S, innovations_);
  Matrix27x3 K = PHt.lazyProduct(llt.solve(Matrix3::Identity()));
  // The rule is every foot update's, a sole's rotation too (file comment, "Flat feet").
  const double alpha = params_.feet_correct_yaw ? 0.0 : heading_.alpha();
  if (alpha > 0.0) {
    // The heading stays the gyro's (file comment): K <- (I - alpha E) K. E K is the heading row
    // psi = up^T K_theta (up = R_hat^T e_z, the vertical in the local error) times the turn of the
    // robot about its base (up on the attitude, e_z x v on the velocity, e_z x (d_i - p) on the
    // feet, R_F^T e_z on a flat foot's rotation), and the gyro bias's part along up; alpha the
    // rule's share by the turn rate (heading_rule.hpp).
    const Vector3 up = x_.R.matrix().row(2).transpose();
    const Eigen::RowVector3d psi = alpha * up.transpose() * K.middleRows<3>(kTheta);
    const auto turned = [](const Vector3& x) { return Vector3(-x.y(), x.x(), 0.0); };  // e_z x x
    K.middleRows<3>(kTheta) -= up * psi;
    K.middleRows<3>(kV) -= turned(x_.v) * psi;
    for (int j = 0; j < numPointFeet(); ++j) {
      K.middleRows<3>(eskf::footIndex(j)) -= turned(x_.d[j] - x_.p) * psi;
    }
    for (int j = 0; params_.flat_feet && j < kFlatFeet; ++j) {
      K.middleRows<3>(rotationIndex(j)) -= foot_R_[j].matrix().row(2).transpose() * psi;
    }
    K.middleRows<3>(kBg) -= alpha * up * (up.transpose() * K.middleRows<3>(kBg));
  }
  dx.noalias() += K * r;

  // Joseph form (I - K H) P (I - K H)^T + K Cov K^T with A = (I - K H) P = P - K (P H^T)^T:
  // P = A - (A H^T) K^T + K Cov K^T = A + (K Cov - A H^T) K^T, two rank-3 products.
  Matrix27 A = P_;
  A.noalias() -= K.lazyProduct(PHt.transpose());
  Matrix27x3 B = K.lazyProduct(cov);  // K Cov - A H^T
  for (int k = 0; k < Blocks; ++k)
    B.noalias() -= A.middleCols<3>(cols[k]).lazyProduct(Hblock(k).transpose());
  A.noalias() += B.lazyProduct(K.transpose());
  P_ = 0.5 * (A + A.transpose());
  return Update::kDone;
}

fusion::PoseUpdate Eskf::updatePose(const fusion::PoseMeasurement& z) {
  fusion::checkPoseMeasurement(z, "Eskf");
  if (!z.valid) return fusion::PoseUpdate::kNotValid;
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  using Matrix27x6 = Eigen::Matrix<double, kDim, 6>;
  const Matrix3& R = x_.R.matrix();
  // r = (Log(R_m R_hat^T), p_m - p_hat), H = [R_hat (dtheta); I (dp)] (file comment).
  Vector6 r;
  r << lie::SO3d::fromQuaternion(Eigen::Quaterniond(z.R_MB.matrix() * R.transpose())).Log(),
      z.p_MB - x_.p;
  Matrix27x6 PHt;  // P H^T
  PHt.leftCols<3>().noalias() = P_.middleCols<3>(kTheta).lazyProduct(R.transpose());
  PHt.rightCols<3>() = P_.middleCols<3>(kP);
  Matrix6 S = z.cov;  // S = H P H^T + N
  S.topRows<3>().noalias() += R.lazyProduct(PHt.middleRows<3>(kTheta));
  S.bottomRows<3>() += PHt.middleRows<3>(kP);
  const Eigen::LLT<Matrix6> llt(S);
  if (llt.info() != Eigen::Success) {
    health_.record(Fault::kUpdateFailed, z.t);
    return fusion::PoseUpdate::kFailed;
  }
  // d^2 = r^T S^-1 r = |L^-1 r|^2 against the 6-dof gate
  if (params_.gating.enabled && llt.matrixL().solve(r).squaredNorm() > pose_gate_) {
    health_.record(Fault::kGated, z.t);
    return fusion::PoseUpdate::kGated;
  }
  const Matrix27x6 K = PHt.lazyProduct(llt.solve(Matrix6::Identity()));
  const Vector27 dx = K * r;
  // Joseph form as for a foot: A = P - K (P H^T)^T, P = A + (K N - A H^T) K^T.
  Matrix27 A = P_;
  A.noalias() -= K.lazyProduct(PHt.transpose());
  Matrix27x6 B = K.lazyProduct(z.cov);
  B.leftCols<3>().noalias() -= A.middleCols<3>(kTheta).lazyProduct(R.transpose());
  B.rightCols<3>() -= A.middleCols<3>(kP);
  A.noalias() += B.lazyProduct(K.transpose());
  P_ = 0.5 * (A + A.transpose());
  inject(dx);
  return fusion::PoseUpdate::kUsed;
}

void Eskf::inject(const Vector27& dx) {
  Vector27 dx_points = dx;  // x_hat <- x_hat (+) dx_hat
  if (params_.flat_feet) {
    dx_points.segment<3 * kFlatFeet>(rotationIndex(0)).setZero();
    for (int i = 0; i < kFlatFeet; ++i) {  // R_F <- R_F Exp(dphi_hat), as the attitude
      foot_R_[i] = lie::SO3d::fromQuaternion(Eigen::Quaterniond(
          foot_R_[i].matrix() * lie::SO3d::Exp(dx.segment<3>(rotationIndex(i))).matrix()));
    }
  }
  x_ = x_.plus(dx_points);
  // Reset: P <- G P G^T, G = blockdiag(I - [dtheta_hat / 2]_x, I, ...) (and I - [dphi_hat / 2]_x
  // on a flat foot's rotation).
  eskf::resetRotation(P_, kTheta, dx.segment<3>(kTheta));
  for (int i = 0; params_.flat_feet && i < kFlatFeet; ++i)
    eskf::resetRotation(P_, rotationIndex(i), dx.segment<3>(rotationIndex(i)));
}

void Eskf::initialiseFoot(int i, const ContactMeasurement& c) {
  eskf::placeFoot(x_, P_, i, c.p_body, c.cov);  // d_i = p + R z_i (nominal_state.hpp)
  rotation_held_[i] = params_.flat_feet && c.R_body.has_value();  // flat: i < kFlatFeet
  // A flat foot: R_F = R_hat Z, and dphi_i = Z^T dtheta - n (file comment, "Flat feet").
  if (rotation_held_[i]) foot_R_[i] = eskf::placeSole(x_.R, P_, i, *c.R_body, c.rot_cov);
}

void Eskf::step(const StepInput& raw) {
  InputCopies copies;
  const auto [in, imu_admitted] = admit(raw, has_previous_, params_.limits, "Eskf", copies, slots_);

  if (has_previous_ && in.dt > 0.0) {
    predict(in.dt);
    heading_.add(yawRate(x_.R.matrix(), previous_.w_m, x_.b_g), in.dt, in.slip);
  }

  // Feet in stance at the previous sample and now are measurements; the others touch down.
  Vector27 dx = Vector27::Zero();
  bool updated = false;
  for (const ContactMeasurement& c : in.stance()) {
    if (!in_contact_[c.foot]) continue;
    switch (updateFoot(c.foot, c, in.t, dx)) {
      case Update::kDone:
        updated = true;
        if (rotation_held_[c.foot] && c.R_body &&
            updateFootRotation(c.foot, c, in.t, dx) == Update::kFailed) {
          health_.record(Fault::kUpdateFailed, in.t);
        }
        break;
      case Update::kFailed:
        health_.record(Fault::kUpdateFailed, in.t);
        break;
      case Update::kGated:
        health_.record(Fault::kGated, in.t);
        break;
      case Update::kReinitialise:  // gated too long: placed anew below, as at a touchdown
        health_.record(Fault::kGated, in.t);
        in_contact_[c.foot] = false;
        break;
    }
  }
  if (updated) inject(dx);
  nis_windows_.endStep(innovations_);

  std::array<bool, kFeet> stance{};
  std::array<double, kFeet> probability{};
  for (const ContactMeasurement& c : in.stance()) {
    stance[c.foot] = true;
    probability[c.foot] = c.probability;
    if (!in_contact_[c.foot]) initialiseFoot(c.foot, c);
  }
  for (int i = 0; i < kFeet; ++i)
    if (!stance[i]) gate_.clear(i);  // lifted off: its gate clock stops
  in_contact_ = stance;
  probability_ = probability;
  if (imu_admitted) {
    previous_ = in.imu;
    has_previous_ = true;
  }
  t_ = in.t;
  if (!guard_.check(estimate(), P_, params_.limits)) recover(in.t);
}

EstimateSample Eskf::estimate() const {
  return {t_, x_.R.quaternion(), x_.v, x_.p};
}

std::optional<BaseCovariance> Eskf::covariance() const {
  BaseCovariance cov;
  cov.P = eskf::worldBaseBlock(P_, x_.R);  // e = J dx, J = blockdiag(R_hat, I, I)
  return cov;
}

}  // namespace legkit::invariant
