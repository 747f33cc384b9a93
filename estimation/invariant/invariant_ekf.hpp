// The contact-aided right-invariant EKF of section 57.5 (Hartley et al. 2020, "Contact-aided
// invariant extended Kalman filtering for robot state estimation", IJRR), in its "imperfect" form
// with IMU biases: the state of a legged robot lives in a matrix Lie group, and the filter's error
// is defined so that, without biases, it evolves independently of the state.
//
// State. X in SE_{2+n}(3): attitude R (body to world), world velocity v and position p, and the
// world positions d_1..d_n of the n feet currently in contact (lie/sek3.hpp),
//        [ R  v  p  d_1 .. d_n ]
//   X =  [ 0  1  0   0  ..  0  ]      plus the biases theta = (b_g, b_a) in R^6, kept beside the
//        [ ...      I          ]      group (they do not transform with the robot's pose).
// n changes at run time (a foot touching down adds a column, a foot lifting off removes one) up
// to kMaxFeet; all storage has that fixed capacity, so step() never allocates.
//
// Error. Right-invariant on the group, additive on the biases:
//   eta = X_hat X^-1 = Exp(xi),  xi = (phi, rho_v, rho_p, rho_d1..rho_dn),  zeta = b_hat - b,
// ordered (xi, zeta) in P (15 + 3n numbers). eta is the world-frame rigid motion that carries the
// true state onto the estimate, X_hat = eta X: R_hat = Exp(phi) R and, for each column,
// c_hat = Exp(phi) c + Jl(phi) rho (exercise 57.5.2).
// Corrections multiply on the left, X_hat <- Exp(delta) X_hat, b_hat <- b_hat + delta_b.
//
// Propagation over dt with the previous IMU sample u = (w_m, a_m) held, w = w_m - b_g,
// a = a_m - b_a. With the same input, estimate and truth obey eta+ = Gamma_g f(eta) Gamma_g^-1
// exactly (lie/imu_dynamics.hpp), so xi is log-linear:
//   xi+ = Phi xi - Ad_{X_hat+} J_u (zeta + n),     Phi = I + A dt + A^2 dt^2 / 2,
//   A = [[0, 0, 0], [[g]_x, 0, 0], [0, I, 0]] on (phi, v, p), zero rows for the feet.
// Phi's navigation block depends on g and dt only; only the bias block B = -Ad_{X_hat+} J_u
// (which is why this filter is "imperfect") depends on the estimate. Two discretisations:
//  - kExact (default): X_hat+ = lie::imu::propagate (exact for a held sample), Phi and B in
//    closed form (lie::imu::phiWithBias's blocks). The white IMU noise over the interval enters
//    like the bias error, through B: its mean over dt has covariance Q/dt, so
//      Q_d = B diag(sigma_g^2, sigma_a^2) B^T / dt  +  sigma_d^2 dt I on each foot
//            +  sigma_bg^2 dt, sigma_ba^2 dt on the biases.
//  - kFirstOrder: the reference implementation's (RossHartley/invariant-ekf, InEKF.cpp):
//    R+ = R Exp(w dt), v+ = v + (R a + g) dt, p+ = p + v dt + (R a + g) dt^2 / 2,
//    Phi = I + A_full dt with A_full's bias block [[-R, 0], [-[v]_x R, -R], [-[p]_x R, 0],
//    [-[d_i]_x R, 0]] at the state before the step, and
//      Q_d = Phi G Q_c G^T Phi^T dt,  G = blockdiag(Ad_{X_hat}, I_6),
//    Q_c = diag(sigma_g^2, sigma_a^2, 0, sigma_d^2 per foot, sigma_bg^2, sigma_ba^2) (body-frame
//    noises mapped to the world by the Adjoint).
// In both, P+ = Phi P Phi^T + Q_d is computed from Phi's blocks (Phi is the identity except on
// the v and p rows of the navigation block and the bias columns), and Ad is never formed: with
// isotropic noises, Ad Q_c Ad^T = sigma_g^2 [I; [c_i]_x] [I; [c_i]_x]^T + diagonal terms.
//
// Correction, one stance foot held in column c: the kinematics give the foot in the body frame,
// y = R^T (d - p) + n, n ~ N(0, Cov) (the ContactMeasurement). In the right-invariant form
//   z = R_hat y + p_hat - d_hat = rho_p - rho_d + R_hat n   (to first order),
// a residual whose Jacobian does not depend on the estimate at all. As the reference does, the
// filter writes it for the correction delta = -xi: H = [0, 0, -I, .., +I (foot), .., 0], noise
// N = R_hat Cov R_hat^T, K = P H^T (H P H^T + N)^-1, delta = K z, P <- P - K H P. All feet
// of a sample are linearised at the same predicted state: they are processed one after another
// (3 x 3 innovations, each corrected for the earlier feet's delta), which equals the reference's
// single stacked update, and the group is moved once, X_hat <- Exp(delta_xi) X_hat.
//
// Heading rule (feet_correct_yaw = false, the default; why, what it measured and what it costs:
// eskf.hpp's "Heading rule" paragraph). The same rule in the right-invariant error: the gain
// loses the heading row (the world z of the rotation error) times the turn of the robot about its
// base, which here is e_z on the rotation, 0 on the velocity and -(e_z x p) on the position and
// every foot, and the part along the gyro bias about the vertical, both times the rule's share
// alpha (heading_rule.hpp); the Joseph form gives P <- P - W W^T + alpha^2 (E W)(E W)^T, whose
// last term touches only the rows of those two sparse columns (correctHeldFeet).
//
// Gating (section 57.9, GatingParams, off by default): each held foot's innovation nu is tested
// with d^2 = nu^T S^-1 nu = |C^-1 nu|^2 (S = C C^T, its sequential innovation covariance) against
// the chi-square quantile of 3 dof; a gated foot is skipped for that sample (Fault::kGated). A foot
// gated for longer than max_gated_time is removed and added anew from its measurement, as at a
// touchdown (engineering/gating.hpp: lock-out).
//
// Contacts, by foot id, after the correction (the reference's order): a held foot that is no
// longer in stance is marginalised (its column of X and its rows and columns of P removed); a foot
// that touches down gets a new column d = p_hat + R_hat y, whose right-invariant error is
// rho_d = rho_p + R_hat n: its rows of P copy those of rho_p, plus R_hat Cov R_hat^T. That
// relation needs R_hat to be the attitude whose error P describes, the corrected one
// (TouchdownAttitude::kCorrected, the default): the error column of d is d_hat - R_hat R^T d, and
// with d_hat = p_hat + R_hat y it is exactly rho_p + R_hat n. The reference implementation
// (RossHartley/invariant-ekf, InEKF::CorrectKinematics) uses the attitude from before the
// correction, R_hat-; then rho_d = rho_p + R_hat- n + (R_hat- - R_hat) R^T (d - p): an error of
// one attitude correction times the leg length that P does not contain (kPredicted reproduces
// it). A stance foot's slip random walk sigma_d enters through Q_d; a held foot whose contact
// probability p_c (its ContactMeasurement::probability at the previous sample) is below one gets
// the soft density of section 57.6, p_c sigma_d^2 + (1 - p_c) sigma_swing^2 (p_c = 1: sigma_d^2
// exactly). This filter holds no swing feet, so sigma_swing (foot_swing_density) serves only
// there.
//
// Pose update (section 57.8, "pose injection": the map is this filter's world frame). A pose z =
// (R_m, p_m) in the world with noise (n_theta, n_p) ~ N(0, z.cov), R_m = Exp(n_theta) R,
// p_m = p + n_p, observes the group from the world side, Y = X b: a left-invariant observation,
// for which a right-invariant filter has no estimate-free Jacobian in the measurement's own
// coordinates (there H = [[I, 0, 0], [-[p_hat]_x, 0, I]], and the mapping of xi to the world
// error is nonlinear in phi times the distance from the origin). The filter instead changes the
// noise's variables: with T = (R, p) the pose part of X and delta = -xi,
//   T = Exp(delta) T_hat,  T_m = Exp(n') T   =>   r = Log(T_m T_hat^-1) = delta_pose + n'
// to first order in (delta, n') (SE(3) Log, tangent (phi, rho)), so H = [I (phi), 0, I (rho_p),
// 0, ..] is constant, and n' = (n_theta, n_p + [p]_x n_theta) (Exp(n') T's position is
// p + n_rho - [p]_x n_theta), N' = A z.cov A^T with A = [[I, 0], [[p_hat]_x, I]]: the adjoint
// at the position. The lever arm [p_hat]_x now sits in the noise, where it is exact to first order
// in the small n_theta. Then K = P H^T S^-1, X_hat <- Exp(delta_xi) X_hat as at a foot
// correction. tests/fusion/delayed_pose_test.cpp checks the NEES after pose updates 36 m from the
// origin. Gated (when gating is on) by d^2 = r^T S^-1 r against the chi-square quantile of 6 dof
// (Fault::kGated).
//
// Flat feet (params.flat_feet, settings feet.flat; the sole and its measurement Z = R_BF = R^T R_F
// Exp(n), n ~ N(0, rot_cov) in the foot frame: eskf.hpp's "Flat feet"). A foot whose contact
// carries Z at its touchdown also gets its rotation R_F (foot to world), kept beside the group
// like the biases, with the right-invariant (world-frame) error R_F,hat = Exp(phi_F) R_F; at most
// kMaxFlatFeet = 2 (a humanoid's: with flat_feet the filter has two foot slots), each after the
// biases in the order of the touchdowns: P = (xi, zeta, phi_F1, .., phi_Fm), 15 + 3 n + 3 m rows,
// and without soles (flat_feet false, m = 0) the point-foot filter, bit for bit. R_F is constant
// in stance and phi_F does not depend on the IMU: Phi is the identity on it, whose only noise is a
// random walk of density foot_rotation_stance_density (softened by p_c as the position's, towards
// 1 rad/sqrt(s)). The measurement: R_hat Z R_F,hat^T = Exp(phi) Exp(R_F n) Exp(-phi_F), so
//   r = Log(R_hat Z R_F,hat^T) = phi - phi_F + R_F n = -delta_phi + delta_phiF + R_F n,
//   H = [-I (phi), .., +I (phi_F), ..],   N = R_F,hat rot_cov R_F,hat^T,
// estimate-independent again: a second 3 x 3 update right after the foot's position (only when
// the position was used; outside the gate and the NIS windows; under the heading rule). At
// touchdown R_F,hat = R_hat Z with the corrected attitude (whatever touchdown_attitude says: the
// reference has no soles), R_hat Z = Exp(phi) Exp(R_F n) R_F, so phi_F = phi + R_F n: its rows of P
// copy phi's, plus N. At lift-off its rows and columns are removed; a correction moves it as the
// group, R_F,hat <- Exp(delta_phiF) R_F,hat. As in the ESKF the heading rule takes its share of a
// sole's update as of a position's; the turn about the base is e_z on every held sole's error, as
// on the attitude (both in the world frame). Measured on the iCub log (legkit run --log
// data/icub-walking/walking.csv --config config/robots/icub.yaml; position RMSE, roll/pitch and
// yaw RMS; the gyro alone 2.39 deg from a zero gyro bias, 0.29 from the still window's): point
// feet 0.025 m, 0.61 deg, 2.43 deg from zero, 0.010 m, 0.58, 0.24 from the still window; flat
// feet 0.015 m, 0.57, 1.32 and 0.008 m, 0.54, 0.28 (the ESKF's 0.015 m, 1.30 deg and 0.008 m,
// 0.26 deg). tests/estimation/flat_feet_test.cpp: the biped's Monte Carlo NEES and gyro bias.
//
// covariance() maps xi to the kit's convention (R = Exp(dtheta) R_hat, v = v_hat + dv,
// p = p_hat + dp) to first order: dtheta = -phi, dv = -(rho_v - [v_hat]_x phi),
// dp = -(rho_p - [p_hat]_x phi).
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>

#include "estimation/engineering/gating.hpp"
#include "estimation/estimator.hpp"
#include "estimation/foot_slots.hpp"
#include "estimation/fusion/delayed_pose.hpp"
#include "estimation/fusion/pose_measurement.hpp"
#include "estimation/innovation_windows.hpp"
#include "estimation/invariant/filter_params.hpp"
#include "estimation/invariant/heading_rule.hpp"
#include "lie/sek3.hpp"
#include "model/imu_model.hpp"
#include "model/imu_noise.hpp"

namespace legkit::invariant {

namespace inekf {

constexpr int kMaxFeet = 6;                   // contact columns at most (foot ids 0..5: a hexapod)
constexpr int kMaxColumns = 2 + kMaxFeet;     // v, p, d_1..d_6
constexpr int kMaxNav = 3 + 3 * kMaxColumns;  // 27: the group part of the error
constexpr int kMaxDim = kMaxNav + 6;          // 33: with the biases
constexpr int kMaxFlatFeet = 2;  // soles with a rotation (flat_feet): 15 + 6 + 6 = 27 <= kMaxDim
using Group = lie::SEKd<double, kMaxColumns>;  // SE_{2+n}(3), n <= kMaxFeet
using Covariance =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kMaxDim, kMaxDim>;
using BiasBlock = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::ColMajor, kMaxNav, 6>;

enum class Discretisation {
  kExact,       // closed-form Phi, exact mean for a held sample (this kit's default)
  kFirstOrder,  // Phi = I + A dt and the reference implementation's mean and Q_d
};

// The attitude that places a foot touching down, d = p_hat + R_hat y (file comment).
enum class TouchdownAttitude {
  kCorrected,  // after this sample's correction: the new foot's error is rho_p + R_hat n
  kPredicted,  // before it, as the reference implementation does
};

// Phi = [[N, B], [0, I_6]] (file comment): N differs from the identity only in the blocks
// v <- phi ([g]_x dt), p <- phi ([g]_x dt^2/2, 0 for first order) and p <- v (I dt).
struct Transition {
  Eigen::Matrix3d v_phi;      // [g]_x dt
  Eigen::Matrix3d p_phi;      // [g]_x dt^2 / 2 (kExact) or 0 (kFirstOrder)
  double p_v = 0.0;           // dt
  BiasBlock B;                // navigation rows x (b_g, b_a) columns
  Covariance matrix() const;  // the full (dof + 6) square Phi, for tests and teaching
};

// Phi for the step from X (before propagation) with bias-corrected rate w and specific force a.
// X_next is X propagated by the same discretisation (used by kExact's B = -Ad_{X_next} J_u).
Transition transition(const Group& X, const Group& X_next, const Eigen::Vector3d& w,
                      const Eigen::Vector3d& a, const Eigen::Vector3d& g, double dt,
                      Discretisation discretisation);

// The mean step of the chosen discretisation (file comment).
Group propagateMean(const Group& X, const Eigen::Vector3d& w, const Eigen::Vector3d& a,
                    const Eigen::Vector3d& g, double dt, Discretisation discretisation);

}  // namespace inekf

// The family's block (filter_params.hpp) and the choices of this filter's own discretisation.
// The feet enter the state at their touchdown (no prior of an unknown foot).
struct InvariantEkfParams : FilterParams {
  inekf::Discretisation discretisation = inekf::Discretisation::kExact;
  inekf::TouchdownAttitude touchdown_attitude = inekf::TouchdownAttitude::kCorrected;

  // The settings of the reference implementation's Cassie example (src/examples/kinematics.cpp):
  // its noise values read as continuous-time standard deviations (gyro 0.01, accel 0.1, bias
  // random walks 1e-5 and 1e-4, contact 0.01), P0 = I, first-order Phi. The
  // touchdown attitude stays the kit's (kCorrected); with kPredicted as well the filter is the
  // reference's, and on its Cassie log gives the reference's states to rounding (tests/estimation).
  static InvariantEkfParams hartleyExample();
};

class InvariantEkf final : public Estimator {
 public:
  using Group = inekf::Group;
  using Covariance = inekf::Covariance;

  // Throws std::invalid_argument for a negative noise density, a non-positive prior sigma or a
  // non-finite gravity.
  explicit InvariantEkf(const InvariantEkfParams& params = {});

  std::string name() const override { return "invariant-ekf"; }
  // Base from x0, biases zero, no feet; P from the Params sigmas. Nothing is propagated until
  // an IMU sample has been admitted (the reference instead propagates a zero reading, free fall,
  // when its first step has dt > 0).
  void reset(const EstimateSample& x0) override;
  // As Estimator::initialise says; the tilt prior is about the world x and y axes.
  void initialise(const InitialState& s) override;
  // Propagation over in.dt with the previous IMU sample, then the contacts of this sample:
  // corrections for the held feet still in stance, removal of the others, new columns for feet
  // that touched down. Bad input and faults as estimation/estimator.hpp's contract says.
  void step(const StepInput& in) override;
  EstimateSample estimate() const override;
  // The (dtheta, dv, dp) block in the BaseCovariance convention (file comment).
  std::optional<BaseCovariance> covariance() const override;
  // NIS: windows (innovation_windows.hpp) of the held feet's corrections of p_c >=
  // kNisMinProbability that were used, each with its sequential innovation nu and S.
  std::optional<InnovationStats> stanceInnovations() const override { return innovations_; }
  // The pose z (world = map frame) as a measurement of X's pose, applied to the current state
  // whatever z.t (DelayedFilter applies it at its stamp). File comment: "Pose update". Throws
  // std::invalid_argument naming the field and z.t for a non-finite pose or a covariance that is
  // not symmetric positive definite, before anything changes; kNotValid, kGated, kFailed change
  // nothing but the health record.
  fusion::PoseUpdate updatePose(const fusion::PoseMeasurement& z);

  const Group& X() const { return X_; }
  const Eigen::Vector3d& b_g() const { return b_g_; }
  const Eigen::Vector3d& b_a() const { return b_a_; }
  // Covariance of (xi, zeta) and the soles' phi_F (flat feet): 15 + 3 n + 3 m rows.
  const Covariance& P() const { return P_; }
  int numFeet() const { return static_cast<int>(X_.numCols()) - 2; }
  // The column of X holding foot `foot` (2, 3, ...), or -1 when it is not in contact.
  int columnOf(int foot) const { return column_of_foot_[foot]; }
  // Flat feet: the number m of soles held, the row of P of foot `foot`'s phi_F (-1 when it holds
  // no rotation) and its R_F,hat (foot to world), placed at its touchdown.
  int numRotations() const { return num_rotations_; }
  int rotationIndexOf(int foot) const;
  const Eigen::Matrix3d& footRotation(int foot) const { return foot_R_[foot]; }

 private:
  void propagate(double dt);
  void correct(const StepInput& in);
  // The covariance parts of propagate() and correct() for a fixed number of feet and of soles'
  // rotations, so that every product has compile-time sizes (dispatched on numFeet() and
  // numRotations()).
  template <int Feet, int Rots>
  void propagateCovariance(const inekf::Transition& Phi, double dt);
  template <int Feet, int Rots>
  void correctHeldFeet(const StepInput& in);
  template <int Feet, int Rots>
  fusion::PoseUpdate correctPose(const fusion::PoseMeasurement& z);
  // Calls f(Feet, Rots) as std::integral_constant for the current numFeet() and numRotations().
  template <typename F>
  void dispatch(F&& f);
  // The (xi_R, xi_v, xi_p) block of P from the kit-convention prior sigmas at x0 (reset()).
  void setNavigationPrior(const EstimateSample& x0, const Eigen::Vector3d& sigma_attitude);
  void removeFoot(int foot);
  // A new column for foot c.foot, placed with attitude R (TouchdownAttitude).
  void addFoot(const ContactMeasurement& c, const Eigen::Matrix3d& R);
  // Flat feet: the sole's rotation of foot c.foot, R_F,hat = R Z (file comment), and its removal.
  void addRotation(const ContactMeasurement& c, const Eigen::Matrix3d& R);
  void removeRotation(int foot);
  // R_F,hat <- Exp(delta_phiF) R_F,hat for the m soles' part of a correction.
  void moveSoles(const Eigen::Ref<const Eigen::VectorXd>& delta_soles);
  int navDim() const { return 3 + 3 * static_cast<int>(X_.numCols()); }

  InvariantEkfParams params_;
  engineering::FootGate gate_;
  HeadingRule heading_;            // alpha of the heading rule (heading_rule.hpp)
  InnovationWindows nis_windows_;  // the stance-foot NIS (stanceInnovations())
  double pose_gate_;  // chi-square quantile of 6 dof for the pose innovation (file comment)
  std::array<bool, inekf::kMaxFeet> replace_{};  // gated too long: re-added after the correction
  FootSlots<inekf::kMaxFeet> slots_;  // foot ids of the log -> this filter's foot columns
  Group X_{2};
  Eigen::Vector3d b_g_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_a_ = Eigen::Vector3d::Zero();
  Covariance P_ = Covariance::Identity(15, 15);
  std::array<int, inekf::kMaxFeet> column_of_foot_{};    // -1: not held
  std::array<double, inekf::kMaxFeet> probability_{};    // p_c of each held foot (previous sample)
  std::array<int, inekf::kMaxFeet> rotation_of_foot_{};  // -1, or which sole (0..m-1) it holds
  std::array<Eigen::Matrix3d, inekf::kMaxFeet> foot_R_;  // R_F,hat of each held sole
  int num_rotations_ = 0;                                // m
  double t_ = 0.0;
  model::ImuReading previous_;
  bool has_previous_ = false;
};

}  // namespace legkit::invariant
