#include "estimation/invariant/invariant_ekf.hpp"

#include <Eigen/Cholesky>
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "estimation/contact/soft_contact.hpp"
#include "estimation/fixed_size.hpp"
#include "lie/imu_dynamics.hpp"

namespace legkit::invariant {

namespace inekf {

namespace {
using Matrix3 = Eigen::Matrix3d;
using Vector3 = Eigen::Vector3d;
}  // namespace

Covariance Transition::matrix() const {
  const Eigen::Index nav = B.rows();
  Covariance Phi = Covariance::Identity(nav + 6, nav + 6);
  Phi.block<3, 3>(3, 0) = v_phi;
  Phi.block<3, 3>(6, 0) = p_phi;
  Phi.block<3, 3>(6, 3) = p_v * Matrix3::Identity();
  Phi.topRightCorner(nav, 6) = B;
  return Phi;
}

Group propagateMean(const Group& X, const Vector3& w, const Vector3& a, const Vector3& g, double dt,
                    Discretisation discretisation) {
  if (discretisation == Discretisation::kExact) return lie::imu::propagate(X, w, a, g, dt);
  // The reference's step: R+ = R Exp(w dt), v+ = v + (R a + g) dt, p+ = p + v dt + (R a + g)
  // dt^2/2.
  const Matrix3& R = X.R();
  const Vector3 acceleration = R * a + g;
  Group::Columns C = X.columns();
  C.col(0) = X.col(0) + acceleration * dt;
  C.col(1) = X.col(1) + X.col(0) * dt + 0.5 * acceleration * (dt * dt);
  return Group(
      lie::SO3d::fromQuaternion(Eigen::Quaterniond(R * lie::SO3d::Exp(Vector3(w * dt)).matrix())),
      C);
}

Transition transition(const Group& X, const Group& X_next, const Vector3& w, const Vector3& a,
                      const Vector3& g, double dt, Discretisation discretisation) {
  Transition T;
  const Matrix3 G = lie::hat3(g);
  T.v_phi = G * dt;  // v <- phi: [g]_x dt
  T.p_v = dt;        // p <- v: I dt
  const Eigen::Index k = X.numCols();
  T.B.setZero(3 + 3 * k, 6);
  if (discretisation == Discretisation::kExact) {
    T.p_phi = 0.5 * G * (dt * dt);  // p <- phi: [g]_x dt^2 / 2 (A^2 dt^2 / 2)
    // B = -Ad_{X_next} J_u, Ad = [[R, 0], [[c_i]_x R, R]] applied block by block; J_u has rows
    // (phi, v, p) only (lie::imu::incrementJacobian).
    const auto J = lie::imu::incrementJacobian<Group>(k, w, a, dt);
    const Matrix3& R = X_next.R();
    const Eigen::Matrix<double, 3, 6> RJphi = R * J.topRows<3>();
    T.B.topRows<3>() = -RJphi;
    for (Eigen::Index i = 0; i < k; ++i) {
      const Vector3 c = X_next.col(i);
      T.B.middleRows<3>(3 + 3 * i).noalias() = -lie::hat3(c) * RJphi;
      if (i < 2) T.B.middleRows<3>(3 + 3 * i).noalias() -= R * J.block<3, 6>(3 + 3 * i, 0);
    }
  } else {
    T.p_phi.setZero();  // I + A dt drops A^2 dt^2 / 2
    // B = A_bias dt at the state before the step (the reference's A).
    const Matrix3 Rdt = X.R() * dt;
    T.B.block<3, 3>(0, 0) = -Rdt;  // phi <- b_g
    for (Eigen::Index i = 0; i < k; ++i) {
      T.B.block<3, 3>(3 + 3 * i, 0).noalias() = -lie::hat3(Vector3(X.col(i))) * Rdt;  // c <- b_g
    }
    T.B.block<3, 3>(3, 3) = -Rdt;  // v <- b_a
  }
  return T;
}

}  // namespace inekf

namespace {

using Matrix3 = Eigen::Matrix3d;
using Vector3 = Eigen::Vector3d;
using inekf::Covariance;
using inekf::Discretisation;

// The rotation matrix nearest to M (through its quaternion): a product of rotations, rounded.
Matrix3 rotationOf(const Matrix3& M) {
  return Eigen::Quaterniond(M).normalized().toRotationMatrix();
}

// T of e = -T xi (file comment): e = (dtheta, dv, dp), xi = (phi, rho_v, rho_p).
Eigen::Matrix<double, 9, 9> xiToBase(const Vector3& v, const Vector3& p) {
  Eigen::Matrix<double, 9, 9> T = Eigen::Matrix<double, 9, 9>::Identity();
  T.block<3, 3>(3, 0) = -lie::hat3(v);
  T.block<3, 3>(6, 0) = -lie::hat3(p);
  return T;
}

}  // namespace

InvariantEkfParams InvariantEkfParams::hartleyExample() {
  InvariantEkfParams p;
  p.imu.gyro_noise_density = 0.01;
  p.imu.accel_noise_density = 0.1;
  p.imu.gyro_bias_random_walk = 1e-5;
  p.imu.accel_bias_random_walk = 1e-4;
  p.foot_stance_density = 0.01;
  p.sigma_attitude = p.sigma_velocity = p.sigma_position = 1.0;
  p.sigma_gyro_bias = p.sigma_accel_bias = 1.0;
  p.discretisation = Discretisation::kFirstOrder;
  p.gravity = Vector3(0.0, 0.0, -9.81);
  p.feet_correct_yaw = true;  // the reference's filter: its feet correct the heading
  return p;
}

InvariantEkf::InvariantEkf(const InvariantEkfParams& params)
    : params_(params),
      gate_(params.gating, "InvariantEkf"),
      heading_(params.heading_turn_rate, params.heading_turn_time),
      pose_gate_(fusion::poseGateThreshold(params.gating)),
      slots_(params.flat_feet ? inekf::kMaxFlatFeet : inekf::kMaxFeet) {
  checkFilterParams(params, "InvariantEkf", false);  // zero densities: exact legs, constant bias
  reset(EstimateSample{});
}

void InvariantEkf::reset(const EstimateSample& x0) {
  Group::Columns C(3, 2);
  C << x0.v, x0.p;
  X_ = Group(lie::SO3d::fromQuaternion(x0.q.normalized()), C);
  b_g_.setZero();
  b_a_.setZero();
  column_of_foot_.fill(-1);
  probability_.fill(0.0);
  rotation_of_foot_.fill(-1);
  foot_R_.fill(Matrix3::Identity());
  num_rotations_ = 0;
  t_ = x0.t;
  previous_ = model::ImuReading{};
  has_previous_ = false;
  slots_.reset();
  gate_.reset();
  heading_.reset();
  nis_windows_.reset();
  replace_.fill(false);
  startHealth(x0);

  P_.setZero(15, 15);
  setNavigationPrior(x0, Vector3::Constant(params_.sigma_attitude));
  P_.block<3, 3>(9, 9).diagonal().setConstant(params_.sigma_gyro_bias * params_.sigma_gyro_bias);
  P_.block<3, 3>(12, 12).diagonal().setConstant(params_.sigma_accel_bias *
                                                params_.sigma_accel_bias);
}

void InvariantEkf::setNavigationPrior(const EstimateSample& x0, const Vector3& sigma_attitude) {
  // Prior diagonal in the kit's convention, mapped into xi = -T^-1 e.
  Eigen::Matrix<double, 9, 1> sigma;
  sigma << sigma_attitude, Vector3::Constant(params_.sigma_velocity),
      Vector3::Constant(params_.sigma_position);
  Eigen::Matrix<double, 9, 9> Tinv = Eigen::Matrix<double, 9, 9>::Identity();
  Tinv.block<3, 3>(3, 0) = lie::hat3(x0.v);
  Tinv.block<3, 3>(6, 0) = lie::hat3(x0.p);
  P_.topLeftCorner<9, 9>() = Tinv * sigma.array().square().matrix().asDiagonal() * Tinv.transpose();
}

void InvariantEkf::initialise(const InitialState& s) {
  checkInitialState(s, name());
  reset(s.x);
  b_g_ = s.b_g;
  b_a_ = s.b_a;
  // The kit's attitude error is in the world frame already: roll, pitch, yaw about x, y, z.
  if (!std::isnan(s.sigma_tilt))
    setNavigationPrior(s.x, Vector3(s.sigma_tilt, s.sigma_tilt, params_.sigma_attitude));
}

void InvariantEkf::step(const StepInput& raw) {
  InputCopies copies;
  const auto [in, imu_admitted] =
      admit(raw, has_previous_, params_.limits, "InvariantEkf", copies, slots_);
  if (has_previous_ && in.dt > 0.0) {
    propagate(in.dt);
    heading_.add(yawRate(X_.R(), previous_.w_m, b_g_), in.dt, in.slip);
  }
  correct(in);
  if (imu_admitted) {
    previous_ = in.imu;
    has_previous_ = true;
  }
  t_ = in.t;
  if (!guard_.check(estimate(), P_, params_.limits)) recover(in.t);
}

namespace {

// The two sparse columns [a b] of the heading rule's E W = a psi + b beta (correctHeldFeet), kept
// as their non-zero rows: the yaw, two rows of p and of each foot, a row of each sole, the three
// of the gyro bias.
template <int D>
class HeadingColumns {
 public:
  void add(int row, double a, double b) {
    row_[n_] = row;
    ab_.row(n_) << a, b;
    ++n_;
  }
  // x += [a b] g for a 2-vector g.
  void addTo(Eigen::Matrix<double, D, 1>& x, const Eigen::Vector2d& g) const {
    for (int i = 0; i < n_; ++i) x(row_[i]) += ab_.row(i).dot(g);
  }
  // P += [a b] G [a b]^T for a symmetric 2 x 2 G, on the rows and columns of [a b] alone.
  void addTo(Eigen::Map<Eigen::Matrix<double, D, D>>& P, const Eigen::Matrix2d& G) const {
    for (int j = 0; j < n_; ++j) {
      const Eigen::RowVector2d g_j = (G * ab_.row(j).transpose()).transpose();
      for (int i = 0; i < n_; ++i) P(row_[i], row_[j]) += ab_.row(i).dot(g_j);
    }
  }

 private:
  static constexpr int kRows = 1 + 2 * (1 + inekf::kMaxFeet) + inekf::kMaxFlatFeet + 3;
  std::array<int, kRows> row_{};
  Eigen::Matrix<double, kRows, 2> ab_;
  int n_ = 0;
};

}  // namespace

template <typename F>
void InvariantEkf::dispatch(F&& f) {
  using Zero = std::integral_constant<int, 0>;
  using One = std::integral_constant<int, 1>;
  using Two = std::integral_constant<int, 2>;
  static_assert(inekf::kMaxFlatFeet == 2, "the soles' dispatch below");
  if (num_rotations_ == 0) {
    withFixedSize<inekf::kMaxFeet>(numFeet(), [&](auto feet) { f(feet, Zero{}); });
  } else if (numFeet() == 1) {  // a sole is held with its foot's column: m <= n <= 2
    f(One{}, One{});
  } else if (num_rotations_ == 1) {
    f(Two{}, One{});
  } else {
    f(Two{}, Two{});
  }
}

int InvariantEkf::rotationIndexOf(int foot) const {
  const int k = rotation_of_foot_[foot];
  return k < 0 ? -1 : navDim() + 6 + 3 * k;
}

void InvariantEkf::propagate(double dt) {
  const Vector3 w = previous_.w_m - b_g_;  // bias-corrected rate
  const Vector3 a = previous_.a_m - b_a_;  // bias-corrected specific force
  const Vector3& g = params_.gravity;
  const Discretisation mode = params_.discretisation;
  const Group X_next = inekf::propagateMean(X_, w, a, g, dt, mode);
  const inekf::Transition Phi = inekf::transition(X_, X_next, w, a, g, dt, mode);
  dispatch([&](auto feet, auto rots) {
    propagateCovariance<decltype(feet)::value, decltype(rots)::value>(Phi, dt);
  });
  X_ = X_next;
}

template <int Feet, int Rots>
void InvariantEkf::propagateCovariance(const inekf::Transition& Phi, double dt) {
  constexpr int Nav = 9 + 3 * Feet;
  constexpr int Tail = 6 + 3 * Rots;  // the biases, then the soles' rotations
  constexpr int D = Nav + Tail;
  Eigen::Map<Eigen::Matrix<double, D, D>> P(P_.data());
  const Eigen::Map<const Eigen::Matrix<double, Nav, 6>> B(Phi.B.data());
  const bool exact = params_.discretisation == Discretisation::kExact;
  const model::ImuNoise& n = params_.imu;
  const double var_g = n.gyro_noise_density * n.gyro_noise_density;
  const double var_a = n.accel_noise_density * n.accel_noise_density;
  // sigma_d^2 of the foot in column 2 + i: the slip density, softened by its p_c (Q_f of 57.6)
  std::array<double, inekf::kMaxFeet> var_d{};
  for (int foot = 0; foot < inekf::kMaxFeet; ++foot) {
    const int col = column_of_foot_[foot];
    if (col < 0) continue;
    var_d[col - 2] = contact::softFootNoiseDensity(probability_[foot], params_.foot_stance_density,
                                                   params_.foot_swing_density);
  }
  // sigma_F^2 of the sole k: its random walk in stance, softened by its foot's p_c
  std::array<double, inekf::kMaxFlatFeet> var_r{};
  for (int foot = 0; Rots > 0 && foot < inekf::kMaxFeet; ++foot) {
    const int k = rotation_of_foot_[foot];
    if (k < 0) continue;
    var_r[k] =
        contact::softFootNoiseDensity(probability_[foot], params_.foot_rotation_stance_density,
                                      params_.foot_rotation_swing_density);
  }
  const auto addDiagonal = [&](int at, double variance) {
    P.template block<3, 3>(at, at).diagonal().array() += variance;
  };
  const auto addFootAndBiasNoise = [&] {
    for (int i = 0; i < Feet; ++i) addDiagonal(9 + 3 * i, var_d[i] * dt);  // slip random walk
    addDiagonal(Nav, n.gyro_bias_random_walk * n.gyro_bias_random_walk * dt);
    addDiagonal(Nav + 3, n.accel_bias_random_walk * n.accel_bias_random_walk * dt);
    for (int k = 0; k < Rots; ++k) addDiagonal(Nav + 6 + 3 * k, var_r[k] * dt);  // soles
  };

  if (!exact) {
    // The reference's Q_d = Phi (G Q_c G^T dt) Phi^T: add G Q_c G^T dt first, then one sandwich.
    // Gyro noise through Ad: sigma_g^2 L L^T, L = [I; [v]_x; [p]_x; [d_i]_x] (R drops out).
    Eigen::Matrix<double, Nav, 3> L;
    L.template topRows<3>().setIdentity();
    for (int i = 0; i < 2 + Feet; ++i) {
      L.template middleRows<3>(3 + 3 * i) = lie::hat3(Vector3(X_.col(i)));
    }
    P.template topLeftCorner<Nav, Nav>() += (var_g * dt) * L.lazyProduct(L.transpose());
    addDiagonal(3, var_a * dt);
    addFootAndBiasNoise();
  }

  // P <- Phi P Phi^T with Phi = [[N, B, 0], [0, I, 0], [0, 0, I]] on (xi, zeta, phi_F) (header):
  // rows first (M = Phi P), in an order that reads each source row before it is overwritten, then
  // the columns of M's navigation rows; the bias and sole rows follow by symmetry. The blocks read
  // and written never overlap.
  P.template middleRows<3>(6) += Phi.p_v * P.template middleRows<3>(3);
  if (exact) P.template middleRows<3>(6) += Phi.p_phi.lazyProduct(P.template topRows<3>());
  P.template middleRows<3>(3) += Phi.v_phi.lazyProduct(P.template topRows<3>());
  P.template topRows<Nav>() += B.lazyProduct(P.template middleRows<6>(Nav));

  auto Pnav = P.template topLeftCorner<Nav, Nav>();
  Pnav.template middleCols<3>(6) += Phi.p_v * Pnav.template middleCols<3>(3);
  if (exact) {
    Pnav.template middleCols<3>(6) +=
        Pnav.template leftCols<3>().lazyProduct(Phi.p_phi.transpose());
  }
  Pnav.template middleCols<3>(3) += Pnav.template leftCols<3>().lazyProduct(Phi.v_phi.transpose());
  // The bias columns of M times B^T; for kExact, Q_d = B diag(sigma_g^2, sigma_a^2) B^T / dt (the
  // white noise's mean over dt enters like the bias error) joins the same product.
  Eigen::Matrix<double, Nav, 6> MB = P.template block<Nav, 6>(0, Nav);
  if (exact) {
    Eigen::Matrix<double, 6, 1> q;
    q << Vector3::Constant(var_g / dt), Vector3::Constant(var_a / dt);
    MB += B * q.asDiagonal();
  }
  Pnav += MB.lazyProduct(B.transpose());
  P.template bottomLeftCorner<Tail, Nav>() = P.template topRightCorner<Nav, Tail>().transpose();
  if (exact) addFootAndBiasNoise();
  Pnav = 0.5 * (Pnav + Pnav.transpose()).eval();  // rounding only
}

void InvariantEkf::correct(const StepInput& in) {
  const Matrix3 R_predicted = X_.R();  // before this sample's correction
  dispatch([&](auto feet, auto rots) {
    correctHeldFeet<decltype(feet)::value, decltype(rots)::value>(in);
  });
  nis_windows_.endStep(innovations_);
  std::array<bool, inekf::kMaxFeet> stance{};
  for (const ContactMeasurement& c : in.stance()) stance[c.foot] = true;
  for (int foot = 0; foot < inekf::kMaxFeet; ++foot) {
    if (!stance[foot]) gate_.clear(foot);  // lifted off: its gate clock stops
    // A foot gated too long is removed too, and added anew below from its measurement.
    if (column_of_foot_[foot] >= 0 && (!stance[foot] || replace_[foot])) removeFoot(foot);
    replace_[foot] = false;
  }
  const bool predicted = params_.touchdown_attitude == inekf::TouchdownAttitude::kPredicted;
  const Matrix3 R_touchdown = predicted ? R_predicted : X_.R();
  for (const ContactMeasurement& c : in.stance()) {
    if (column_of_foot_[c.foot] < 0) {
      addFoot(c, R_touchdown);
      // A sole: with the corrected attitude always (file comment, "Flat feet").
      if (params_.flat_feet && c.R_body && num_rotations_ < inekf::kMaxFlatFeet)
        addRotation(c, X_.R());
    }
    probability_[c.foot] = c.probability;
  }
}

template <int Feet, int Rots>
void InvariantEkf::correctHeldFeet(const StepInput& in) {
  constexpr int Nav = 9 + 3 * Feet;
  constexpr int D = Nav + 6 + 3 * Rots;
  Eigen::Map<Eigen::Matrix<double, D, D>> P(P_.data());
  const Matrix3 R = X_.R();  // the predicted attitude: every foot is linearised here
  const Vector3 p = X_.col(1);
  Eigen::Matrix<double, D, 1> delta = Eigen::Matrix<double, D, 1>::Zero();
  // The heading stays the gyro's (file comment): K' = (I - alpha E) K (alpha the rule's share by
  // the turn rate, heading_rule.hpp), so a correction K nu = W C^-1 nu loses alpha E W C^-1 nu and
  // P <- P - W W^T + alpha^2 (E W)(E W)^T (Joseph form with K'). E W = a psi + b beta: the heading
  // row psi (world z of the rotation) times a, the turn of the robot about its base, which in the
  // right-invariant error is e_z on the rotation, 0 on v, -(e_z x p) on p and on every foot and
  // e_z on each held sole; and beta = up^T W_bg, the gyro bias's part along up = R_hat^T e_z,
  // times b = up on the bias. a and b are sparse (at most 16 rows between them), so the rank-2
  // term is added on their rows and columns only. Every update takes it, a sole's too.
  const double alpha = params_.feet_correct_yaw ? 0.0 : heading_.alpha();
  const Vector3 up = R.row(2).transpose();
  HeadingColumns<D> ab;  // [a b] on its rows
  if (alpha > 0.0) {
    const Vector3 p_turned = Vector3(p.y(), -p.x(), 0.0);  // -(e_z x p)
    ab.add(2, 1.0, 0.0);
    for (int c = 1; c < Nav / 3 - 1; ++c) {
      ab.add(3 + 3 * c, p_turned.x(), 0.0);
      ab.add(4 + 3 * c, p_turned.y(), 0.0);
    }
    for (int k = 0; k < Rots; ++k) ab.add(Nav + 8 + 3 * k, 1.0, 0.0);
    for (int j = 0; j < 3; ++j) ab.add(Nav + j, 0.0, up(j));
  }
  // One update: W = P H^T C^-T and the whitened innovation C^-1 nu (S = C C^T).
  const auto correctWith = [&](const Eigen::Matrix<double, D, 3>& W, const Vector3& nu_white) {
    delta += W * nu_white;
    P -= W.lazyProduct(W.transpose());
    if (alpha == 0.0) return;
    Eigen::Matrix<double, 2, 3> psi_beta;  // [psi; beta]
    psi_beta.row(0) = W.template middleRows<1>(2);
    psi_beta.row(1) = up.transpose() * W.template middleRows<3>(Nav);
    ab.addTo(delta, -alpha * (psi_beta * nu_white));
    ab.addTo(P, alpha * alpha * (psi_beta * psi_beta.transpose()));
  };
  bool corrected = false;
  for (const ContactMeasurement& c : in.stance()) {
    const int col = column_of_foot_[c.foot];
    if (col < 0) continue;       // touching down now: added after the correction
    const int id = 3 + 3 * col;  // error index of this foot's rho_d
    // z = R_hat y + p_hat - d_hat, H = [.., -I (p), .., +I (d), ..]; the innovation is taken
    // relative to the earlier feet's correction (sequential = stacked).
    const Vector3 z = R * c.p_body + p - X_.col(col);
    const Vector3 nu = z - (delta.template segment<3>(id) - delta.template segment<3>(6));
    const Eigen::Matrix<double, D, 3> U =
        P.template middleCols<3>(id) - P.template middleCols<3>(6);  // P H^T
    const Matrix3 S =
        U.template middleRows<3>(id) - U.template middleRows<3>(6) + R * c.cov * R.transpose();
    // S = C C^T (Cholesky). K = U S^-1 = W C^-1 with W = U C^-T, so K S K^T = W W^T, and
    // the correction is K nu = W (C^-1 nu). W is D x 3, column-major: the rank-3 update of P
    // runs down its columns.
    const Eigen::LLT<Matrix3> llt(S);
    if (llt.info() != Eigen::Success) {  // the contract: skip this foot's update, counted
      health_.record(Fault::kUpdateFailed, in.t);
      continue;
    }
    const Matrix3 C_inv = llt.matrixL().solve(Matrix3::Identity());
    const Vector3 nu_white = C_inv * nu;  // d^2 = nu^T S^-1 nu = |C^-1 nu|^2
    if (gate_.enabled()) {
      const engineering::FootGate::Decision decision =
          gate_.decide(c.foot, nu_white.squaredNorm(), in.t);
      if (decision != engineering::FootGate::Decision::kUse) {
        health_.record(Fault::kGated, in.t);
        replace_[c.foot] = decision == engineering::FootGate::Decision::kReinitialise;
        continue;
      }
    }
    if (c.probability >= kNisMinProbability) nis_windows_.add(c.foot, nu, S, innovations_);
    correctWith(U * C_inv.transpose(), nu_white);
    corrected = true;
    if constexpr (Rots > 0) {
      if (rotation_of_foot_[c.foot] >= 0 && c.R_body) {
        // Its sole (file comment, "Flat feet"): r = Log(R_hat Z R_F,hat^T), H = [-I (phi), +I
        // (phi_F)], N = R_F,hat rot_cov R_F,hat^T; under the heading rule, not gated.
        const int f = Nav + 6 + 3 * rotation_of_foot_[c.foot];
        const Matrix3& R_F = foot_R_[c.foot];
        const Vector3 r =
            lie::SO3d::fromQuaternion(Eigen::Quaterniond(R * *c.R_body * R_F.transpose())).Log();
        const Vector3 nu_F =
            r - (delta.template segment<3>(f) - delta.template segment<3>(0));  // sequential
        const Eigen::Matrix<double, D, 3> U_F =
            P.template middleCols<3>(f) - P.template leftCols<3>();  // P H^T
        const Matrix3 S_F = U_F.template middleRows<3>(f) - U_F.template topRows<3>() +
                            R_F * c.rot_cov * R_F.transpose();
        const Eigen::LLT<Matrix3> llt_F(S_F);
        if (llt_F.info() != Eigen::Success) {
          health_.record(Fault::kUpdateFailed, in.t);
          continue;
        }
        const Matrix3 C_F_inv = llt_F.matrixL().solve(Matrix3::Identity());
        correctWith(U_F * C_F_inv.transpose(), C_F_inv * nu_F);
      }
    }
  }
  if (!corrected) return;
  X_ = Group::Exp(Group::Tangent(delta.template head<Nav>())) * X_;  // X_hat <- Exp(delta) X_hat
  b_g_ += delta.template segment<3>(Nav);
  b_a_ += delta.template segment<3>(Nav + 3);
  if constexpr (Rots > 0) moveSoles(delta.template segment<3 * Rots>(Nav + 6));
}

void InvariantEkf::moveSoles(const Eigen::Ref<const Eigen::VectorXd>& delta_soles) {
  for (int foot = 0; foot < inekf::kMaxFeet; ++foot) {  // R_F,hat <- Exp(delta_phiF) R_F,hat
    const int k = rotation_of_foot_[foot];
    if (k < 0) continue;
    foot_R_[foot] =
        rotationOf(lie::SO3d::Exp(Vector3(delta_soles.segment<3>(3 * k))).matrix() * foot_R_[foot]);
  }
}

fusion::PoseUpdate InvariantEkf::updatePose(const fusion::PoseMeasurement& z) {
  fusion::checkPoseMeasurement(z, "InvariantEkf");
  if (!z.valid) return fusion::PoseUpdate::kNotValid;
  fusion::PoseUpdate result = fusion::PoseUpdate::kFailed;
  dispatch([&](auto feet, auto rots) {
    result = correctPose<decltype(feet)::value, decltype(rots)::value>(z);
  });
  return result;
}

template <int Feet, int Rots>
fusion::PoseUpdate InvariantEkf::correctPose(const fusion::PoseMeasurement& z) {
  constexpr int Nav = 9 + 3 * Feet;
  constexpr int D = Nav + 6 + 3 * Rots;
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  Eigen::Map<Eigen::Matrix<double, D, D>> P(P_.data());
  const Matrix3& R = X_.R();
  const Vector3 p = X_.col(1);
  // r = Log(T_m T_hat^-1): T_m T_hat^-1 = (R_m R_hat^T, p_m - R_m R_hat^T p_hat) (file comment).
  const lie::SO3d dR =
      lie::SO3d::fromQuaternion(Eigen::Quaterniond(z.R_MB.matrix() * R.transpose()));
  const Vector3 phi = dR.Log();
  Vector6 r;
  r << phi, lie::SO3d::JlInv(phi) * (z.p_MB - dR.matrix() * p);
  // N' = A N A^T, A = [[I, 0], [[p_hat]_x, I]]: the pose noise in the variables of r.
  const Matrix3 p_x = lie::hat3(p);
  Matrix6 N = z.cov;
  N.template bottomRows<3>().noalias() += p_x.lazyProduct(z.cov.template topRows<3>());
  N.template rightCols<3>() += N.template leftCols<3>().lazyProduct(p_x.transpose()).eval();
  // H = [I (phi), 0, I (rho_p), 0, ..]: U = P H^T = (P_phi, P_rho_p), S = H U + N'.
  Eigen::Matrix<double, D, 6> U;
  U.template leftCols<3>() = P.template leftCols<3>();
  U.template rightCols<3>() = P.template middleCols<3>(6);
  Matrix6 S = N;
  S.template topRows<3>() += U.template topRows<3>();
  S.template bottomRows<3>() += U.template middleRows<3>(6);
  // S = C C^T, K = U S^-1 = W C^-1 with W = U C^-T (as for a foot).
  const Eigen::LLT<Matrix6> llt(S);
  if (llt.info() != Eigen::Success) {
    health_.record(Fault::kUpdateFailed, z.t);
    return fusion::PoseUpdate::kFailed;
  }
  const Matrix6 C_inv = llt.matrixL().solve(Matrix6::Identity());
  const Vector6 r_white = C_inv * r;  // d^2 = r^T S^-1 r = |C^-1 r|^2
  if (params_.gating.enabled && r_white.squaredNorm() > pose_gate_) {
    health_.record(Fault::kGated, z.t);
    return fusion::PoseUpdate::kGated;
  }
  const Eigen::Matrix<double, D, 6> W = U * C_inv.transpose();
  const Eigen::Matrix<double, D, 1> delta = W * r_white;
  P -= W.lazyProduct(W.transpose());
  X_ = Group::Exp(Group::Tangent(delta.template head<Nav>())) * X_;  // X_hat <- Exp(delta) X_hat
  b_g_ += delta.template segment<3>(Nav);
  b_a_ += delta.template segment<3>(Nav + 3);
  if constexpr (Rots > 0) moveSoles(delta.template segment<3 * Rots>(Nav + 6));
  return fusion::PoseUpdate::kUsed;
}

namespace {

// Marginalising a Gaussian: P without the rows and columns at..at+2.
void removeRowsAndColumns(Covariance& P, int at) {
  const int n = static_cast<int>(P.rows());
  const int tail = n - at - 3;
  Covariance Pm(n - 3, n - 3);
  Pm.topLeftCorner(at, at) = P.topLeftCorner(at, at);
  Pm.topRightCorner(at, tail) = P.topRightCorner(at, tail);
  Pm.bottomLeftCorner(tail, at) = P.bottomLeftCorner(tail, at);
  Pm.bottomRightCorner(tail, tail) = P.bottomRightCorner(tail, tail);
  P = Pm;
}

}  // namespace

void InvariantEkf::removeFoot(int foot) {
  if (rotation_of_foot_[foot] >= 0) removeRotation(foot);  // its sole first (indices after nav)
  const int col = column_of_foot_[foot];
  removeRowsAndColumns(P_, 3 + 3 * col);  // its rows and columns in P
  X_.removeColumn(col);
  column_of_foot_[foot] = -1;
  for (int& c : column_of_foot_) {
    if (c > col) --c;
  }
}

void InvariantEkf::removeRotation(int foot) {
  const int k = rotation_of_foot_[foot];
  removeRowsAndColumns(P_, navDim() + 6 + 3 * k);
  rotation_of_foot_[foot] = -1;
  for (int& j : rotation_of_foot_) {
    if (j > k) --j;
  }
  --num_rotations_;
}

void InvariantEkf::addFoot(const ContactMeasurement& c, const Matrix3& R) {
  const int col = static_cast<int>(X_.numCols());
  const int at = 3 + 3 * col;  // = the navigation dimension before the new column
  const int n = static_cast<int>(P_.rows());
  const int tail = n - at;  // the biases and the soles' rotations
  // rho_d = rho_p + R_hat n: the new rows copy rho_p's, plus R_hat Cov R_hat^T on the diagonal.
  Covariance Pa(n + 3, n + 3);
  Pa.topLeftCorner(at, at) = P_.topLeftCorner(at, at);
  Pa.topRightCorner(at, tail) = P_.topRightCorner(at, tail);
  Pa.bottomLeftCorner(tail, at) = P_.bottomLeftCorner(tail, at);
  Pa.bottomRightCorner(tail, tail) = P_.bottomRightCorner(tail, tail);
  Pa.block(0, at, at, 3) = P_.block(0, 6, at, 3);
  Pa.block(at + 3, at, tail, 3) = P_.block(at, 6, tail, 3);
  Pa.block(at, 0, 3, at) = P_.block(6, 0, 3, at);
  Pa.block(at, at + 3, 3, tail) = P_.block(6, at, 3, tail);
  Pa.block<3, 3>(at, at) = P_.block<3, 3>(6, 6) + R * c.cov * R.transpose();
  P_ = Pa;
  X_.appendColumn(X_.col(1) + R * c.p_body);  // d = p_hat + R_hat y
  column_of_foot_[c.foot] = col;
}

void InvariantEkf::addRotation(const ContactMeasurement& c, const Matrix3& R) {
  // R_F,hat = R_hat Z and phi_F = phi + R_F n: the new rows copy phi's, plus N (file comment).
  const Matrix3 R_F = rotationOf(R * *c.R_body);
  const int n = static_cast<int>(P_.rows());
  Covariance Pa(n + 3, n + 3);
  Pa.topLeftCorner(n, n) = P_;
  Pa.bottomLeftCorner(3, n) = P_.topRows<3>();
  Pa.topRightCorner(n, 3) = P_.leftCols<3>();
  Pa.bottomRightCorner<3, 3>() = P_.topLeftCorner<3, 3>() + R_F * c.rot_cov * R_F.transpose();
  P_ = Pa;
  foot_R_[c.foot] = R_F;
  rotation_of_foot_[c.foot] = num_rotations_++;
}

EstimateSample InvariantEkf::estimate() const {
  EstimateSample e;
  e.t = t_;
  e.q = Eigen::Quaterniond(X_.R());
  e.v = X_.col(0);
  e.p = X_.col(1);
  return e;
}

std::optional<BaseCovariance> InvariantEkf::covariance() const {
  const Eigen::Matrix<double, 9, 9> T = xiToBase(X_.col(0), X_.col(1));
  BaseCovariance cov;
  cov.P = T * P_.topLeftCorner<9, 9>() * T.transpose();  // the sign of e = -T xi cancels
  cov.has_attitude = true;
  return cov;
}

}  // namespace legkit::invariant
