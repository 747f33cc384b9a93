#include "estimation/linear_kf/linear_kf.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <lie/so3.hpp>
#include <sstream>
#include <stdexcept>
#include <string>

#include "estimation/contact/soft_contact.hpp"
#include "estimation/fixed_size.hpp"
#include "estimation/leg_odometry/base_velocity.hpp"

namespace legkit::linear_kf {
namespace {

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("LinearKf: ") + what);
}

// The 3-row blocks of one sample's stacked measurement (LinearKf::updateStance): the stance feet
// first, then the velocity if any.
struct Stack {
  std::array<int, kFeet + 1> at{};             // H_b reads x at at[b]: d_i (minus p), or v
  std::array<Eigen::Vector3d, kFeet + 1> z;    // z_b, the measured world vector
  std::array<Eigen::Matrix3d, kFeet + 1> own;  // Own_b, the block's noise without attitude
  std::array<Eigen::Matrix3d, kFeet> with_v;   // R_(i, v) without attitude: shared dr_i
  int feet = 0;
  int blocks = 0;
};

// Per block of a stacked update, its innovation and the marginal of its innovation covariance.
struct BlockInnovations {
  std::array<Eigen::Vector3d, kFeet + 1> y;
  std::array<Eigen::Matrix3d, kFeet + 1> S;
};

// K = N S^-1 from the Cholesky factor L of S (S = L L^T, the lower triangle of `llt`): K^T solves
// L L^T K^T = N^T by forward then back substitution, row operations on K^T (row-major, each an
// AXPY of length 18 at a size known to the compiler). Eigen's LLT::solve gives the same numbers
// (to rounding) through its general triangular solver, which packs and blocks its operands as for
// large matrices: on bench_linear_kf that took 11k of the step's 41.5k instructions, and the step
// takes 35.5k with this loop (callgrind, 2026-11-29).
template <int M>
Eigen::Matrix<double, kDim, M> gainFromCholesky(const Eigen::Matrix<double, M, M>& llt,
                                                const Eigen::Matrix<double, kDim, M>& N) {
  Eigen::Matrix<double, M, kDim, Eigen::RowMajor> Kt = N.transpose();
  for (int i = 0; i < M; ++i) {  // L Y = N^T
    for (int j = 0; j < i; ++j) Kt.row(i) -= llt(i, j) * Kt.row(j);
    Kt.row(i) /= llt(i, i);
  }
  for (int i = M - 1; i >= 0; --i) {  // L^T K^T = Y
    for (int j = i + 1; j < M; ++j) Kt.row(i) -= llt(j, i) * Kt.row(j);
    Kt.row(i) /= llt(i, i);
  }
  return Kt.transpose();
}

// One update with all M = 3 * stack.blocks rows and the full R (linear_kf.hpp), fixed-size.
// False (nothing changed) when S does not factorise; else each block's innovation y_b and its
// marginal S_bb in *blocks (the stance-foot NIS).
template <int M>
bool stackedUpdate(Vector18& x, Matrix18& P, const Stack& st, const Eigen::Matrix3d& Sigma_theta,
                   BlockInnovations* blocks) {
  constexpr int kBlocks = M / 3;
  // H_b picks rows (of x, of N) or columns (of P): d_i - p for a foot, v for the velocity.
  const auto rowsOf = [&](int b, const auto& A) {
    return b < st.feet ? (A.template middleRows<3>(st.at[b]) - A.template middleRows<3>(kP)).eval()
                       : A.template middleRows<3>(st.at[b]).eval();
  };
  Eigen::Matrix<double, M, 1> y;
  Eigen::Matrix<double, kDim, M> N;  // N = P H^T
  for (int b = 0; b < kBlocks; ++b) {
    y.template segment<3>(3 * b) = st.z[b] - rowsOf(b, x);
    N.template middleCols<3>(3 * b) = rowsOf(b, P).transpose();  // P H_b^T = (H_b P)^T
  }
  // S = H N + R with the full R; lower blocks computed, upper ones mirrored.
  Eigen::Matrix<double, M, M> S;
  for (int a = 0; a < kBlocks; ++a) {
    for (int b = 0; b <= a; ++b) {
      Eigen::Matrix3d S_ab = rowsOf(a, N.template middleCols<3>(3 * b)) +
                             attitudeNoiseBlock(st.z[a], st.z[b], Sigma_theta);
      if (a == b) S_ab += st.own[a];
      if (a == st.feet && b < st.feet) S_ab += st.with_v[b].transpose();  // R_(v, i) = R_(i, v)^T
      S.template block<3, 3>(3 * a, 3 * b) = S_ab;
      if (b < a) S.template block<3, 3>(3 * b, 3 * a) = S_ab.transpose();
    }
  }
  const Eigen::LLT<Eigen::Matrix<double, M, M>> llt(S);
  if (llt.info() != Eigen::Success) return false;  // the contract: the update is skipped
  for (int b = 0; b < kBlocks; ++b) {
    blocks->y[b] = y.template segment<3>(3 * b);
    blocks->S[b] = S.template block<3, 3>(3 * b, 3 * b);
  }
  const Eigen::Matrix<double, kDim, M> K = gainFromCholesky<M>(llt.matrixLLT(), N);  // N S^-1
  x.noalias() += K.lazyProduct(y);
  josephUpdate(P, K, N, S);
  return true;
}

}  // namespace

// -- The model's matrices ----------------------------------------------------------------------

Eigen::Matrix<double, 6, 3> inputMatrix(double dt) {
  Eigen::Matrix<double, 6, 3> B;
  B << 0.5 * dt * dt * Eigen::Matrix3d::Identity(), dt * Eigen::Matrix3d::Identity();
  return B;
}

Matrix6 navigationNoise(double dt, const Eigen::Matrix3d& Sigma_u) {
  // B Sigma_u B^T with B = [dt^2/2 I; dt I]
  const double h = 0.5 * dt * dt;
  Matrix6 Q;
  Q << h * h * Sigma_u, h * dt * Sigma_u, h * dt * Sigma_u, dt * dt * Sigma_u;
  return Q;
}

double footNoiseVariance(double dt, bool in_stance, const ProcessNoise& noise, double p_c) {
  const double sw = noise.foot_swing_density;
  // random walk: sigma_d^2 dt, the stance density softened by p_c (Q_f of 57.6)
  const double density =
      in_stance ? contact::softFootNoiseDensity(p_c, noise.foot_stance_density, sw) : sw * sw;
  return density * dt;
}

ProcessModel processModel(double dt, const ContactMask& contact, const ProcessNoise& noise) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw std::invalid_argument("processModel: dt must be positive and finite");
  if (!(noise.accel_density >= 0.0 && noise.foot_stance_density >= 0.0 &&
        noise.foot_swing_density >= 0.0))
    throw std::invalid_argument("processModel: noise densities must be non-negative");
  ProcessModel m;
  m.F.setIdentity();
  m.F.block<3, 3>(kP, kV) = dt * Eigen::Matrix3d::Identity();  // p <- p + v dt
  m.B.setZero();
  m.B.topRows<6>() = inputMatrix(dt);
  m.Q.setZero();
  const double sa2 = noise.accel_density * noise.accel_density;
  m.Q.topLeftCorner<6, 6>() = navigationNoise(dt, sa2 / dt * Eigen::Matrix3d::Identity());
  for (int i = 0; i < kFeet; ++i)
    m.Q.block<3, 3>(footIndex(i), footIndex(i))
        .diagonal()
        .setConstant(footNoiseVariance(dt, contact[i], noise));
  return m;
}

Matrix3x18 footMeasurementMatrix(int i) {
  if (i < 0 || i >= kFeet)
    throw std::invalid_argument("footMeasurementMatrix: foot id " + std::to_string(i) +
                                " is outside 0..3");
  Matrix3x18 H = Matrix3x18::Zero();
  H.block<3, 3>(0, kP) = -Eigen::Matrix3d::Identity();
  H.block<3, 3>(0, footIndex(i)) = Eigen::Matrix3d::Identity();
  return H;
}

Matrix3x18 velocityMeasurementMatrix() {
  Matrix3x18 H = Matrix3x18::Zero();
  H.block<3, 3>(0, kV) = Eigen::Matrix3d::Identity();
  return H;
}

Eigen::Matrix3d footMeasurementNoise(const Eigen::Matrix3d& R_hat, const Eigen::Vector3d& r,
                                     const Eigen::Matrix3d& cov_r,
                                     const Eigen::Matrix3d& Sigma_theta) {
  const Eigen::Matrix3d z_x = lie::hat3(Eigen::Vector3d(R_hat * r));
  return R_hat * cov_r * R_hat.transpose() + z_x * Sigma_theta * z_x.transpose();
}

Eigen::Matrix3d attitudeNoiseBlock(const Eigen::Vector3d& z_a, const Eigen::Vector3d& z_b,
                                   const Eigen::Matrix3d& Sigma_theta) {
  return lie::hat3(z_a) * Sigma_theta * lie::hat3(z_b).transpose();
}

// -- The filter --------------------------------------------------------------------------------

LinearKf::LinearKf(const LinearKfParams& params)
    : params_(params), gate_(params.gating, "LinearKf"), attitude_(params.attitude) {
  const LinearKfParams& p = params;
  require(p.imu.accel_noise_density >= 0.0 && p.imu.gyro_noise_density >= 0.0,
          "IMU noise densities must be non-negative");
  require(
      p.foot_stance_density >= 0.0 && p.foot_swing_density >= 0.0 && p.foot_velocity_sigma >= 0.0,
      "foot densities and foot_velocity_sigma must be non-negative");
  require(p.sigma_position > 0.0 && p.sigma_velocity > 0.0 && p.foot_init_sigma > 0.0,
          "prior sigmas must be positive");
  require(p.attitude_correlation_time > 0.0, "attitude_correlation_time must be positive");
  require(p.accel_compensation_time >= 0.0, "accel_compensation_time must be non-negative");
  require(p.gravity.allFinite() && p.b_a.allFinite(), "gravity and b_a must be finite");
  checkLimits(params.limits, "LinearKf");
  reset(EstimateSample{});
}

void LinearKf::reset(const EstimateSample& x0) {
  attitude_ = AttitudeFilter(params_.attitude);  // its own priors (initialise() may change them)
  attitude_.reset(lie::SO3d::fromQuaternion(x0.q));
  x_.setZero();
  x_.segment<3>(kP) = x0.p;
  x_.segment<3>(kV) = x0.v;
  for (int i = 0; i < kFeet; ++i) x_.segment<3>(footIndex(i)) = x0.p;
  const double sp2 = params_.sigma_position * params_.sigma_position;
  const double sv2 = params_.sigma_velocity * params_.sigma_velocity;
  const double sf2 = params_.foot_init_sigma * params_.foot_init_sigma;
  P_.setZero();
  P_.diagonal() << Eigen::Vector3d::Constant(sp2), Eigen::Vector3d::Constant(sv2),
      Eigen::Matrix<double, 3 * kFeet, 1>::Constant(sf2);
  a_w_.setZero();
  previous_contact_.fill(false);
  previous_probability_.fill(0.0);
  has_previous_ = false;
  t_ = x0.t;
  slots_.reset();
  gate_.reset();
  nis_windows_.reset();
  startHealth(x0);
}

void LinearKf::initialise(const InitialState& s) {
  checkInitialState(s, name());
  reset(s.x);
  params_.b_a = s.b_a;
  AttitudeFilterParams attitude = params_.attitude;
  if (!std::isnan(s.sigma_tilt)) attitude.sigma_tilt = s.sigma_tilt;
  attitude_ = AttitudeFilter(attitude);
  attitude_.reset(lie::SO3d::fromQuaternion(s.x.q), s.b_g);
}

void LinearKf::step(const StepInput& raw) {
  InputCopies copies;
  const auto [in, imu_admitted] =
      admit(raw, has_previous_, params_.limits, "LinearKf", copies, slots_);
  const Eigen::Vector3d v_before = x_.segment<3>(kV);
  if (has_previous_ && in.dt > 0.0) {
    // u = R_hat (a_m - b_a) + g with the attitude at the start of the interval (zero-order hold).
    const Eigen::Vector3d f_w = attitude_.R() * (previous_.a_m - params_.b_a);
    attitude_.propagate(previous_, in.dt, a_w_);
    predict(in.dt, f_w);
  }
  const Eigen::Matrix3d Sigma_theta =
      params_.model_attitude_error ? attitude_.attitudeCovariance() : Eigen::Matrix3d::Zero();
  ContactMask contact{};
  std::array<double, kFeet> probability{};
  for (const ContactMeasurement& c : in.stance()) {
    contact[c.foot] = true;
    probability[c.foot] = c.probability;
  }
  // The velocity measurement needs this sample's rate: the admitted one, else the held one.
  const bool velocity = params_.use_leg_velocity && in.dt > 0.0 && (imu_admitted || has_previous_);
  const Eigen::Vector3d* w_m = velocity ? (imu_admitted ? &in.imu.w_m : &previous_.w_m) : nullptr;
  if (!updateStance(in, w_m, Sigma_theta)) health_.record(Fault::kUpdateFailed, in.t);
  if (params_.accel_compensation_time > 0.0 && has_previous_ && in.dt > 0.0) {
    // a_w <- a_w + (dv / dt - a_w) dt / T: first-order low-pass of the velocity's rate of change.
    const double T = std::max(params_.accel_compensation_time, in.dt);
    a_w_ += (x_.segment<3>(kV) - v_before - a_w_ * in.dt) / T;
  }
  for (int i = 0; i < kFeet; ++i)
    if (!contact[i]) gate_.clear(i);  // lifted off: its gate clock stops
  previous_contact_ = contact;
  previous_probability_ = probability;
  if (imu_admitted) {
    previous_ = in.imu;
    has_previous_ = true;
  }
  t_ = in.t;
  if (!guard_.check(estimate(), P_, params_.limits)) recover(in.t);
}

void LinearKf::predict(double dt, const Eigen::Vector3d& f_w) {
  // x+ = F x + B u:  p += v dt + u dt^2/2,  v += u dt,  feet unchanged.
  const Eigen::Vector3d u = f_w + params_.gravity;
  x_.segment<3>(kP) += dt * x_.segment<3>(kV) + 0.5 * dt * dt * u;
  x_.segment<3>(kV) += dt * u;

  // F P F^T with F = I + dt E, E taking v into p: only the rows and columns of p change,
  //   P_pp <- P_pp + dt (P_pv + P_vp) + dt^2 P_vv,   P_pj <- P_pj + dt P_vj (j not p),
  // written so that P stays exactly symmetric.
  const Eigen::Matrix3d P_pv = P_.block<3, 3>(kP, kV);
  P_.block<3, 3>(kP, kP) += dt * (P_pv + P_pv.transpose()) + (dt * dt) * P_.block<3, 3>(kV, kV);
  P_.block<3, kDim - 3>(kP, kV) += dt * P_.block<3, kDim - 3>(kV, kV);
  P_.block<kDim - 3, 3>(kV, kP) = P_.block<3, kDim - 3>(kP, kV).transpose();

  // + Q: navigation block B Sigma_u B^T, then each foot's random walk.
  const double sa2 = params_.imu.accel_noise_density * params_.imu.accel_noise_density;
  Eigen::Matrix3d Sigma_u = Eigen::Matrix3d::Identity() * (sa2 / dt);
  if (params_.model_attitude_error) {
    // The input is off by [f_w]_x theta, a correlated error: white density 2 tau C.
    const Eigen::Matrix3d f_x = lie::hat3(f_w);
    const Eigen::Matrix3d C = f_x * attitude_.attitudeCovariance() * f_x.transpose();
    Sigma_u += (params_.attitude_correlation_time / dt) * (C + C.transpose());  // 2 tau C / dt
  }
  P_.topLeftCorner<6, 6>() += navigationNoise(dt, Sigma_u);
  const ProcessNoise noise = params_.processNoise();
  for (int i = 0; i < kFeet; ++i) {
    const int d = footIndex(i);
    P_.block<3, 3>(d, d).diagonal().array() +=
        footNoiseVariance(dt, previous_contact_[i], noise, previous_probability_[i]);
  }
}

bool LinearKf::updateStance(const StepInput& in, const Eigen::Vector3d* w_m,
                            const Eigen::Matrix3d& Sigma_theta) {
  const Eigen::Matrix3d& R_hat = attitude_.R().matrix();
  const leg_odometry::ContactSpan stance = in.stance();
  // The gate (file comment): a foot that fails it is left out of everything below.
  std::array<bool, leg_odometry::kMaxContacts> used{};
  for (std::size_t j = 0; j < stance.size(); ++j) {
    used[j] = true;
    if (!gate_.enabled()) continue;
    const ContactMeasurement& c = stance[j];
    const int d = footIndex(c.foot);
    const Eigen::Vector3d z = R_hat * c.p_body;
    const Eigen::Vector3d y = z - (x_.segment<3>(d) - x_.segment<3>(kP));
    const Eigen::Matrix3d own = R_hat * c.cov * R_hat.transpose();
    // S_ii = P_dd - P_dp - P_pd + P_pp + R_ii
    const Eigen::Matrix3d S = P_.block<3, 3>(d, d) - P_.block<3, 3>(d, kP) - P_.block<3, 3>(kP, d) +
                              P_.block<3, 3>(kP, kP) + own + attitudeNoiseBlock(z, z, Sigma_theta);
    const engineering::FootGate::Decision decision = gateBlock(c.foot, y, S, in.t);
    used[j] = decision == engineering::FootGate::Decision::kUse;
    if (decision == engineering::FootGate::Decision::kReinitialise) {
      health_.record(Fault::kGated, in.t);
      placeFoot(c.foot, z, own + attitudeNoiseBlock(z, z, Sigma_theta));
    }
  }
  // The velocity: the base velocity of the stance feet that carry r_dot, averaged with weights
  // p_c (Cov(r_dot_i) = sigma_rdot^2 / p_c), from a virtual foot at their weighted centroid.
  Eigen::Vector3d r_bar = Eigen::Vector3d::Zero(), r_dot_bar = Eigen::Vector3d::Zero();
  Eigen::Matrix3d cov_r_bar = Eigen::Matrix3d::Zero();
  double W = 0.0;  // sum of the weights p_c
  for (std::size_t j = 0; j < stance.size(); ++j) {
    const ContactMeasurement& c = stance[j];
    if (!used[j] || !w_m || !c.v_body || !(c.probability > 0.0)) continue;
    const double p_c = c.probability;
    r_bar += p_c * c.p_body;
    r_dot_bar += p_c * *c.v_body;
    cov_r_bar += (p_c * p_c) * c.cov;
    W += p_c;
  }
  const Eigen::Vector3d w = w_m ? Eigen::Vector3d(*w_m - attitude_.b_g()) : Eigen::Vector3d::Zero();

  Stack st;
  for (std::size_t j = 0; j < stance.size(); ++j) {
    if (!used[j]) continue;
    const ContactMeasurement& c = stance[j];
    const int i = st.feet++;
    st.at[i] = footIndex(c.foot);
    st.z[i] = R_hat * c.p_body;                     // z_i = R_hat r_i
    st.own[i] = R_hat * c.cov * R_hat.transpose();  // R_hat Cov(r_i) R_hat^T
    // dz_i = R_hat dr_i, dz_v = -R_hat [w]_x p_c dr_i / W + ...:
    // R_hat Cov(r_i) (p_c / W) [w]_x R_hat^T
    const double share = W > 0.0 && c.v_body && c.probability > 0.0 ? c.probability / W : 0.0;
    st.with_v[i] =
        share > 0.0 ? Eigen::Matrix3d(st.own[i] * R_hat * lie::hat3(w) * R_hat.transpose() * share)
                    : Eigen::Matrix3d::Zero();
  }
  st.blocks = st.feet;
  if (W > 0.0) {
    r_bar /= W;
    r_dot_bar /= W;
    cov_r_bar /= W * W;  // Cov(weighted mean) = sum p_c^2 Cov(r_i) / W^2
    leg_odometry::FootVelocityNoise noise;
    const double sg = params_.imu.gyro_noise_density, sr = params_.foot_velocity_sigma;
    noise.gyro_cov = Eigen::Matrix3d::Identity() * (sg * sg / in.dt);  // one gyro sample
    // sum p_c^2 (sigma_rdot^2 / p_c) / W^2 = sigma_rdot^2 / W (sigma_rdot^2 / k for hard feet)
    noise.r_dot_cov = Eigen::Matrix3d::Identity() * (sr * sr / W);
    const int v = st.blocks++;
    st.at[v] = kV;
    st.z[v] = leg_odometry::baseVelocityFromFoot(R_hat, w, r_bar, r_dot_bar);  // z_v
    st.own[v] = leg_odometry::baseVelocityCovariance(R_hat, w, r_bar, cov_r_bar, noise);
    if (gate_.enabled()) {
      // S_vv = P_vv + R_vv; a velocity gated too long is used (kReinitialise)
      const Eigen::Matrix3d S =
          P_.block<3, 3>(kV, kV) + st.own[v] + attitudeNoiseBlock(st.z[v], st.z[v], Sigma_theta);
      const Eigen::Vector3d y = st.z[v] - x_.segment<3>(kV);
      if (gateBlock(kFeet, y, S, in.t) == engineering::FootGate::Decision::kGate) --st.blocks;
    }
  }
  // Fixed-size matrices for each possible number of rows (kMaxRows = 15 at most).
  if (st.blocks == 0) {
    nis_windows_.endStep(innovations_);
    return true;
  }
  BlockInnovations nis;
  bool done = true;
  static_assert(kMaxRows == 3 * (kFeet + 1), "a block per foot and one for the velocity");
  withFixedSize<kFeet + 1, 1>(st.blocks, [&](auto blocks) {
    done = stackedUpdate<3 * decltype(blocks)::value>(x_, P_, st, Sigma_theta, &nis);
  });
  // The run's NIS (stanceInnovations(), innovation_windows.hpp): the foot blocks of p_c >=
  // kNisMinProbability. A foot touching down (in swing at the previous sample) has the swing
  // walk's variance, metres: its rows only place it, and are left out.
  if (done) {
    int b = 0;
    for (std::size_t j = 0; j < stance.size(); ++j) {
      if (!used[j]) continue;
      const ContactMeasurement& c = stance[j];
      if (previous_contact_[c.foot] && c.probability >= kNisMinProbability) {
        nis_windows_.add(c.foot, nis.y[b], nis.S[b], innovations_);
      }
      ++b;
    }
  }
  nis_windows_.endStep(innovations_);
  return done;
}

engineering::FootGate::Decision LinearKf::gateBlock(int id, const Eigen::Vector3d& y,
                                                    const Eigen::Matrix3d& S, double t) {
  const Eigen::LLT<Eigen::Matrix3d> llt(S);
  // d^2 = y^T S^-1 y = |L^-1 y|^2; an S that does not factorise is left to the update's check
  if (llt.info() != Eigen::Success) return engineering::FootGate::Decision::kUse;
  const engineering::FootGate::Decision decision =
      gate_.decide(id, llt.matrixL().solve(y).squaredNorm(), t);
  if (decision == engineering::FootGate::Decision::kGate) health_.record(Fault::kGated, t);
  return decision;
}

void LinearKf::placeFoot(int i, const Eigen::Vector3d& z, const Eigen::Matrix3d& own) {
  const int d = footIndex(i);
  x_.segment<3>(d) = x_.segment<3>(kP) + z;  // d_i = p_hat + z_i
  // dd_i = dp + n: the rows of p, and P_dd = P_pp + own
  const Matrix3x18 rows = P_.middleRows<3>(kP);
  P_.middleRows<3>(d) = rows;
  P_.middleCols<3>(d) = rows.transpose();
  P_.block<3, 3>(d, d) = P_.block<3, 3>(kP, kP) + own;
}

EstimateSample LinearKf::estimate() const {
  return {t_, attitude_.R().quaternion(), x_.segment<3>(kV), x_.segment<3>(kP)};
}

std::optional<BaseCovariance> LinearKf::covariance() const {
  // BaseCovariance order (theta, v, p); x order (p, v).
  BaseCovariance cov;
  cov.has_attitude = false;
  cov.P.setZero();
  cov.P.topLeftCorner<3, 3>() = attitude_.attitudeCovariance();
  cov.P.block<3, 3>(3, 3) = P_.block<3, 3>(kV, kV);
  cov.P.block<3, 3>(3, 6) = P_.block<3, 3>(kV, kP);
  cov.P.block<3, 3>(6, 3) = P_.block<3, 3>(kP, kV);
  cov.P.block<3, 3>(6, 6) = P_.block<3, 3>(kP, kP);
  return cov;
}

}  // namespace legkit::linear_kf
