// Contact detection (section 57.6): the one small interface every detector of the kit implements,
// so that the run pipeline, the studies and the estimator manager of section 57.11 can swap them.
//
// A detector sees what a robot measures, one sample at a time (ContactSignals): per foot a force
// reading and the leg's kinematics, the IMU, the joint torques when the robot reports them, and
// the base estimate of the previous step (the chicken-and-egg rule of 57.6: detect with the last
// estimate, use the detection in this step). It never sees ground truth. It answers per foot a
// hard flag, a contact probability p_c and whether it could decide at all: a detector whose input
// is missing or broken for a foot (no force column, a NaN torque, a sensor stuck at saturation)
// says so in `problem` instead of answering "no contact", and the fallback chain
// (fallback_detector.hpp) hands that foot to the next detector.
//
// Robot-agnostic: any number of feet up to kMaxFeet, each a foot id. Fixed size: update() never
// allocates.
#pragma once

#include <Eigen/Core>
#include <array>
#include <limits>
#include <string>

#include "estimation/estimate.hpp"
#include "estimation/leg_odometry/contact_span.hpp"

namespace legkit::contact {

constexpr int kMaxFeet = leg_odometry::kMaxContacts;
constexpr int kNumJoints = 12;  // the built-in quadruped's joints (3 per leg, FL FR RL RR)
using JointVector = Eigen::Matrix<double, kNumJoints, 1>;

// What the robot measures about one foot at one sample.
struct FootSignals {
  // Normal force from a foot sensor [N]; NaN when the robot has none (or the reading is lost).
  double force = std::numeric_limits<double>::quiet_NaN();
  // The leg's kinematics, when known: foot position and velocity relative to the body, body
  // frame (p = FK(q), v = J(q) dq for a jointed leg) [m], [m/s].
  bool has_kinematics = false;
  Eigen::Vector3d p_body = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_body = Eigen::Vector3d::Zero();
};

// The base state of the previous estimator step (world frame), for the detectors that need it
// (kinematic, momentum observer). valid is false before the first estimate.
struct BaseFeedback {
  bool valid = false;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // body to world
  Eigen::Vector3d v = Eigen::Vector3d::Zero();      // [m/s]
  Eigen::Vector3d p = Eigen::Vector3d::Zero();      // [m]
};

// The feedback of an estimator's estimate x (the previous step's, 57.6's chicken-and-egg rule).
inline BaseFeedback feedbackFrom(const EstimateSample& x) {
  return {true, x.q.toRotationMatrix(), x.v, x.p};
}

struct ContactSignals {
  double t = 0.0;   // sample time [s]
  double dt = 0.0;  // since the previous sample [s]; 0 at the first
  int num_feet = 4;
  std::array<FootSignals, kMaxFeet> feet{};
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();  // body rate as measured [rad/s]
  Eigen::Vector3d acc = Eigen::Vector3d::Zero();   // specific force as measured [m/s^2]
  BaseFeedback base;
  // Joint space of the built-in quadruped, for the detectors that use its dynamics (force from
  // joint torques, momentum observer). has_torque is false when the log has no tau columns.
  bool has_joints = false;
  JointVector q = JointVector::Zero(), dq = JointVector::Zero();
  bool has_torque = false;
  JointVector tau = JointVector::Zero();
};

// One foot's answer.
struct FootContact {
  bool contact = false;      // the hard decision
  double probability = 0.0;  // p_c in [0, 1]; 0 or 1 for a detector that only decides
  // The force the detector decided on [N] (measured or estimated), NaN when it used none.
  double force = std::numeric_limits<double>::quiet_NaN();
  // Why this detector could not decide for this foot at this sample (a static string such as
  // "force is NaN", "force stuck at saturation", "no torque columns"); nullptr when it could.
  // When set, `contact` and `probability` mean nothing and a caller must not read them as "no
  // contact".
  const char* problem = nullptr;
  bool usable() const { return problem == nullptr; }
};

struct ContactEstimate {
  double t = 0.0;
  int num_feet = 0;
  std::array<FootContact, kMaxFeet> feet{};
};

class ContactDetector {
 public:
  virtual ~ContactDetector() = default;
  virtual std::string name() const = 0;
  // Forgets everything (timers, integrals, the previous sample): the next update() is a first one.
  virtual void reset() = 0;
  // Every foot's contact at one sample. Throws std::invalid_argument (naming the field and the
  // time) only for input no caller can mean: num_feet outside [1, kMaxFeet], dt < 0 or not
  // finite. A bad reading of one foot is not an exception: that foot's answer carries a problem.
  virtual ContactEstimate update(const ContactSignals& signals) = 0;
};

}  // namespace legkit::contact
