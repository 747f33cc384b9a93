#include "io/log_columns.hpp"

#include <stdexcept>
#include <unordered_map>

namespace legkit::io {
namespace {

constexpr std::array<const char*, 3> kAxes = {"x", "y", "z"};
// Upper triangle of a symmetric 3x3 matrix, row by row.
constexpr std::array<const char*, 6> kCovNames = {"xx", "xy", "xz", "yy", "yz", "zz"};
constexpr std::array<int, 6> kCovRow = {0, 0, 0, 1, 1, 2};
constexpr std::array<int, 6> kCovCol = {0, 1, 2, 1, 2, 2};

std::string jointName(const char* prefix, int joint) {
  return std::string(prefix) + "_" + kLegNames[joint / kJointsPerLeg] + "_" +
         std::to_string(joint % kJointsPerLeg);
}

std::string footName(int foot) {
  return "foot" + std::to_string(foot);
}

// force_FL (quadruped logs) or foot0_force (logs described by foot columns only).
std::string perFootName(const char* what, int foot, bool leg_names) {
  if (leg_names) return std::string(what) + "_" + kLegNames[foot];
  return footName(foot) + "_" + what;
}

void appendVector(std::vector<Column>& out, const std::string& prefix, Field field) {
  for (int i = 0; i < 3; ++i) out.push_back({prefix + kAxes[i], field, 0, i});
}

void appendJoints(std::vector<Column>& out, const char* prefix, Field field) {
  for (int j = 0; j < kNumJoints; ++j) out.push_back({jointName(prefix, j), field, 0, j});
}

// joint<k>_q for every k, then joint<k>_dq (the quadruped's order: angles, then velocities).
void appendGenericJoints(std::vector<Column>& out, int num_joints, bool velocity) {
  for (int k = 0; k < num_joints; ++k) {
    out.push_back({"joint" + std::to_string(k) + "_q", Field::kJointQ, 0, k});
  }
  for (int k = 0; velocity && k < num_joints; ++k) {
    out.push_back({"joint" + std::to_string(k) + "_dq", Field::kJointDq, 0, k});
  }
}

void appendFootVelocity(std::vector<Column>& out, int foot) {
  const std::string f = footName(foot);
  for (int i = 0; i < 3; ++i) out.push_back({f + "_v" + kAxes[i], Field::kFootV, foot, i});
}

void appendFootKinematics(std::vector<Column>& out, int foot, FootCovariance covariance) {
  const std::string f = footName(foot);
  for (int i = 0; i < 3; ++i) out.push_back({f + "_p" + kAxes[i], Field::kFootP, foot, i});
  if (covariance == FootCovariance::kDiagonal) {
    for (int i = 0; i < 3; ++i) out.push_back({f + "_var_" + kAxes[i], Field::kFootVar, foot, i});
  } else if (covariance == FootCovariance::kFull) {
    for (int i = 0; i < 6; ++i) {
      out.push_back({f + "_cov_" + kCovNames[i], Field::kFootCov, foot, i});
    }
  }
}

void appendGroundTruth(std::vector<Column>& out, bool velocity, bool valid) {
  appendVector(out, "gt_p", Field::kGtP);
  constexpr std::array<const char*, 4> kQuat = {"w", "x", "y", "z"};
  for (int i = 0; i < 4; ++i) out.push_back({std::string("gt_q") + kQuat[i], Field::kGtQ, 0, i});
  if (velocity) appendVector(out, "gt_v", Field::kGtV);
  if (valid) out.push_back({"gt_valid", Field::kGtValid, 0, 0});
}

// The contact_truth group of `feet` feet, kind by kind (as force_ and contact_).
void appendContactTruth(std::vector<Column>& out, int feet, bool leg_names) {
  for (int k = 0; k < feet; ++k)
    out.push_back({perFootName("gt_contact", k, leg_names), Field::kGtContact, k, 0});
  for (int k = 0; k < feet; ++k)
    out.push_back({perFootName("gt_fn", k, leg_names), Field::kGtFn, k, 0});
  for (int k = 0; k < feet; ++k)
    out.push_back({perFootName("gt_ft", k, leg_names), Field::kGtFt, k, 0});
  for (int k = 0; k < feet; ++k) {
    const std::string vf = perFootName("gt_vf", k, leg_names) + "_";
    for (int i = 0; i < 3; ++i) out.push_back({vf + kAxes[i], Field::kGtVf, k, i});
  }
  for (int k = 0; k < feet; ++k)
    out.push_back({perFootName("gt_slip", k, leg_names), Field::kGtSlip, k, 0});
}

// Every name the format knows, including both spellings of the per-foot columns.
std::unordered_map<std::string, Column> buildNameTable() {
  std::vector<Column> all;
  all.push_back({"t", Field::kTime, 0, 0});
  appendVector(all, "gyro_", Field::kGyro);
  appendVector(all, "acc_", Field::kAcc);
  appendJoints(all, "q", Field::kQ);
  appendJoints(all, "dq", Field::kDq);
  appendJoints(all, "tau", Field::kTau);
  appendGenericJoints(all, kMaxJoints, true);
  for (int k = 0; k < kMaxFeet; ++k) {
    for (bool leg_names : {false, true}) {
      if (leg_names && k >= kNumLegs) continue;
      all.push_back({perFootName("force", k, leg_names), Field::kForce, k, 0});
      all.push_back({perFootName("contact", k, leg_names), Field::kContact, k, 0});
    }
    appendFootKinematics(all, k, FootCovariance::kDiagonal);
    appendFootKinematics(all, k, FootCovariance::kFull);
    appendFootVelocity(all, k);
  }
  appendGroundTruth(all, true, true);
  appendContactTruth(all, kMaxFeet, false);
  appendContactTruth(all, kNumLegs, true);
  std::unordered_map<std::string, Column> table;
  for (Column& c : all) {
    const std::string name = c.name;
    table.emplace(name, std::move(c));
  }
  return table;
}

}  // namespace

std::vector<Column> columnsOf(const LogLayout& layout) {
  const bool feet = layout.foot_columns != FootCovariance::kNone;
  const bool generic = layout.num_joints > 0;
  if (layout.num_joints < 0 || layout.num_joints > kMaxJoints) {
    throw std::invalid_argument("log layout: num_joints = " + std::to_string(layout.num_joints) +
                                " (0 .. " + std::to_string(kMaxJoints) + ")");
  }
  if (!layout.joints && !feet && !generic) {
    throw std::invalid_argument(
        "log layout: needs quadruped joint columns, foot columns or generic joint columns");
  }
  if (generic && (layout.joints || feet)) {
    throw std::invalid_argument(
        "log layout: generic joint columns (num_joints > 0) exclude the quadruped joint columns "
        "and the foot columns");
  }
  if (layout.foot_velocity && !feet) {
    throw std::invalid_argument("log layout: foot velocity columns need foot columns");
  }
  if (layout.gt_valid && !layout.ground_truth) {
    throw std::invalid_argument("log layout: a gt_valid column needs the ground-truth columns");
  }
  if (!layout.joint_velocity && !layout.joints && !generic) {
    throw std::invalid_argument(
        "log layout: joint_velocity = false describes joint columns; without them leave it true");
  }
  if (!layout.gt_velocity && !layout.ground_truth) {
    throw std::invalid_argument(
        "log layout: gt_velocity = false describes a ground truth; without one leave it true");
  }
  if (layout.num_feet < 1 || layout.num_feet > kMaxFeet ||
      (layout.joints && layout.num_feet != kNumLegs)) {
    throw std::invalid_argument("log layout: num_feet = " + std::to_string(layout.num_feet) +
                                " (4 with joint columns, 1.." + std::to_string(kMaxFeet) +
                                " with foot columns or generic joints)");
  }
  if (layout.torque && !layout.joints) {
    throw std::invalid_argument("log layout: torque columns need joint columns");
  }
  std::vector<Column> out;
  out.push_back({"t", Field::kTime, 0, 0});
  appendVector(out, "gyro_", Field::kGyro);
  appendVector(out, "acc_", Field::kAcc);
  if (layout.joints) {
    appendJoints(out, "q", Field::kQ);
    if (layout.joint_velocity) appendJoints(out, "dq", Field::kDq);
  }
  appendGenericJoints(out, layout.num_joints, layout.joint_velocity);
  if (layout.torque) appendJoints(out, "tau", Field::kTau);
  if (layout.force) {
    for (int k = 0; k < layout.num_feet; ++k) {
      out.push_back({perFootName("force", k, layout.joints), Field::kForce, k, 0});
    }
  }
  if (layout.contact) {
    for (int k = 0; k < layout.num_feet; ++k) {
      out.push_back({perFootName("contact", k, layout.joints), Field::kContact, k, 0});
    }
  }
  if (feet) {
    for (int k = 0; k < layout.num_feet; ++k) appendFootKinematics(out, k, layout.foot_columns);
  }
  if (layout.foot_velocity) {
    for (int k = 0; k < layout.num_feet; ++k) appendFootVelocity(out, k);
  }
  if (layout.ground_truth) appendGroundTruth(out, layout.gt_velocity, layout.gt_valid);
  if (layout.contact_truth) appendContactTruth(out, layout.num_feet, layout.joints);
  return out;
}

std::optional<Column> columnNamed(std::string_view name) {
  static const std::unordered_map<std::string, Column> table = buildNameTable();
  const auto it = table.find(std::string(name));
  if (it == table.end()) return std::nullopt;
  return it->second;
}

double valueOf(const LogRow& row, const Column& c) {
  switch (c.field) {
    case Field::kTime:
      return row.t;
    case Field::kGyro:
      return row.gyro(c.index);
    case Field::kAcc:
      return row.acc(c.index);
    case Field::kQ:
      return row.q(c.index);
    case Field::kDq:
      return row.dq(c.index);
    case Field::kTau:
      return row.tau(c.index);
    case Field::kForce:
      return row.force[c.foot];
    case Field::kContact:
      return row.contact[c.foot] ? 1.0 : 0.0;
    case Field::kFootP:
      return row.feet[c.foot].p_body(c.index);
    case Field::kFootVar:
      return row.feet[c.foot].cov(c.index, c.index);
    case Field::kFootCov:
      return row.feet[c.foot].cov(kCovRow[c.index], kCovCol[c.index]);
    case Field::kFootV:
      return row.feet[c.foot].v_body(c.index);
    case Field::kJointQ:
      return row.joint_q(c.index);
    case Field::kJointDq:
      return row.joint_dq(c.index);
    case Field::kGtP:
      return row.gt_p(c.index);
    case Field::kGtQ:
      return c.index == 0 ? row.gt_q.w() : row.gt_q.vec()(c.index - 1);
    case Field::kGtV:
      return row.gt_v(c.index);
    case Field::kGtValid:
      return row.gt_valid ? 1.0 : 0.0;
    case Field::kGtContact:
      return row.gt_feet[c.foot].contact ? 1.0 : 0.0;
    case Field::kGtFn:
      return row.gt_feet[c.foot].normal_force;
    case Field::kGtFt:
      return row.gt_feet[c.foot].tangential_force;
    case Field::kGtVf:
      return row.gt_feet[c.foot].velocity(c.index);
    case Field::kGtSlip:
      return row.gt_feet[c.foot].slip_speed;
  }
  throw std::logic_error("valueOf: unknown field");
}

void setValue(LogRow& row, const Column& c, double value) {
  switch (c.field) {
    case Field::kTime:
      row.t = value;
      return;
    case Field::kGyro:
      row.gyro(c.index) = value;
      return;
    case Field::kAcc:
      row.acc(c.index) = value;
      return;
    case Field::kQ:
      row.q(c.index) = value;
      return;
    case Field::kDq:
      row.dq(c.index) = value;
      return;
    case Field::kTau:
      row.tau(c.index) = value;
      return;
    case Field::kForce:
      row.force[c.foot] = value;
      return;
    case Field::kContact:
      row.contact[c.foot] = value != 0.0;
      return;
    case Field::kFootP:
      row.feet[c.foot].p_body(c.index) = value;
      return;
    case Field::kFootVar:
      row.feet[c.foot].cov(c.index, c.index) = value;
      return;
    case Field::kFootCov: {
      Eigen::Matrix3d& cov = row.feet[c.foot].cov;
      cov(kCovRow[c.index], kCovCol[c.index]) = value;
      cov(kCovCol[c.index], kCovRow[c.index]) = value;  // symmetric
      return;
    }
    case Field::kFootV:
      row.feet[c.foot].v_body(c.index) = value;
      return;
    case Field::kJointQ:
      row.joint_q(c.index) = value;
      return;
    case Field::kJointDq:
      row.joint_dq(c.index) = value;
      return;
    case Field::kGtP:
      row.gt_p(c.index) = value;
      return;
    case Field::kGtQ:
      if (c.index == 0) {
        row.gt_q.w() = value;
      } else {
        row.gt_q.vec()(c.index - 1) = value;
      }
      return;
    case Field::kGtV:
      row.gt_v(c.index) = value;
      return;
    case Field::kGtValid:
      row.gt_valid = value != 0.0;
      return;
    case Field::kGtContact:
      row.gt_feet[c.foot].contact = value != 0.0;
      return;
    case Field::kGtFn:
      row.gt_feet[c.foot].normal_force = value;
      return;
    case Field::kGtFt:
      row.gt_feet[c.foot].tangential_force = value;
      return;
    case Field::kGtVf:
      row.gt_feet[c.foot].velocity(c.index) = value;
      return;
    case Field::kGtSlip:
      row.gt_feet[c.foot].slip_speed = value;
      return;
  }
  throw std::logic_error("setValue: unknown field");
}

}  // namespace legkit::io
