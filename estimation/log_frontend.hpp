// Turns the rows of a log into estimator inputs (StepInput): the only place where a log's leg
// description meets a robot model.
//  - quadruped joints: a foot in contact becomes p_body = FK(q), v_body = J(q) dq, with
//    covariance J Cov(q) J^T + sigma_foot^2 I (encoder noise mapped through the leg, plus the
//    contact-point uncertainty of a round foot);
//  - generic joints (joint<k>_ columns, a robot's own URDF or MJCF): the same, through a
//    model::LegKinematics (FK, J and J Cov(q) J^T + sigma_foot^2 I exactly as above);
//  - robot-agnostic foot columns: p_body and its covariance are taken as the log gives them; the
//    velocity from the foot<k>_v columns when the log has them, otherwise from
//    FootVelocityDifferentiator (below) when the caller hands one in, otherwise none.
// Frames. Joints, generic joints and foot columns all describe the feet in the BASE frame; with
// an IMU extrinsic (model/imu_extrinsic.hpp) every foot is moved into the IMU frame, the
// estimators' body: p_I = R_BI^T (p_B - p_BI), v_I = R_BI^T v_B, Cov_I = R_BI^T Cov_B R_BI
// (estimation/imu_extrinsic_frames.hpp). With the identity extrinsic (the default) base = IMU and
// nothing is transformed.
// Which feet are in stance comes either from the log's contact columns (input(row, dt); a log
// without them yields no contacts), or from a contact detector (section 57.6): signals() gives
// the detector what the robot measured, and input(row, dt, estimate, soft) turns its answer into
// stance feet weighted by their contact probability. estimation/contact_pipeline.hpp chains the
// two for a whole run.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "estimation/contact/contact_detector.hpp"
#include "estimation/contact/soft_contact.hpp"
#include "estimation/step_input.hpp"
#include "io/log.hpp"
#include "model/imu_extrinsic.hpp"
#include "model/leg_kinematics.hpp"
#include "model/quadruped.hpp"

namespace legkit {

struct FrontendNoise {
  double encoder_angle_sigma = 1.75e-4;  // [rad] per joint (about 0.01 deg)
  double foot_point_sigma = 0.005;       // contact point on a round foot [m]
  // Flat feet (feet.flat, section 57.5): each contact also carries the foot's orientation R_BF
  // from the robot's own model, with covariance J_w Cov(q) J_w^T (in the foot frame) plus
  // foot_rotation_sigma^2 I. That floor is how flat a foot in "contact" really is: a force
  // threshold calls a foot down at heel strike and still at toe-off, when a 0.2 m sole with one
  // end 1 cm off the ground is tilted by 0.05 rad (3 deg), and the sole rolls between the two.
  // Measured on the iCub log (config/robots/icub.yaml, ESKF position RMSE and yaw RMS, from its
  // still-window gyro bias; point feet 0.010 m, 0.20 deg, the gyro alone 0.29 deg): 0.01 rad
  // 0.013 m, 0.37 deg (the sole trusted flatter than it is); 0.02 0.012, 0.32; 0.03 0.010, 0.31;
  // 0.05 0.008, 0.26; 0.1 0.009, 0.23. From a zero gyro bias (point feet 0.026 m, 2.39 deg):
  // 0.017, 1.25; 0.017, 1.22; 0.015, 1.26; 0.015, 1.30; 0.017, 1.48. 0.05 is the physical figure
  // above, and the sweep's best position both ways; the one flat-footed log in the kit is the
  // iCub's, so it holds on one robot's walk so far.
  bool foot_rotations = false;
  double foot_rotation_sigma = 0.05;  // [rad]
};

// The differentiator's time constant [s]. Measured on the 5 s analytic trot (seed 7, the kit's
// encoder noise of 1.75e-4 rad, 1 kHz) against the exact J dq of every stance sample
// (test_frontend_feet): RMS error 0.113 m/s unfiltered, 0.032 / 0.027 / 0.026 / 0.026 / 0.031
// m/s at tau = 2 / 3 / 4 / 5 / 7 ms, 0.054 m/s at 15 ms (lag: a stance foot's velocity relative
// to the bouncing body changes within tens of milliseconds). 4 ms is the minimum; a log with
// noisier positions wants a longer one.
constexpr double kFootVelocityTau = 0.004;

// The velocity of each foot relative to the body from its positions alone, for logs of foot
// columns without foot<k>_v columns. Causal, per foot:
//   y_k = (p_k - p_{k-1}) / dt_k                  (backward difference)
//   v_k = v_{k-1} + a_k (y_k - v_{k-1}),  a_k = max(dt_k / (tau + dt_k), 1 / n_k)
// a first-order low pass of time constant tau that starts as the mean of the n_k differences
// since the foot touched down (in stance now, not at the previous row). The touchdown row itself
// takes v = y (its difference spans the last swing interval) and is forgotten at the next row:
// the swing's velocity never leaks into the stance. A foot has no velocity before its second row
// after reset(); a row with dt = 0 keeps the last velocity. Fixed size: update() never allocates.
class FootVelocityDifferentiator {
 public:
  // Throws std::invalid_argument for a tau that is negative or not finite.
  explicit FootVelocityDifferentiator(double tau = kFootVelocityTau);
  void reset();
  // One row: the feet's positions (any frame fixed to the body), whether each is in stance, and
  // dt from the previous row.
  void update(const std::array<Eigen::Vector3d, io::kMaxFeet>& p,
              const std::array<bool, io::kMaxFeet>& down, int num_feet, double dt);
  // The filtered velocity of foot `foot` after the last update(), none before its second row.
  const std::optional<Eigen::Vector3d>& velocity(int foot) const { return v_[foot]; }
  double tau() const { return tau_; }

 private:
  double tau_;
  std::array<std::optional<Eigen::Vector3d>, io::kMaxFeet> p_previous_;
  std::array<std::optional<Eigen::Vector3d>, io::kMaxFeet> v_;
  std::array<bool, io::kMaxFeet> down_{};
  std::array<int, io::kMaxFeet> samples_{};  // differences averaged since the touchdown
};

class LogFrontend {
 public:
  // A log of quadruped joints or of foot columns. Throws std::invalid_argument for a layout with
  // generic joints (they need the constructor below) or with no leg description.
  LogFrontend(const io::LogLayout& layout, const model::QuadrupedKinematics& kinematics,
              const FrontendNoise& noise = {}, const model::ImuExtrinsic& extrinsic = {});
  // A log of generic joints (layout.num_joints > 0) through `legs`, which must outlive the front
  // end (and its copies). Throws std::invalid_argument when the layout has no generic joints or
  // its joint or foot count differs from legs'.
  LogFrontend(const io::LogLayout& layout, const model::LegKinematics& legs,
              const FrontendNoise& noise = {}, const model::ImuExtrinsic& extrinsic = {});
  LogFrontend(const io::LogLayout&, const model::LegKinematics&&, const FrontendNoise& = {},
              const model::ImuExtrinsic& = {}) = delete;  // a temporary would dangle

  // The input of row k of a log (dt measured from row k-1, 0 for k = 0). On a log of foot
  // columns without velocity columns, `velocities` (when given) is updated with the row and
  // gives the stance feet their v_body; without it they have none.
  StepInput input(const io::LogRow& row, double dt,
                  FootVelocityDifferentiator* velocities = nullptr) const;
  // Every row of `log` as an input, dt measured between rows (for tests and benchmarks that
  // replay a log with the conversion kept out of what they measure); foot velocities of a log
  // of foot columns without them from a FootVelocityDifferentiator run over the whole log.
  std::vector<StepInput> inputs(const io::Log& log) const;

  // What a contact detector may see of row k: the force column of each foot (NaN without one),
  // the leg kinematics (FK and J dq of the joints or generic joints, or the foot columns when the
  // log has their velocity columns; none for foot columns without them), in the IMU frame, the
  // IMU, q, dq and tau when the log has the quadruped's, and `base`, the estimate of the
  // previous step. Never the contact_ or gt_ columns.
  contact::ContactSignals signals(const io::LogRow& row, double dt,
                                  const contact::BaseFeedback& base) const;
  // The input of row k with the stance feet a detector decided: a foot is in stance when its
  // answer is usable, says contact and has p_c >= soft.min_probability; its covariance is the
  // soft one, R / (p_c + eps) + R_swing (1 - p_c) (contact/soft_contact.hpp), and its
  // ContactMeasurement::probability is p_c. `velocities` as for input(row, dt), with the
  // detector's answers as the stance flags.
  StepInput input(const io::LogRow& row, double dt, const contact::ContactEstimate& contacts,
                  const contact::SoftContactParams& soft,
                  FootVelocityDifferentiator* velocities = nullptr) const;

  const io::LogLayout& layout() const { return layout_; }
  const model::ImuExtrinsic& extrinsic() const { return extrinsic_; }
  // The quadruped model (its geometry serves the rolling foot; unused for other logs).
  const model::QuadrupedKinematics& quadruped() const { return kinematics_; }
  // Whether the stance feet need a FootVelocityDifferentiator for their v_body: foot columns
  // without velocity columns.
  bool differentiatesFeet() const {
    return layout_.foot_columns != io::FootCovariance::kNone && !layout_.foot_velocity;
  }

 private:
  // The input of row k without its feet.
  StepInput imuInput(const io::LogRow& row, double dt) const;
  // Foot `foot` of row k as a stance measurement in the IMU frame, with the covariance of a
  // certain contact; v_body from `velocities` on a log that differentiates its feet.
  ContactMeasurement measurement(const io::LogRow& row, int foot,
                                 const FootVelocityDifferentiator* velocities) const;
  // The same in the base frame (before the extrinsic).
  ContactMeasurement baseMeasurement(const io::LogRow& row, int foot) const;
  // Feeds row k's foot columns, in the IMU frame, to `velocities` with the stance flags `down`.
  void differentiate(const io::LogRow& row, double dt, const std::array<bool, io::kMaxFeet>& down,
                     FootVelocityDifferentiator* velocities) const;

  io::LogLayout layout_;
  model::QuadrupedKinematics kinematics_;
  const model::LegKinematics* legs_ = nullptr;  // generic joints only
  FrontendNoise noise_;
  model::ImuExtrinsic extrinsic_;
  bool moves_feet_ = false;  // a non-identity extrinsic
};

}  // namespace legkit
