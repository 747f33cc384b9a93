// The error-state (multiplicative) extended Kalman filter of section 57.5, the classic filter of
// FAST-LIO2-style systems, for a quadruped: IMU-driven prediction, one foot-position measurement
// per stance foot.
//
// Nominal state and error state. The filter carries a nominal state
//   x = (R, v, p, d_1..d_4, b_g, b_a)
// (attitude body to world, world velocity and position, the four feet in the world, gyro and
// accelerometer biases) and a Gaussian on the small error between it and the truth, 27 numbers:
//   dx = (dtheta, dv, dp, dd_1..dd_4, db_g, db_a),   R = R_hat Exp(dtheta)   (local, body frame)
// and every other component additive (v = v_hat + dv, ...). The error's mean is zero between
// updates; only its covariance P (27 x 27) is propagated.
//
// Prediction. The nominal state follows the strapdown equations with the previous IMU sample
// held over dt, w = w_m - b_g and f = a_m - b_a, integrated exactly for constant input:
//   R+ = R Exp(w dt),  v+ = v + R Gamma_1(w dt) f dt + g dt,
//   p+ = p + v dt + R Gamma_2(w dt) f dt^2 + g dt^2 / 2,   d, b_g, b_a unchanged.
// The error obeys, to first order (continuous time, noises n_g, n_a, random walks n_*):
//   d(dtheta)/dt = -[w]_x dtheta - db_g - n_g
//   d(dv)/dt     = -R_hat [f]_x dtheta - R_hat db_a - R_hat n_a
//   d(dp)/dt     = dv
//   d(dd_i)/dt   = n_d,i,   d(db_g)/dt = n_bg,   d(db_a)/dt = n_ba
// i.e. d(dx)/dt = F(x_hat, u) dx + G n. F depends on the estimate (R_hat, b_hat) and on the
// measured input: this is the section's point of comparison with the invariant EKF, whose A
// (lie/imu_dynamics.hpp) is constant on the navigation block.
//
// Discretisation. Phi is not the first-order I + F dt: it is the exact Jacobian of the discrete
// nominal step above with respect to the error (the derivative of x+(x_hat (+) dx) (-) x+(x_hat)
// at dx = 0), built in closed form from Exp, Gamma_1, Gamma_2, Jr and the derivatives of
// Gamma_m(phi) f (lie::imu::dGammaTimesVector). It agrees with I + F dt to first order in dt;
// the difference (terms like -R_hat [f]_x dtheta dt^2 / 2 in dp) is what a first-order ESKF
// drops. Phi is the identity except on the rows (dtheta, dv, dp), which depend on
// (dtheta, dv, dp) and (db_g, db_a) only; the filter uses that structure
// (P <- Phi P Phi^T touches only 9 rows and columns).
// Process noise from the continuous densities (model::ImuNoise): sigma_g^2 dt on dtheta; per axis
// sigma_a^2 [[dt, dt^2/2], [dt^2/2, dt^3/3]] on (dv, dp) (white acceleration integrated once and
// twice); sigma_bg^2 dt, sigma_ba^2 dt on the biases; sigma_d^2 dt on each foot, with
// sigma_d = foot_stance_density in stance (the foot may slip a little) and foot_swing_density in
// swing (the foot moves freely); a stance foot of contact probability p_c (the previous sample's
// ContactMeasurement::probability) gets the soft density of section 57.6,
// p_c sigma_stance^2 + (1 - p_c) sigma_swing^2 (p_c = 1: the stance density exactly). The noises
// are isotropic, so R_hat drops out of R_hat n_a.
//
// Measurement of a stance foot i: the leg kinematics give the foot in the body frame,
//   z_i = h_i(x) + n,   h_i(x) = R^T (d_i - p),   n ~ N(0, Cov_i)   (the ContactMeasurement).
// With R = R_hat Exp(dtheta), R^T = Exp(-dtheta) R_hat^T, so h_i = h_hat + [h_hat]_x dtheta and
//   H_i = [ [h_hat]_x  (dtheta),  -R_hat^T (dp),  R_hat^T (dd_i) ],  zero elsewhere.
// The feet are processed one after the other (3 x 3 innovations), all linearised at the same
// predicted nominal state, which equals one stacked update. Covariance update in Joseph form,
//   P <- (I - K H) P (I - K H)^T + K Cov K^T,
// computed with H's nine non-zero columns only (each foot is a few rank-3 products, not 27 x 27
// matrix products).
//
// Heading rule (feet_correct_yaw = false, the default). Turning the whole state about gravity
// changes no IMU reading and no leg measurement: absolute yaw is unobservable. The gyro bias
// about the vertical is observable from the feet only through accelerations, and then only as
// well as the legs' scale is known: legs that read a speed short by a fraction e, turning at
// rate omega, ask for a yaw rate off by e omega (0.4 rad/s and 5 %: 1.2 deg/s, the real Go1's
// "about 1 deg per second while turning"). No real robot's legs are known to a few percent; with
// the rule no foot corrects the heading: the gain loses the part that turns the robot about the
// vertical through its base (the attitude, the velocity and the feet about the base turned
// together, the position kept) and the part along the gyro bias about the vertical, R_hat^T e_z,
//   K <- (I - alpha E) K   (the Joseph form below is exact for any gain),
// and the heading drifts as the gyro integrates it. alpha (heading_rule.hpp) is the rule's share:
// 1 while the robot turns (the low-passed yaw rate at FilterParams::heading_turn_rate or more)
// and while the slip detector accuses a foot, falling to 0 as the robot walks straight, where a
// leg-scale error tells no false turn and the feet may learn the vertical gyro bias (57.5, "Its
// share by the turn rate", measures it). Measured with the whole rule (alpha = 1; legkit run
// --scenario ..., chapter 57.5): physics-real yaw 1.44 deg (the gyro alone 1.46; with
// heading corrections 5.7-6.0), position 0.09 m (0.13); the ideal physics trot, where the exact leg
// scale lets the feet learn the bias, pays for it: yaw 1.59 against 0.65-0.90, position 0.21-0.25 m
// against 0.20-0.23 m. The default, because it holds on every robot measured: on the eight physics
// scenarios each filter's yaw stays within 0.02 deg of the gyro's (0.04 on the iCub log), where
// heading corrections lose it on physics-real (above) and physics-ice (2.7 / 1.6 deg against 0.70).
// What it costs is on a robot whose legs are exact, whose feet would learn the gyro bias: the 300 s
// analytic trot (legkit run --scenario trot --duration 300 --config FILE with correct_yaw true /
// false): yaw 1.5 / 0.7 deg (ESKF / InEKF) against the rule's 5.4 and the gyro's 4.7, position
// 1.9 / 0.7 m against 4.6 / 1.9 m. And a defect not yet understood: there the ESKF's (and the
// TSIF's) position covariance follows the growing heading variance only in part, the InEKF's in
// full (ANEES 1.33 against 0.77; on the analytic front end without a file, 5.37 against 1.00;
// the plain filters 0.50 and 0.45). A robot with legs calibrated to a fraction of a percent sets
// feet.correct_yaw: true.
//
// Gating (section 57.9, GatingParams, off by default): before a stance foot's update, its
// innovation r (against the error mean of the feet before it) is tested with d^2 = r^T S^-1 r,
// S its sequential innovation covariance, against the chi-square quantile of 3 dof; a gated foot
// is skipped for that sample (Fault::kGated). A foot gated for longer than max_gated_time is
// re-initialised from its measurement as at a touchdown (engineering/gating.hpp: lock-out).
//
// Injection and reset. After the updates the error mean dx_hat is moved into the nominal state,
// x_hat <- x_hat (+) dx_hat (R_hat <- R_hat Exp(dtheta_hat), the rest added), and the error is
// reset to zero. The new error is dtheta+ = dtheta - dtheta_hat - [dtheta_hat/2]_x dtheta to
// first order, so P <- G P G^T with G = blockdiag(I - [dtheta_hat/2]_x, I, ..., I).
//
// Contacts. A foot that touches down (in stance now, not at the previous sample) is
// re-initialised from the kinematics after the update: d_i = p_hat + R_hat z_i, and its rows of P
// become those of that function of the state, dd_i = dp - R_hat [z_i]_x dtheta + R_hat n, i.e.
// correlated with attitude and position and with Cov_i added. Its measurement at touchdown is
// used only for that (using it again as an update would count it twice). A foot in stance at two
// consecutive samples is a measurement. At reset the feet are unknown (weak prior
// foot_init_sigma) and every foot is out of contact.
//
// Pose update (section 57.8, "pose injection": the map is this filter's world frame). A pose z =
// (R_m, p_m) in the world with noise (n_theta, n_p) ~ N(0, z.cov), R_m = Exp(n_theta) R,
// p_m = p + n_p. With R = R_hat Exp(dtheta) = Exp(R_hat dtheta) R_hat, the residual
//   r = (Log(R_m R_hat^T), p_m - p_hat) = (R_hat dtheta, dp) + n   (to first order),
//   H = [R_hat (dtheta); I (dp)], zero elsewhere,
// updated in Joseph form and injected as the feet are. Gated (when gating is on) by
// d^2 = r^T S^-1 r against the chi-square quantile of 6 dof (Fault::kGated).
//
// Flat feet (params.flat_feet, settings feet.flat; DILIGENT-KIO's foot pose, Ramadoss et al.
// 2021). A humanoid's sole has an orientation that stays put while it stands, and the kinematics
// measure it: Z = R_BF, the foot frame in the body, with noise Z = Z_true Exp(n), n ~ N(0,
// rot_cov) in the foot frame (ContactMeasurement::R_body). The filter keeps two feet, each with
// its position d_i and its rotation R_F,i (foot to world), in the same 27 numbers:
//   dx = (dtheta, dv, dp, dd_1, dd_2, dphi_1, dphi_2, db_g, db_a),   R_F = R_F,hat Exp(dphi)
// (a local error, as the attitude's). The rotation is constant in stance up to a random walk of
// density foot_rotation_stance_density (soft contact as for the position), free in swing.
// Measurement, with h = R^T R_F: (R_hat Exp(dtheta))^T R_F,hat Exp(dphi) =
// h_hat Exp(-h_hat^T dtheta) Exp(dphi), so
//   r = Log(h_hat^T Z) = dphi_i - h_hat^T dtheta + n,   H = [ -h_hat^T (dtheta), I (dphi_i) ],
// a second 3 x 3 update after the foot's position (only when the position was used; outside the
// gate and the NIS windows). At touchdown R_F = R_hat Z, and R = R_hat Exp(dtheta) gives
// dphi_i = Z^T dtheta - n: its rows of P are Z^T times those of dtheta, plus rot_cov. The
// injection and the reset treat dphi_i as the attitude's dtheta (R_F <- R_F Exp(dphi_hat),
// G = I - [dphi_hat / 2]_x). The heading rule holds a sole's update as it holds a position's: a
// sole tells the body's rotation against a foot that does not turn, through the encoders' angles
// with no leg scale in it, so it observes the gyro bias about the vertical (absolute yaw stays
// unobservable: turning the body and the soles together changes no h); but a sole's heading is
// also where the kinematics' own error lands (an ankle's offset, a foot that twists on its rubber
// while it stands), and while the robot turns nothing tells that from the gyro's bias. So the
// soles get the rule's share alpha as the positions do, the turn about the base being R_F^T e_z
// on each sole's error. Measured on the iCub log (legkit run --log data/icub-walking/walking.csv,
// config/robots/icub.yaml; position RMSE, roll/pitch and yaw RMS, the gyro alone 2.39 deg from a
// zero gyro bias, 0.29 deg from the still window's): point feet 0.026 m, 0.61 deg, 2.39 deg from
// zero, 0.010 m, 0.58, 0.20 from the still window; flat feet 0.015 m, 0.57, 1.30 and 0.008 m,
// 0.54, 0.26. With the soles outside the rule: flat feet 0.017 m, 0.57,
// 1.68 from zero and 0.012 m, 0.93 deg from the still window, 0.64 deg worse than the gyro's
// yaw: once the bias is known, the soles' heading is their own error. How much the sole is
// trusted matters too (frontend.foot_rotation_sigma, log_frontend.hpp).
//
// covariance() maps the local attitude error to the kit's world-frame convention:
// R = R_hat Exp(dtheta) = Exp(R_hat dtheta) R_hat, so dtheta_w = R_hat dtheta; v and p are
// additive in both.
//
// All matrices are fixed-size Eigen: step() never allocates.
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
#include "estimation/invariant/nominal_state.hpp"
#include "lie/so3.hpp"
#include "model/imu_model.hpp"
#include "model/imu_noise.hpp"

namespace legkit::invariant {

namespace eskf {

// The state, its error vector (and its flat feet's layout), the strapdown step and h_i are the
// TSIF's too: this namespace extends the shared one (nominal_state.hpp), so eskf::State is
// nominal::State.
using namespace nominal;  // NOLINT(google-build-using-namespace)

// F of d(dx)/dt = F dx + G n at the estimate x and input u (file comment): the chapter's
// state-dependent error dynamics, for analysis and teaching (the filter uses Phi below).
Matrix27 errorDynamics(const State& x, const model::ImuReading& u);

// Phi = d(propagate(x (+) dx) (-) propagate(x)) / d(dx) at dx = 0. Only the rows
// (dtheta, dv, dp) differ from the identity, and they depend only on (dtheta, dv, dp) and
// (db_g, db_a): those two blocks are all that is stored.
struct Transition {
  Eigen::Matrix<double, 9, 9> nav;   // rows (dtheta, dv, dp) x columns (dtheta, dv, dp)
  Eigen::Matrix<double, 9, 6> bias;  // rows (dtheta, dv, dp) x columns (db_g, db_a)
  Matrix27 matrix() const;           // the full 27 x 27 Phi
};
Transition transition(const State& x, const model::ImuReading& u, double dt);

}  // namespace eskf

// The family's block (filter_params.hpp) and the prior of the feet, in the state from reset.
struct EskfParams : FilterParams {
  double foot_init_sigma = 1.0;  // prior of the (unknown) feet at reset [m]
};

class Eskf final : public Estimator {
 public:
  // Throws std::invalid_argument for a negative noise density, a non-positive prior sigma or a
  // non-finite gravity. A zero bias random walk is a constant bias (nominal_state.hpp).
  explicit Eskf(const EskfParams& params = {});

  std::string name() const override { return "eskf"; }
  // Base from x0, biases zero, feet unknown and out of contact; P from the Params sigmas.
  void reset(const EstimateSample& x0) override;
  // As Estimator::initialise says; the tilt prior is about the world x and y axes.
  void initialise(const InitialState& s) override;
  // Prediction over in.dt with the previous IMU sample, then the stance feet; bad input and
  // faults as estimation/estimator.hpp's contract says.
  void step(const StepInput& in) override;
  EstimateSample estimate() const override;
  // The (dtheta_w, dv, dp) block of P with the attitude error mapped to the world frame.
  std::optional<BaseCovariance> covariance() const override;
  // NIS: windows (innovation_windows.hpp) of the foot updates of p_c >= kNisMinProbability that
  // were used, each with its sequential innovation r and S.
  std::optional<InnovationStats> stanceInnovations() const override { return innovations_; }
  // The pose z (world = map frame) as a measurement of the base pose, applied to the current
  // state whatever z.t (DelayedFilter applies it at its stamp). File comment: "Pose update".
  // Throws std::invalid_argument naming the field and z.t for a non-finite pose or a covariance
  // that is not symmetric positive definite, before anything changes; kNotValid, kGated, kFailed
  // change nothing but the health record.
  fusion::PoseUpdate updatePose(const fusion::PoseMeasurement& z);

  const eskf::State& state() const { return x_; }
  const eskf::Matrix27& P() const { return P_; }
  bool inContact(int i) const { return in_contact_[i]; }
  // Flat feet: foot i's rotation R_F (foot to world), placed at its touchdown; i < kFlatFeet.
  const lie::SO3d& footRotation(int i) const { return foot_R_[i]; }

 private:
  void predict(double dt);
  enum class Update { kDone, kFailed, kGated, kReinitialise };
  // kFailed (nothing changed) when the innovation covariance does not factorise; kGated or
  // kReinitialise (nothing changed) when the gate rejects the innovation.
  Update updateFoot(int i, const ContactMeasurement& c, double t, eskf::Vector27& dx);
  // A flat foot's orientation (file comment, "Flat feet"); kFailed as updateFoot.
  Update updateFootRotation(int i, const ContactMeasurement& c, double t, eskf::Vector27& dx);
  // One 3-dimensional measurement of foot i: residual z - h(x_hat), Jacobian blocks H over the
  // error blocks at cols, noise cov; the heading rule and the Joseph form, and for a position
  // the gate and the NIS windows (of a contact of this probability p_c).
  enum class Measured { kPosition, kRotation };
  template <int Blocks>
  Update correct(int i, const std::array<int, Blocks>& cols,
                 const Eigen::Matrix<double, 3, 3 * Blocks>& H, const Eigen::Vector3d& residual,
                 const Eigen::Matrix3d& cov, double t, Measured measured, double probability,
                 eskf::Vector27& dx);
  // Foot position states: four, or two with flat feet (their rotations take the other two).
  int numPointFeet() const { return params_.flat_feet ? eskf::kFlatFeet : eskf::kFeet; }
  void inject(const eskf::Vector27& dx);
  void initialiseFoot(int i, const ContactMeasurement& c);

  EskfParams params_;
  engineering::FootGate gate_;
  HeadingRule heading_;            // alpha of the heading rule (heading_rule.hpp)
  InnovationWindows nis_windows_;  // the stance-foot NIS (stanceInnovations())
  double pose_gate_;  // chi-square quantile of 6 dof for the pose innovation (file comment)
  FootSlots<eskf::kFeet> slots_;  // foot ids of the log -> this filter's foot states
  eskf::State x_;
  eskf::Matrix27 P_ = eskf::Matrix27::Identity();  // covariance of the error dx
  std::array<bool, eskf::kFeet> in_contact_{};
  std::array<double, eskf::kFeet> probability_{};  // p_c of the feet in contact (previous sample)
  std::array<lie::SO3d, eskf::kFlatFeet> foot_R_;  // flat feet: R_F, foot to world
  std::array<bool, eskf::kFeet> rotation_held_{};  // flat: R_F placed at this stance's touchdown
  double t_ = 0.0;
  model::ImuReading previous_;
  bool has_previous_ = false;
};

}  // namespace legkit::invariant
