#include "robot_command.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <memory>

#include "estimation/settings.hpp"
#include "io/log_reader.hpp"
#include "model/mujoco_kinematics.hpp"
#include "output.hpp"
#include "validators.hpp"

namespace legkit::tools {
namespace {

// The joints of a log row in LegKinematics' order: q_<leg>_<j> or joint<k>_q.
model::LegJointVector jointAngles(const io::LogLayout& layout, const io::LogRow& row) {
  model::LegJointVector q = model::LegJointVector::Zero();
  if (layout.num_joints > 0) {
    q.head(layout.num_joints) = row.joint_q.head(layout.num_joints);
  } else {
    q.head<io::kNumJoints>() = row.q;
  }
  return q;
}

// One line per foot: id, name and B_p_f at q [m].
void printFeet(std::ostream& out, const model::LegKinematics& legs,
               const model::LegJointVector& q) {
  std::size_t width = 0;
  for (int f = 0; f < legs.numFeet(); ++f) width = std::max(width, legs.footName(f).size());
  Eigen::Vector3d p;
  model::FootJacobian J;
  for (int f = 0; f < legs.numFeet(); ++f) {
    legs.foot(f, q, p, J);
    out << "    foot" << f << "  " << std::left << std::setw(static_cast<int>(width))
        << legs.footName(f) << std::right << std::fixed << std::setprecision(4) << std::setw(9)
        << p.x() << std::setw(9) << p.y() << std::setw(9) << p.z() << "\n";
  }
}

}  // namespace

RobotCommand::RobotCommand(CLI::App& app)
    : command_(app.add_subcommand(
          "robot", "The robot of a settings file as the kit sees it: joints, feet, mass")) {
  CLI::App& c = *command_;
  // Not CLI::ExistingFile: a file that cannot be read is an input error (exit 2) like a bad one.
  c.add_option("settings", settings_, "Settings file whose robot section to show")
      ->check(nonEmptyName())
      ->required();
  // Within a turn either way (any joint angle is one there): a larger value is in degrees.
  c.add_option(
       "--angles", angles_,
       "Joint angles [rad], comma-separated, in the joint order printed: the feet there too")
      ->check(finiteRange(-2.0 * M_PI, 2.0 * M_PI))
      ->delimiter(',');
  c.add_option("--log", log_,
               "A log for this robot: its joints must be the robot's; the feet at its first row")
      ->check(nonEmptyName());
}

int RobotCommand::run(std::ostream& out) const {
  const Settings settings = loadSettings(settings_);
  const RobotSettings& robot = settings.robot;
  const std::unique_ptr<model::LegKinematics> legs =
      model::makeLegKinematics(robot.model, robot.base, robot.feet, robot.joints);
  const int n = legs->numJoints();
  if (!angles_.empty() && static_cast<int>(angles_.size()) != n) {
    throw UsageError("--angles: " + std::to_string(angles_.size()) +
                     " angles given, the robot of " + settings_ + " has " + std::to_string(n) +
                     " joints");
  }
  for (std::size_t k = 0; k < angles_.size(); ++k) {
    if (!std::isfinite(angles_[k])) {
      throw UsageError("--angles: angle " + std::to_string(k) + " is not a finite number");
    }
  }
  io::Log log;
  if (!log_.empty()) {
    log = io::readLog(log_);
    const int columns = log.layout.num_joints > 0 ? log.layout.num_joints
                        : log.layout.joints       ? io::kNumJoints
                                                  : 0;
    if (columns != n || (log.layout.num_joints > 0) != !robot.model.empty()) {
      throw InputError(
          log_ + ": the log's joints are not the robot's: it has " +
          (log.layout.num_joints > 0
               ? std::to_string(columns) + " generic joint columns (joint<k>_q)"
           : log.layout.joints ? std::string("the built-in quadruped's columns (q_<leg>_<j>)")
                               : std::string("no joint columns (foot columns)")) +
          ", the robot of " + settings_ + " " +
          (robot.model.empty() ? std::string("is the built-in quadruped (q_<leg>_<j> columns)")
                               : "has " + std::to_string(n) + " joints (joint0_q .. joint" +
                                     std::to_string(n - 1) + "_q, robot.joints)"));
    }
    if (log.rows.empty()) throw InputError(log_ + ": the log has no rows");
  }

  out << "robot of " << settings_ << "\n";
  out << "  model   " << (robot.model.empty() ? "the built-in Go2-class quadruped" : robot.model)
      << "\n";
  if (!robot.base.empty()) out << "  base    " << robot.base << "\n";
  const double mass = robotMass(settings, legs.get());
  out << "  mass    " << std::fixed << std::setprecision(3) << mass
      << (robot.mass > 0.0 ? " kg (robot.mass)\n" : " kg (the sum of the model's bodies)\n");
  const contact::SchmittParams f = detectorContext(settings, mass, legs->numFeet()).schmitt;
  out << "  contact schmitt f_high " << std::setprecision(1) << f.f_high << " N, f_low " << f.f_low
      << " N, saturation " << f.saturation << " N"
      << (settings.schmitt.f_high ? " (contact.schmitt)\n"
                                  : " (auto: the Go2 design scaled to m g / n_feet)\n");
  const model::ImuExtrinsic& T = settings.imu_extrinsic;
  out << "  IMU     at [" << std::setprecision(5) << T.p_BI.x() << ", " << T.p_BI.y() << ", "
      << T.p_BI.z() << "] m in the base frame, R_BI = [w x y z] [" << T.q_BI.w() << ", "
      << T.q_BI.x() << ", " << T.q_BI.y() << ", " << T.q_BI.z() << "] (imu.extrinsic)\n";
  out << "  joints  " << n << ", in the log's column order:\n";
  for (int k = 0; k < n; ++k) {
    const std::string column = robot.model.empty() ? "" : "joint" + std::to_string(k) + "_q";
    out << "    " << std::left << std::setw(robot.model.empty() ? 0 : 11) << column << std::right
        << legs->jointName(k) << "\n";
  }
  out << "  feet    " << legs->numFeet() << ", in the base frame [m], x y z:\n";
  out << "   at zero angles\n";
  printFeet(out, *legs, model::LegJointVector::Zero());
  if (!angles_.empty()) {
    model::LegJointVector q = model::LegJointVector::Zero();
    for (int k = 0; k < n; ++k) q[k] = angles_[static_cast<std::size_t>(k)];
    out << "   at --angles\n";
    printFeet(out, *legs, q);
  }
  if (!log_.empty()) {
    out << "   at " << log_ << "'s first row (t = " << std::setprecision(3) << log.rows[0].t
        << " s)\n";
    printFeet(out, *legs, jointAngles(log.layout, log.rows[0]));
  }
  return kExitOk;
}

}  // namespace legkit::tools
