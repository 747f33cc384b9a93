// Bloesch's two-state implicit filter (TSIF, section 57.5; Bloesch, Burri, Sommer, Siegwart and
// Hutter, "The Two-State Implicit Filter - Recursive Estimation for Mobile Robots", RA-L 2017).
//
// Explicit filters (the KFs and the InEKF of this section) write a process model
// x_{k+1} = f(x_k, u_k) and a measurement model z = h(x). The TSIF writes neither: every piece of
// information is a residual that should be zero, and a residual may involve the state at two
// consecutive instants. Each step solves one small weighted least-squares problem over the pair
// (x_k, x_{k+1}) and then forgets x_k:
//
//   min  || x_k (-) x_hat_k ||^2_{Lambda_k}                          prior on x_k
//      + || r_imu(x_k, x_{k+1}, u_k) ||^2_{W_imu}                    IMU between the two states
//      + sum_i || d_{i,k+1} - d_{i,k} ||^2_{W_c,i}                   feet: still in stance,
//                                                                    a weak random walk in swing
//      + sum_stance || R_{k+1}^T (d_{i,k+1} - p_{k+1}) - p_body,i ||^2_{Cov_i^-1}   kinematics
//
// by Gauss-Newton (at most `iterations`, stopping once the step of x_{k+1} has dx1^T S dx1 below
// `step_tolerance`, S the information of x_{k+1} given both states' residuals), and the new
// estimate of x_{k+1} is its marginal: x_k is forgotten. For a linear Gaussian model this is
// exactly the Kalman filter; with one Gauss-Newton iteration started from the IMU prediction it is
// the EKF, and a second iteration re-linearises the IMU and kinematics residuals around the
// improved pair (an iterated filter that also smooths x_k). The prediction and the update are no
// longer separate stages: the IMU is just another residual, and a contact switches on or off by
// changing one residual's weight.
//
// State x = (R, v, p, d_1..d_4, b_g, b_a): attitude (body to world), world velocity and position,
// the four feet in the world, gyro and accelerometer biases. Error (tangent) vector, 27 entries,
//   dx = (dtheta, dv, dp, dd_1..dd_4, db_g, db_a),   R = R_hat Exp(dtheta)   (local, body-frame
// attitude error; the rest additive). covariance() maps dtheta to the kit's world-frame
// convention, dtheta_w = R_hat dtheta.
//
// IMU residual (previous sample u_k = (w_m, a_m) held over dt, phi = (w_m - b_g,k) dt,
// f = a_m - b_a,k; the exact solution of the strapdown equations for constant input, as
// lie::imu::propagate integrates it):
//   r_R  = Log( Exp(phi)^T R_k^T R_{k+1} )
//   r_v  = v_{k+1} - v_k - g dt - R_k Gamma_1(phi) f dt
//   r_p  = p_{k+1} - p_k - v_k dt - g dt^2/2 - R_k Gamma_2(phi) f dt^2
//   r_bg = b_g,k+1 - b_g,k,   r_ba = b_a,k+1 - b_a,k
// Its noise Q (imuNoise) is what the continuous densities integrate to over dt: sigma_g^2 dt on
// r_R; on (r_v, r_p) per axis sigma_a^2 [[dt, dt^2/2], [dt^2/2, dt^3/3]] (white acceleration
// integrated once and twice); sigma_bg^2 dt and sigma_ba^2 dt on the biases. A zero random walk
// (a constant bias, the contract of nominal_state.hpp) is a zero block: the two states share one
// bias.
//
// Solver. The normal equations of the pair are 54 x 54; the filter solves them in covariance form,
// which is the same solution with x_k eliminated through its prior's covariance P_k instead of its
// information. Linearised at (x_k, x_{k+1}), the prior says delta_0 = e_0 + A dx_0 ~ N(0, P_k)
// (e_0 = x_k (-) x_hat_k, A = Jr^-1(e_0,theta)), and the residuals between the two states
// r_b + J_0 dx_0 + J_1 dx_1 = -n, n ~ N(0, Q), so that
//   dx_1 = mu + G delta_0 - J_1^-1 n,   G = -J_1^-1 J_0 A^-1,   mu = -(G e_0 + J_1^-1 r_b):
// a prediction of x_{k+1} with covariance P_1 = G P_k G^T + J_1^-1 Q J_1^-T (G is the identity
// but on the navigation rows: at the first iteration, the ESKF's Phi). The kinematics residuals
// r + H dx_1 = n' are then one stacked Kalman update of it (at most 12 rows: four feet, or two
// flat feet with their soles), dx_1 = mu + K nu, nu = -(r + H mu); x_k's step is its smoothed
// estimate given x_{k+1}'s, delta_0 = P_k G^T P_1^-1 (dx_1 - mu). The marginal covariance of
// x_{k+1} is that of the last iteration's update (in the Joseph form, as the ESKF's), moved to the
// tangent at x_{k+1} (+) dx_1 as the ESKF's reset does (P <- G P G^T, G = I - [dtheta/2]_x). So with one
// iteration the filter is the ESKF, with its feet stacked instead of sequential (the same in
// exact arithmetic). An earlier version kept the information Lambda and factorised the 27 x 27
// blocks of the normal equations, and formed the new information from the same Jacobians with
// two 27 x 27 inversions: 28.9 us a step against 9.7 now (bench_tsif, one iteration, idle; the
// ESKF 4.5), for the same numbers.
// Every matrix is fixed-size Eigen: step() never allocates. Ceres was the other candidate;
// building a ceres::Problem, its residual blocks and its sparse linear solver anew 1000 times a
// second costs allocations and far more time than these few dense 27 x 27 products, and Ceres
// does not hand back the marginal, so it would be computed by hand anyway.
//
// Contacts. A stance foot's residual d_{k+1} - d_k has the small density foot_stance_density
// (slip); a swing foot gets the large foot_swing_density, so it keeps a state but barely
// constrains anything. Between the two, a stance foot of contact probability p_c
// (ContactMeasurement::probability, this sample's) gets the soft density of section 57.6,
// p_c sigma_stance^2 + (1 - p_c) sigma_swing^2: the residual's weight follows p_c continuously. A
// foot that touches down is new: it takes no part in the step's solve (a free foot whose only
// residual is its kinematics makes that residual zero whatever the base, so it tells the base
// nothing), and after it is placed at its kinematics, d = p + R p_body, with the covariance its
// Jacobian gives (nominal::placeFoot, the ESKF's touchdown). An earlier version gave the new foot
// a weak prior (1 m) instead: information the robot does not have, since its mean comes from the
// estimate. At eight touchdowns a second it added up, and over 300 s made the filter
// over-confident in position (ANEES/dof 3.5 on 2 runs; chapter 57.10).
//
// Heading rule (feet_correct_yaw = false, the default; why: eskf.hpp's "Heading rule" paragraph).
// The Gauss-Newton step of x_{k+1} loses its heading part, dx1 <- (I - alpha E) dx1 with
// E = V B^T (B picks the heading about the vertical and the gyro bias along it, V turns the robot
// about its base; alpha the rule's share, heading_rule.hpp), and the covariance is the ESKF's
// Joseph covariance for that gain, P_opt + alpha^2 V C V^T, where C = B^T (P_pred - P_opt) B is
// the 2 x 2 the feet would have taken from the heading. With one iteration the TSIF then still
// equals the ESKF (physics-real: the same 0.092 m and 1.44 deg).
//
// Gating (section 57.9, GatingParams, off by default). The TSIF has no innovation in the EKF's
// sense: the kinematics residual is one term of a joint solve. Its stand-in is the residual at the
// IMU prediction of x_{k+1}, before any kinematics enter, r_i = R^T (d_i - p) - p_body, tested
// against the prediction's covariance P_1 of the first iteration: S_i = J_i P_1 J_i^T + Cov_i,
// and d^2 = r_i^T S_i^-1 r_i against the chi-square quantile of 3 dof. With one iteration this is
// the ESKF's innovation test (both filters agree to ~1e-6). A gated foot keeps its stance residual
// but its kinematics residual is left out of the step (Fault::kGated); one gated for longer than
// max_gated_time is placed anew from its measurement as at a touchdown (engineering/gating.hpp:
// lock-out).
//
// Flat feet (params.flat_feet, settings feet.flat; the ESKF's model, eskf.hpp's "Flat feet"). The
// two feet keep their rotations R_F,i (foot to world) in the 27 numbers, dphi_i where a
// quadruped's feet 3 and 4 are, local as the attitude: R_F = R_F,hat Exp(dphi). Between the two
// states a sole stays put, Log(R_F,k^T R_F,k+1) (Jacobians -I and I, exact at the first
// iteration), with the random walk foot_rotation_stance_density (soft in p_c, as a foot's
// position) or foot_rotation_swing_density of the contact at k, as the ESKF's Q (where touchdown
// settling ends, p_c goes from 0 to 1 at k+1). At k+1 a stance sole adds the ESKF's
// r = Log(h_hat^T Z) = dphi_i - h_hat^T dtheta + n, h = R^T R_F, as the residual Log(Z^T h) = -r
// with J = H = [-h_hat^T, I] (soleResidual, nominal_state.hpp), noise rot_cov. At touchdown the
// sole is placed with its foot at R_F = R Z, with the ESKF's rows Z^T P_theta + rot_cov. The
// heading rule takes the soles' step as the positions': dx1 <- (I - alpha E) dx1 and C = B^T
// (P_pred - P_opt) B, with R_F^T e_z the turn about the base on each sole's error. No position or
// sole residual changes with the turn V, so the rest is updated optimally whatever the rule, and
// the heading and the vertical bias follow it through their correlation: with one iteration this
// follows the ESKF's update of each foot's position and then its sole (on the iCub log their
// positions differ by at most 28 um, 25 um with point feet). iCub log (legkit run,
// config/robots/icub.yaml): 0.015 m, 0.57 and 1.30 deg from a zero gyro bias, 0.008 m, 0.54 and
// 0.26 deg from the still window's; ANEES 0.55 and 0.46; the ESKF's to the table's digits.
//
// At the first sample (dt = 0, no previous IMU reading) there is no pair to solve: the filter
// stores the reading and places the feet that touch down (likewise for any later step shorter
// than kMinDt).
//
// Numerics. In information form the pair is badly scaled by nature: at 1 kHz the IMU's weight on
// position, 12 / (sigma_a^2 dt^3), is about 1e13, while a swing foot's information is of order 1,
// and the marginal of x_{k+1} formed as the Schur complement of the normal equations subtracted
// terms of 1e13 to leave the information of a position nobody observes (over-confident in lateral
// position after a few minutes: ANEES/dof 1.5 over 300 s, 4 runs; chapter 57.10). The covariance
// form never forms those weights.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>

#include "estimation/engineering/gating.hpp"
#include "estimation/estimator.hpp"
#include "estimation/foot_slots.hpp"
#include "estimation/invariant/filter_params.hpp"
#include "estimation/invariant/heading_rule.hpp"
#include "estimation/invariant/nominal_state.hpp"
#include "lie/so3.hpp"
#include "model/imu_model.hpp"
#include "model/imu_noise.hpp"

namespace legkit::invariant {

namespace tsif {

// The state, its error vector, the strapdown step and h_i are the ESKF's too: this namespace
// extends the shared one (nominal_state.hpp), so tsif::State is nominal::State.
using namespace nominal;  // NOLINT(google-build-using-namespace)

constexpr double kMinDt = 1e-5;             // [s] shorter steps are carried over to the next one
constexpr double kMinFootVariance = 1e-12;  // [m^2] (1 um)^2 added to every kinematics covariance

using Soles = std::array<lie::SO3d, kFlatFeet>;  // flat feet: R_F of each sole

using Vector15 = Eigen::Matrix<double, 15, 1>;
using Matrix15 = Eigen::Matrix<double, 15, 15>;

// The IMU residual between two states and its Jacobians. The feet do not enter it, so each
// Jacobian is 15 x 15 over the navigation blocks (dtheta, dv, dp, db_g, db_a) of its state, in
// that order (the same order as the residual's rows r_R, r_v, r_p, r_bg, r_ba).
struct ImuResidual {
  Vector15 r;
  Matrix15 J_x0;  // d r / d(x_k)
  Matrix15 J_x1;  // d r / d(x_{k+1})
};
ImuResidual imuResidual(const State& x0, const State& x1, const model::ImuReading& u, double dt,
                        const Eigen::Vector3d& g = model::gravity());

// The noise Q of that residual for the densities of `noise` over dt (file comment), in the order of
// its rows.
Matrix15 imuNoise(const model::ImuNoise& noise, double dt);

// The kinematics residual of foot i seen at p_body, R^T (d_i - p) - p_body, and its 3 x 9
// Jacobian over (dtheta, dp, dd_i) of the state.
Eigen::Vector3d kinematicsResidual(const State& x, int i, const Eigen::Vector3d& p_body,
                                   Matrix39* J_x = nullptr);

}  // namespace tsif

// The family's block (filter_params.hpp), the prior of the feet and the iterations.
struct TsifParams : FilterParams {
  double foot_init_sigma = 1.0;  // prior of the (unknown) feet at reset [m]
  int iterations = 1;            // most Gauss-Newton iterations per step
  // Stop iterating once the step of x_{k+1} is below this in its own information norm,
  // dx1^T S dx1 (twice the cost decrease the step predicts; chi-square units). Measured on the
  // 10 s bench trot (bench_tsif, BM_TsifIterationStats): every first step is below 1e-2, every
  // second one below 1e-6, so with 1e-6 a step takes at most 2 iterations (3 with 1e-12, whose
  // estimate is the same to 4 nm).
  double step_tolerance = 1e-6;
};

class Tsif final : public Estimator {
 public:
  // Throws std::invalid_argument for a non-positive white noise or foot density, sigma or
  // iteration count, a negative step tolerance, or a negative bias random walk (zero is a
  // constant bias).
  explicit Tsif(const TsifParams& params = {});

  std::string name() const override { return "tsif"; }
  // Base from x0, biases zero, feet unknown (weak prior); P from the Params sigmas.
  void reset(const EstimateSample& x0) override;
  // As Estimator::initialise says; the tilt prior is about the world x and y axes.
  void initialise(const InitialState& s) override;
  // One two-state Gauss-Newton solve and marginalisation. Bad input and faults as
  // estimation/estimator.hpp's contract says; a prediction or kinematics covariance that does not
  // factorise is a failed update (the step is not taken and the filter restarts from its
  // estimate).
  void step(const StepInput& in) override;
  EstimateSample estimate() const override;
  // The (dtheta_w, dv, dp) block of P, attitude mapped to the world frame.
  std::optional<BaseCovariance> covariance() const override;

  const tsif::State& state() const { return x_; }
  // The covariance of the error dx (tangent at state()), and its inverse, the information.
  const tsif::Matrix27& P() const { return P_; }
  tsif::Matrix27 information() const;
  bool inContact(int i) const { return in_contact_[i]; }
  // Flat feet: foot i's rotation R_F (foot to world), placed at its touchdown; i < kFlatFeet.
  const lie::SO3d& footRotation(int i) const { return foot_R_[i]; }
  // Gauss-Newton iterations the last step took, and the dx1^T S dx1 of its last stopping test (0
  // when it had none: the last allowed iteration needs none, so one iteration never has one).
  int lastIterations() const { return last_iterations_; }
  double lastStepNorm2() const { return last_step_norm2_; }

 private:
  // Foot i's contact at this sample, c (nullptr: none), for the next: in contact and its p_c.
  void holdContact(int i, const ContactMeasurement* c);
  // The end of every step: the held IMU sample, the time and the health check.
  void finishStep(const StepInput& in, bool imu_admitted);
  // The contract's failed update (a covariance that does not factorise): the step is not taken;
  // the filter restarts from its estimate before it, and the sample counts as a first sample.
  void failedUpdate(const StepInput& in, bool imu_admitted);
  // Foot i touches down (file comment, "Contacts", "Flat feet"): placed in x and P_ at its
  // kinematics, d = p + R p_body, and a flat foot's sole in R_F at R Z.
  void placeFoot(int i, const ContactMeasurement& c, tsif::State& x, tsif::Soles& R_F);

  TsifParams params_;
  engineering::FootGate gate_;
  HeadingRule heading_;           // alpha of the heading rule (heading_rule.hpp)
  FootSlots<tsif::kFeet> slots_;  // foot ids of the log -> this filter's foot states
  tsif::State x_;
  tsif::Soles foot_R_;                             // flat feet: R_F, foot to world
  std::array<bool, tsif::kFeet> rotation_held_{};  // flat: R_F placed at this stance's touchdown
  tsif::Matrix27 P_ = tsif::Matrix27::Identity();  // covariance of the error dx (tangent at x_)
  std::array<bool, tsif::kFeet> in_contact_{};
  std::array<double, tsif::kFeet> probability_{};  // p_c of the feet in contact (flat: the soles')
  double t_ = 0.0;
  model::ImuReading previous_;
  bool has_previous_ = false;
  int last_iterations_ = 0;
  double last_step_norm2_ = 0.0;
  double pending_dt_ = 0.0;  // time of the steps shorter than kMinDt, not yet solved over
};

}  // namespace legkit::invariant
