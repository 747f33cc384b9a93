// The column table of a log: every column name the format knows, what field of LogRow it fills,
// and the canonical order in which the writer puts them.
//
//   t                                  time [s]
//   gyro_x gyro_y gyro_z               gyro reading, body frame [rad/s]
//   acc_x acc_y acc_z                  accelerometer reading (specific force), body frame [m/s^2]
//   q_<leg>_<j>, dq_<leg>_<j>          joint angle [rad] and velocity [rad/s]; leg FL FR RL RR,
//                                      j = 0 hip abduction, 1 hip flexion, 2 knee (the dq_, or
//                                      the joint<k>_dq below, are optional: all or none)
//   tau_<leg>_<j>                      joint torque [N m]                         (optional)
//   force_<leg> | foot<k>_force        normal ground-reaction force [N]           (optional)
//   contact_<leg> | foot<k>_contact    contact flag, 0 or 1                        (optional)
//   foot<k>_px foot<k>_py foot<k>_pz   foot k in the body frame [m]               (optional)
//   foot<k>_var_x .._var_y .._var_z    its variances [m^2], or
//   foot<k>_cov_xx _xy _xz _yy _yz _zz its full covariance [m^2]
//   foot<k>_vx foot<k>_vy foot<k>_vz   its velocity relative to the body, J dq [m/s] (optional)
//   joint<k>_q, joint<k>_dq            generic joint k < 24: angle [rad], velocity [rad/s]; a
//                                      robot described by its URDF/MJCF (instead of q_/dq_ and
//                                      of foot columns)
//   gt_px gt_py gt_pz                  true base position, world [m]              (optional)
//   gt_qw gt_qx gt_qy gt_qz            true attitude, unit quaternion body to world
//   gt_vx gt_vy gt_vz                  true base velocity, world [m/s]  (optional within the
//                                      group: a motion-capture truth may give the pose only)
//   gt_valid                           1: the truth of this row is valid, 0: a dropout (any
//                                      finite gt values; never scored)       (optional)
//   gt_contact_<leg> | foot<k>_gt_contact   true contact, 0 or 1            (optional group,
//   gt_fn_<leg>      | foot<k>_gt_fn        true normal force [N], >= 0      simulation only;
//   gt_ft_<leg>      | foot<k>_gt_ft        true tangential force [N], >= 0  no estimator
//   gt_vf_<leg>_x.._z | foot<k>_gt_vf_x..   true foot velocity, world [m/s]  reads it)
//   gt_slip_<leg>    | foot<k>_gt_slip      sliding speed of the contact [m/s], >= 0
//
// Per-foot columns of a log with joint columns use the leg names (force_FL); a log described
// by foot columns or generic joints uses the foot number (foot0_force). The reader accepts
// either spelling.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/log.hpp"

namespace legkit::io {

// The field of LogRow a column fills.
enum class Field {
  kTime,
  kGyro,     // index: axis 0..2
  kAcc,      // index: axis 0..2
  kQ,        // index: joint 0..11 (3 * leg + joint)
  kDq,       // index: joint 0..11
  kTau,      // index: joint 0..11
  kForce,    // foot
  kContact,  // foot
  kFootP,    // foot, index: axis 0..2
  kFootVar,  // foot, index: axis 0..2
  kFootCov,  // foot, index: 0..5 = xx, xy, xz, yy, yz, zz
  kFootV,    // foot, index: axis 0..2
  kJointQ,   // index: generic joint 0..kMaxJoints-1
  kJointDq,  // index: generic joint 0..kMaxJoints-1
  kGtP,      // index: axis 0..2
  kGtQ,      // index: 0..3 = w, x, y, z
  kGtV,      // index: axis 0..2
  kGtValid,
  kGtContact,  // foot
  kGtFn,       // foot
  kGtFt,       // foot
  kGtVf,       // foot, index: axis 0..2
  kGtSlip,     // foot
};

struct Column {
  std::string name;
  Field field = Field::kTime;
  int foot = 0;
  int index = 0;
};

// Every column of a log with this layout, in the order the writer writes them.
std::vector<Column> columnsOf(const LogLayout& layout);

// The column a header name stands for, or nothing if the format does not know the name.
std::optional<Column> columnNamed(std::string_view name);

// Read and write one field of a row (contact flags as 0.0 / 1.0).
double valueOf(const LogRow& row, const Column& column);
void setValue(LogRow& row, const Column& column, double value);

}  // namespace legkit::io
