// One run of a legged robot as the estimators see it: a table with one row per IMU sample.
//
// This is the only input an estimator ever gets. A simulated run (sim/) and a run recorded on a
// real robot use exactly the same records; chapters/57.0-logs-and-simulator.md documents the CSV
// columns, their units and the loader's errors. The CSV side lives in io/log_reader.hpp and
// io/log_writer.hpp; this header only holds the records.
//
// Two ways to describe the legs; a log carries exactly one of them (the reader refuses both: the
// estimators would have to pick one and silently ignore the other):
//  - quadruped joints (the built-in Go2-class model): 12 joint angles and velocities, legs FL, FR,
//    RL, RR, joints per leg: hip abduction, hip flexion, knee. Foot ids 0..3 are FL..RR.
//  - robot-agnostic feet: for up to kMaxFeet feet, the foot position in the base frame and its
//    covariance, already computed by the robot's own kinematics (the base frame is the IMU's
//    unless the settings give an IMU extrinsic: the front end, estimation/log_frontend.hpp, then
//    moves the feet into the IMU frame before they become legkit::ContactMeasurement).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

namespace legkit::io {

constexpr int kNumLegs = 4;       // quadruped layout: FL, FR, RL, RR
constexpr int kJointsPerLeg = 3;  // hip abduction, hip flexion, knee
constexpr int kNumJoints = kNumLegs * kJointsPerLeg;
constexpr int kMaxFeet = 6;     // robot-agnostic layout: a biped up to a hexapod
constexpr int kMaxJoints = 24;  // generic joint columns: a hexapod's 18, a humanoid's legs

using JointVector = Eigen::Matrix<double, kNumJoints, 1>;         // index = 3 * leg + joint
using GenericJointVector = Eigen::Matrix<double, kMaxJoints, 1>;  // joint<k>_ columns, k < 24

// How the body-frame foot columns give their uncertainty.
enum class FootCovariance {
  kNone,      // the log has no foot columns
  kDiagonal,  // foot<k>_var_x, _var_y, _var_z                      [m^2]
  kFull,      // foot<k>_cov_xx, _cov_xy, _cov_xz, _cov_yy, _cov_yz, _cov_zz  [m^2]
};

// Which column groups a log carries. t, gyro_* and acc_* are always there; so is at least one of
// the two leg descriptions (joints, or feet).
struct LogLayout {
  bool joints = true;         // q_<leg>_<j>, dq_<leg>_<j> (optional)      [rad], [rad/s]
  bool torque = false;        // tau_<leg>_<j>                             [N m]
  bool force = false;         // force_<foot>: normal ground-reaction force [N]
  bool contact = false;       // contact_<foot>: 0 or 1
  bool ground_truth = false;  // gt_px..pz [m], gt_qw..qz (body to world), gt_vx..vz [m/s, world]
  int num_feet = kNumLegs;    // number of feet (4 with joints; 1..kMaxFeet with foot columns)
  FootCovariance foot_columns = FootCovariance::kNone;  // body-frame foot position columns
  // True contact per foot (simulation only): gt_contact_, gt_fn_, gt_ft_, gt_vf_<foot>_x.._z,
  // gt_slip_. No estimator reads them; they are there to score contact detection and slip.
  bool contact_truth = false;
  // Body-frame foot velocity columns foot<k>_vx, _vy, _vz (with foot_columns only): the foot's
  // velocity relative to the body, as the robot's own kinematics computed it (J(q) dq) [m/s].
  bool foot_velocity = false;
  // gt_vx..vz present (with ground_truth). A motion-capture log often has the pose only; the
  // evaluation then differentiates the pose (eval/metrics.hpp says how).
  bool gt_velocity = true;
  // A gt_valid column (with ground_truth): 0 on rows where the truth is missing (a motion-capture
  // dropout); such rows are masked out of every metric, never scored.
  bool gt_valid = false;
  // Generic joint columns joint<k>_q [rad], joint<k>_dq [rad/s], k < num_joints (kMaxJoints at
  // most): a robot described by its own URDF or MJCF (model/leg_kinematics.hpp), whose joints
  // the settings name in column order. Exclusive with `joints` and with foot columns.
  int num_joints = 0;
  // The joint velocities dq_<leg>_<j> or joint<k>_dq present (with `joints` or generic joints).
  // A log may give the angles only: the front end then differentiates them
  // (estimation/log_conditioning.hpp).
  bool joint_velocity = true;

  bool operator==(const LogLayout& o) const {
    return joints == o.joints && torque == o.torque && force == o.force && contact == o.contact &&
           ground_truth == o.ground_truth && num_feet == o.num_feet &&
           foot_columns == o.foot_columns && contact_truth == o.contact_truth &&
           foot_velocity == o.foot_velocity && gt_velocity == o.gt_velocity &&
           gt_valid == o.gt_valid && num_joints == o.num_joints &&
           joint_velocity == o.joint_velocity;
  }
  bool operator!=(const LogLayout& o) const { return !(*this == o); }
};

// A foot seen from the body, as the robot's own kinematics computed it.
struct FootKinematics {
  Eigen::Vector3d p_body = Eigen::Vector3d::Zero();  // foot position in the base frame [m]
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();     // its covariance [m^2] (diagonal if kDiagonal)
  Eigen::Vector3d v_body = Eigen::Vector3d::Zero();  // its velocity relative to the body [m/s]
};

// The true state of one foot's contact, as the physics simulator knows it (contact_truth group).
struct FootTruth {
  bool contact = false;           // the foot touches the ground
  double normal_force = 0.0;      // ground reaction along the normal [N], >= 0
  double tangential_force = 0.0;  // its magnitude in the tangent plane [N], >= 0
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // world velocity of the foot point [m/s]
  double slip_speed = 0.0;  // sliding speed of the contact point [m/s], >= 0 (0 off the ground)
};

// One IMU sample and everything measured at the same instant. Fixed size: no heap per row.
// Fields of a group the layout does not carry are left at their default (zero, false, identity).
struct LogRow {
  double t = 0.0;                                  // time [s], strictly increasing
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();  // w_m: body angular rate + bias + noise [rad/s]
  Eigen::Vector3d acc = Eigen::Vector3d::Zero();   // a_m = R^T (a - g) + b_a + n_a       [m/s^2]
  JointVector q = JointVector::Zero();             // joint angles      [rad]
  JointVector dq = JointVector::Zero();            // joint velocities  [rad/s]
  JointVector tau = JointVector::Zero();           // joint torques     [N m]
  GenericJointVector joint_q = GenericJointVector::Zero();   // joint<k>_q   [rad]
  GenericJointVector joint_dq = GenericJointVector::Zero();  // joint<k>_dq  [rad/s]
  std::array<double, kMaxFeet> force{};         // normal ground-reaction force per foot [N]
  std::array<bool, kMaxFeet> contact{};         // contact flag per foot
  std::array<FootKinematics, kMaxFeet> feet{};  // body-frame foot positions (foot columns)
  // Ground truth (simulation, motion capture): base pose and world-frame velocity.
  Eigen::Vector3d gt_p = Eigen::Vector3d::Zero();            // position in world [m]
  Eigen::Quaterniond gt_q = Eigen::Quaterniond::Identity();  // R: body to world
  Eigen::Vector3d gt_v = Eigen::Vector3d::Zero();            // velocity in world [m/s]
  bool gt_valid = true;                       // false where the truth is missing (gt_valid column)
  std::array<FootTruth, kMaxFeet> gt_feet{};  // true contact per foot (contact_truth group)
};

// Exact equality (==, no tolerance) of every field: what a write + read round trip guarantees.
bool exactlyEqual(const LogRow& a, const LogRow& b);

// A whole run. comments are the '#' lines before the header (free text: robot, scenario, seed).
struct Log {
  LogLayout layout;
  std::vector<std::string> comments;
  std::vector<LogRow> rows;
  // Where it came from, for messages that point into the file: the path (or stream name) given
  // to readLog, empty for a log made in memory.
  std::string source;

  // The 1-based line of rows[k] in its file: the comment lines, the header, then one line per
  // row. Exact for every file the reader accepts, as it allows nothing else before the last row
  // (no blank or comment line between rows; a byte-order mark is not a line, and CR, CR LF and LF
  // each end one line), and for a log made in memory it is the line the writer puts the row on.
  // Nothing is stored per row.
  std::size_t lineOfRow(std::size_t k) const { return comments.size() + 2 + k; }
};

// Leg names in column order; foot ids 0..3 of a quadruped log.
constexpr std::array<const char*, kNumLegs> kLegNames = {"FL", "FR", "RL", "RR"};

}  // namespace legkit::io
