// The linear Kalman filter of section 57.4, in the style of the MIT Cheetah estimator
// (Bledt, Di Carlo et al. 2018): attitude comes from a separate attitude filter and is treated as
// a known input, which leaves a state whose dynamics and measurements are exactly linear.
//
// State (18 numbers, all in the world frame):
//   x = [p, v, d_FL, d_FR, d_RL, d_RR]       base position, base velocity, the four feet.
//
// Prediction (zero-order hold of the previous IMU sample over dt, eq. x+ = F x + B u):
//   u = R_hat (a_m - b_a_hat) + g           world acceleration from the accelerometer
//   F = I + [0 I dt 0; 0 0 0; ...]          p <- p + v dt, everything else unchanged
//   B = [dt^2/2 I; dt I; 0]                 the held acceleration integrated once and twice
//   P <- F P F^T + Q
// Process noise Q:
//   - navigation block: the accelerometer's white noise is a sampled noise held over dt, so it
//     enters exactly as the input does, B Sigma_u B^T with Sigma_u = sigma_a^2 / dt I (per axis
//     [[dt^3/4, dt^2/2], [dt^2/2, dt]] sigma_a^2 on (p, v));
//   - attitude error: u uses R_hat, not R. With R = Exp(theta) R_hat the input is off by
//     [f_w]_x theta (f_w = R_hat (a_m - b_a), the specific force in the world). theta is the
//     attitude filter's error, slowly varying with correlation time tau (about 1 / k_P); a
//     correlated error of covariance C and correlation time tau integrates like a white noise of
//     density 2 tau C, so Sigma_u gets 2 tau [f_w]_x Sigma_theta [f_w]_x^T / dt as well;
//   - feet: sigma_d^2 dt I per foot (a random walk), with the density scheduled by contact: small
//     in stance (the foot may slip a little), large in swing (the foot moves freely). Q over the
//     interval (t_{k-1}, t_k] uses the contact flags of sample k-1, known when it starts. A stance
//     foot with contact probability p_c (ContactMeasurement::probability) gets the soft density
//     of section 57.6, Q_f = [p_c sigma_stance^2 + (1 - p_c) sigma_swing^2] I dt; p_c = 1 is the
//     hard stance density exactly.
// Because F is the identity plus one dt block, F P F^T is done as two block additions (rows then
// columns of p get dt times those of v), never as an 18 x 18 product.
//
// Measurement of stance foot i (leg kinematics, the body-frame foot position r_i = p_body):
//   z_i = R_hat r_i = d_i - p + n_i,         H_i = [-I 0 ... I (at d_i) ... 0]
// With R = Exp(theta) R_hat, R_hat r_i = Exp(-theta) R r_i is off by [z_i]_x theta, so
//   n_i = R_hat dr_i + [z_i]_x theta,        own part R_hat Cov(r_i) R_hat^T.
// Swing feet: the chapter gives them a huge R, which makes their gain K = 0. Skipping their
// update is the exact limit of that (with K = 0 the Joseph update leaves x and P unchanged),
// cheaper and free of the round-off a 1e4-sized R brings; the large swing process noise is what
// lets the first stance measurement after touchdown place the foot, with a gain close to one on
// d_i.
//
// Optional velocity measurement (leg odometry, section 57.3), on by default: with the stance feet
// that carry a body-frame velocity r_dot_i, the mean of their base velocities
// v_i = -R_hat (w x r_i + r_dot_i), weighted by their contact probabilities p_c,i (a foot's
// Cov(r_dot_i) = sigma_rdot^2 I / p_c,i: the contact term of 57.6's soft R_i; p_c = 0 drops it),
// equals the velocity from one virtual foot at the weighted centroid,
//   z_v = -R_hat (w x r_bar + r_dot_bar),    r_bar = sum p_c,i r_i / W,  r_dot_bar likewise,
// W = sum p_c,i, with w = w_m - b_g_hat, so leg_odometry::baseVelocityFromFoot /
// baseVelocityCovariance give it and its own covariance directly, with Cov(r_bar) =
// sum p_c,i^2 Cov(r_i) / W^2, Cov(r_dot_bar) = sigma_rdot^2 I / W (hard feet: W = k, the plain
// mean), and the gyro sample noise sigma_g^2 / dt counted once (it is common to all feet, so
// averaging does not reduce it). Its attitude part is [z_v]_x theta. H_v = [0 I 0 ...].
//
// One stacked update. The measurements of a sample are NOT independent: every block carries the
// same attitude error theta, and the velocity shares the feet's kinematic noise through r_bar.
// So all stance feet and the velocity form one measurement of at most 3 x 4 + 3 = 15 rows, with
// the full noise covariance, block (a, b):
//   R_ab = delta_ab Own_a + [z_a]_x Sigma_theta [z_b]_x^T          (attitude: every pair)
//        + R_hat Cov(r_i) (p_c,i / W) [w]_x R_hat^T   for a = foot i with r_dot_i, b = the velocity
// (the last from dz_i = R_hat dr_i and dz_v = -R_hat [w]_x dr_bar; its transpose for (v, i)).
// Processing the blocks one after the other with their diagonal R_aa alone would drop the
// off-diagonal blocks and claim more information than there is (the tests measure by how much).
// The stacked matrices are fixed-size Eigen, one instantiation per number of 3-row blocks (1 to
// 5): no allocation.
//
// Covariance update in Joseph form, P <- (I - K H) P (I - K H)^T + K R K^T, expanded with
// N = P H^T (18 x m) and S = H N + R:
//   K = N S^-1,   P <- P - K N^T - N K^T + K S K^T = P + K V^T + V K^T,   V = K S / 2 - N.
// This is the Joseph expression term by term, so it keeps its defining property: an error in K
// changes P only to second order (the short form P <- (I - K H) P does not), and the result is
// symmetric by construction. H is never formed: its identity blocks make N a set of P's column
// differences and H N a set of N's row differences.
//
// Gating (section 57.9, GatingParams, off by default): before the stacked update, each stance
// foot's block is tested on its own, d^2 = y_i^T S_ii^-1 y_i with S_ii = H_i P H_i^T + R_ii (its
// marginal in the stacked S), against the chi-square quantile of 3 dof; a gated foot is left out
// of the stack and of the velocity's centroid (Fault::kGated). The velocity block, built from the
// feet that passed, is tested the same way and left out when it fails. A foot gated for longer
// than max_gated_time is re-initialised from its measurement, d_i = p_hat + z_i with the rows of
// P of p plus its own noise (engineering/gating.hpp: lock-out); a velocity gated that long is used.
//
// Attitude. The filter owns an AttitudeFilter (attitude_filter.hpp) and steps it first, with the
// same previous IMU sample. An accelerometer cannot tell a tilt from a horizontal acceleration,
// and a tilt error is expensive here: pitch error times forward speed becomes a vertical velocity
// error in every leg measurement. So the filter hands the attitude filter its own estimate of the
// base's world acceleration, a_w = the change of v per step low-passed over
// accel_compensation_time, and the attitude filter levels against a_m - R_hat^T a_w: the legs,
// through v, tell it which part of a_m is motion. Its covariance Sigma_theta enters Q and R as
// above.
//
// covariance() reports the (dv, dp) block in the kit's BaseCovariance order (theta, v, p), with
// has_attitude = false; its attitude block holds the attitude filter's own covariance, not
// correlated with the rest (for plots only).
//
// Everything is fixed-size Eigen: step() never allocates.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>

#include "estimation/engineering/gating.hpp"
#include "estimation/estimator.hpp"
#include "estimation/foot_slots.hpp"
#include "estimation/innovation_windows.hpp"
#include "estimation/linear_kf/attitude_filter.hpp"
#include "model/imu_model.hpp"
#include "model/imu_noise.hpp"

namespace legkit::linear_kf {

constexpr int kFeet = 4;               // FL FR RL RR
constexpr int kDim = 6 + 3 * kFeet;    // 18
constexpr int kP = 0, kV = 3, kD = 6;  // offsets of p, v and the first foot in x
// Offset of foot i (0..3) in x.
constexpr int footIndex(int i) {
  return kD + 3 * i;
}

using Vector18 = Eigen::Matrix<double, kDim, 1>;
using Matrix18 = Eigen::Matrix<double, kDim, kDim>;
using Matrix18x3 = Eigen::Matrix<double, kDim, 3>;
using Matrix3x18 = Eigen::Matrix<double, 3, kDim>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;
// The stacked measurement of one sample: every stance foot and the velocity, at most 15 rows.
constexpr int kMaxRows = 3 * kFeet + 3;
using ContactMask = std::array<bool, kFeet>;  // true: foot in stance

// Process-noise densities of the model (continuous time, discretised by the functions below).
struct ProcessNoise {
  double accel_density = 0.04;         // sigma_a [m/s^2/sqrt(Hz)], accelerometer white noise
  double foot_stance_density = 0.001;  // sigma_d in stance [m/sqrt(s)]
  double foot_swing_density = 10.0;    // sigma_d in swing [m/sqrt(s)] (the chapter's 1e2 m^2/s)
};

// The matrices of x+ = F x + B u, P+ = F P F^T + Q (file comment), dense, for teaching and the
// exercises. The filter uses the same building blocks below without forming them.
struct ProcessModel {
  Matrix18 F;
  Eigen::Matrix<double, kDim, 3> B;
  Matrix18 Q;
};
// Throws std::invalid_argument for dt <= 0 or a negative density.
ProcessModel processModel(double dt, const ContactMask& contact, const ProcessNoise& noise);

// B's non-zero block, [dt^2/2 I; dt I] (rows p, v).
Eigen::Matrix<double, 6, 3> inputMatrix(double dt);
// Q's (p, v) block: B Sigma_u B^T for an input covariance Sigma_u (sigma_a^2 / dt I for the
// accelerometer noise alone).
Matrix6 navigationNoise(double dt, const Eigen::Matrix3d& Sigma_u);
// Q's block of one foot is this times I: sigma_d^2 dt with the swing density, or in stance the
// soft density of contact probability p_c (eq. Q_f of 57.6; p_c = 1: the stance density).
double footNoiseVariance(double dt, bool in_stance, const ProcessNoise& noise, double p_c = 1.0);

// H_i = [-I 0 ... I (columns of foot i) ... 0]. Throws std::invalid_argument for i outside 0..3.
Matrix3x18 footMeasurementMatrix(int i);
// H_v = [0 I 0 ... 0].
Matrix3x18 velocityMeasurementMatrix();
// The Joseph update for an m-row measurement, given N = P H^T (18 x m), S = H N + R and a gain K:
//   P <- P + K V^T + V K^T,  V = K S / 2 - N,
// which is (I - K H) P (I - K H)^T + K R K^T expanded, for any K (the filter passes N S^-1).
// The filter calls it with fixed-size matrices (m = 3 per stacked block), so it never allocates.
template <typename GainType, typename NType, typename SType>
void josephUpdate(Matrix18& P, const Eigen::MatrixBase<GainType>& K,
                  const Eigen::MatrixBase<NType>& N, const Eigen::MatrixBase<SType>& S) {
  // (I - K H) P (I - K H)^T + K R K^T = P - K N^T - N K^T + K S K^T = P + K V^T + V K^T
  // (K V^T + V K^T is formed before it is added, so that P stays exactly symmetric.)
  Eigen::Matrix<double, kDim, GainType::ColsAtCompileTime, 0, kDim, GainType::MaxColsAtCompileTime>
      V = -N;
  V.noalias() += 0.5 * K.lazyProduct(S);  // coefficient-wise products: the inner size is small
  Matrix18 W;
  W.noalias() = K.lazyProduct(V.transpose());
  P += W + W.transpose();
}

// The diagonal block of R for stance foot i:
//   R_ii = R_hat Cov(r) R_hat^T + [R_hat r]_x Sigma_theta [R_hat r]_x^T.
Eigen::Matrix3d footMeasurementNoise(const Eigen::Matrix3d& R_hat, const Eigen::Vector3d& r,
                                     const Eigen::Matrix3d& cov_r,
                                     const Eigen::Matrix3d& Sigma_theta);
// The block of R between two measurements that share the attitude error, with z_a, z_b their
// world vectors (R_hat r for a foot): R_ab = [z_a]_x Sigma_theta [z_b]_x^T. Between two stance
// feet this is the whole off-diagonal block.
Eigen::Matrix3d attitudeNoiseBlock(const Eigen::Vector3d& z_a, const Eigen::Vector3d& z_b,
                                   const Eigen::Matrix3d& Sigma_theta);

struct LinearKfParams {
  // Sensor densities: the simulator's Go2-class IMU (model::ImuNoise::go2()).
  model::ImuNoise imu = model::ImuNoise::go2();
  // Feet: a foot that does not slip barely moves in stance (the simulator's feet never slip);
  // a swing foot moves ~0.1 m in 0.2 s, far less than the swing density's 10 * sqrt(0.2) = 4.5 m.
  double foot_stance_density = 0.001;  // [m/sqrt(s)]
  double foot_swing_density = 10.0;    // [m/sqrt(s)]
  // Accelerometer bias, assumed known (not estimated by this filter) [m/s^2].
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();
  // Leg-odometry velocity measurement (file comment) and the noise of the body-frame foot
  // velocity r_dot per axis (encoder-rate noise through the leg Jacobian, ~0.01 rad/s * 0.3 m).
  bool use_leg_velocity = true;
  double foot_velocity_sigma = 0.005;  // [m/s]
  // Account for the attitude filter's error in Q and R (file comment).
  bool model_attitude_error = true;
  double attitude_correlation_time = 1.0;  // tau [s], about 1 / k_P
  // Give the attitude filter the base's world acceleration, a_w = the filter's velocity change
  // per step low-passed with this time constant [s] (0: do not, plain accelerometer tilt).
  double accel_compensation_time = 0.05;
  // Prior standard deviations at reset (per axis).
  double sigma_position = 0.01;   // [m]
  double sigma_velocity = 0.05;   // [m/s]
  double foot_init_sigma = 1.0;   // feet unknown until their first stance measurement [m]
  AttitudeFilterParams attitude;  // the attitude filter the linear KF owns
  Eigen::Vector3d gravity = model::gravity();
  InputLimits limits;  // sensor ranges and the largest dt integrated (estimation/health.hpp)
  engineering::GatingParams gating;  // innovation gate of the feet and the velocity (file comment)

  // The densities processModel() uses.
  ProcessNoise processNoise() const {
    return {imu.accel_noise_density, foot_stance_density, foot_swing_density};
  }
};

class LinearKf final : public Estimator {
 public:
  // Throws std::invalid_argument for a negative density or sigma, a non-positive prior, a
  // non-positive correlation time or a non-finite gravity (and whatever AttitudeFilter rejects).
  explicit LinearKf(const LinearKfParams& params = {});

  std::string name() const override { return "linear-kf"; }
  // p, v from x0, feet unknown (at p, variance foot_init_sigma^2) and out of contact; the
  // attitude filter from x0's attitude with zero gyro bias.
  void reset(const EstimateSample& x0) override;
  // reset(s.x), then the attitude filter's gyro bias from s.b_g and, when s.sigma_tilt is given,
  // its roll and pitch prior; s.b_a replaces the known accelerometer bias (Params::b_a) until the
  // next initialise().
  void initialise(const InitialState& s) override;
  // Prediction over in.dt with the previous IMU sample (attitude filter first), then one stacked
  // update of the stance feet and the leg-odometry velocity. Bad input and faults as
  // estimation/estimator.hpp's contract says.
  void step(const StepInput& in) override;
  EstimateSample estimate() const override;
  std::optional<BaseCovariance> covariance() const override;
  // NIS: windows of each foot block of the stacked update (innovation_windows.hpp; not the
  // leg-odometry velocity), y_i and its marginal S_ii, p_c >= kNisMinProbability.
  std::optional<InnovationStats> stanceInnovations() const override { return innovations_; }

  const Vector18& x() const { return x_; }
  const Matrix18& P() const { return P_; }
  const AttitudeFilter& attitude() const { return attitude_; }
  const LinearKfParams& params() const { return params_; }

 private:
  void predict(double dt, const Eigen::Vector3d& f_w);
  // The stance feet and, when w_m is given (this sample's gyro reading, or the held one), the
  // leg-odometry velocity, as one stacked update with the full R (file comment). False (nothing
  // changed) when S does not factorise.
  bool updateStance(const StepInput& in, const Eigen::Vector3d* w_m,
                    const Eigen::Matrix3d& Sigma_theta);

  // The gate of one 3-row block (id: a foot, or kFeet for the velocity) with innovation y and
  // marginal S; records Fault::kGated when it decides kGate.
  engineering::FootGate::Decision gateBlock(int id, const Eigen::Vector3d& y,
                                            const Eigen::Matrix3d& S, double t);
  // d_i = p_hat + z_i, its rows of P those of p plus own on the diagonal (a touchdown's placement).
  void placeFoot(int i, const Eigen::Vector3d& z, const Eigen::Matrix3d& own);

  LinearKfParams params_;
  engineering::FootGate gate_;
  InnovationWindows nis_windows_;  // the stance-foot NIS (stanceInnovations())
  FootSlots<kFeet> slots_;         // foot ids of the log -> this filter's foot states
  AttitudeFilter attitude_;
  Vector18 x_ = Vector18::Zero();
  Eigen::Vector3d a_w_ = Eigen::Vector3d::Zero();  // low-passed world acceleration of the base
  Matrix18 P_ = Matrix18::Identity();
  ContactMask previous_contact_{};
  std::array<double, kFeet> previous_probability_{};  // p_c of the stance feet of sample k-1
  model::ImuReading previous_;
  bool has_previous_ = false;
  double t_ = 0.0;
};

}  // namespace legkit::linear_kf
