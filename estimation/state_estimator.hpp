// The estimator manager of section 57.11: contact detection, leg odometry and a filter behind the
// one call a robot's control loop makes at every IMU sample (1 kHz on a Go2-class robot),
//   update(imu, joints, forces) -> state, covariance, contacts, health,
// configured from the settings file, plus the query a model-predictive controller makes at 50-100
// Hz: the state at the controller's own timestamp, from a ring buffer of past states (57.10's
// point 4: a state more than 2-3 ms off the query time starts the controller's prediction from the
// wrong place, so the answer says how old it is).
//
// Per update: the samples become one io::LogRow (what a log would have recorded), the contact
// pipeline (estimation/contact_pipeline.hpp: the settings' detector, p_c, rolling foot, slip
// check, settling) turns it into the filter's input with the filter's previous estimate, and the
// filter steps. Fixed size: update() and stateAt() never allocate.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "estimation/contact_pipeline.hpp"
#include "estimation/engineering/monitors.hpp"
#include "estimation/engineering/stationary_init.hpp"
#include "estimation/estimator.hpp"
#include "estimation/settings.hpp"
#include "io/log.hpp"
#include "model/imu_extrinsic.hpp"
#include "model/leg_kinematics.hpp"

namespace legkit {

// One IMU sample: w_m and a_m in the IMU (body) frame.
struct ImuSample {
  double t = 0.0;                                  // [s], strictly increasing
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();  // [rad/s]
  Eigen::Vector3d acc = Eigen::Vector3d::Zero();   // [m/s^2]
};

// The joint encoders at the same instant. The built-in quadruped has 12 joints (index 3 leg +
// joint, legs FL FR RL RR); a robot of settings.robot has its model's (up to io::kMaxJoints = 24,
// in its joint<k>_ column order). count must be the robot's joint count.
struct JointSample {
  int count = io::kNumJoints;
  io::GenericJointVector q = io::GenericJointVector::Zero();   // [rad], the first `count` used
  io::GenericJointVector dq = io::GenericJointVector::Zero();  // [rad/s]
  // False: no encoder reading this sample. The legs then give the filter nothing (IMU only);
  // the detector sees the last valid angles with zero rates.
  bool valid = true;
};

// The foot sensors at the same instant.
struct ForceSample {
  std::array<double, io::kMaxFeet> force{};  // normal force per foot [N]
  // False: no force reading this sample (the force detectors report "force is NaN" for each
  // foot; the fallback chain then falls back to the kinematic detector).
  bool valid = false;
  // The robot's own contact flags, read only when the settings' contact source is "truth".
  std::array<bool, io::kMaxFeet> contact{};
};

// How the filter was started (EstimatorOutput::start).
enum class StartMode {
  kNotStarted,   // no sample yet, or still searching for a still window
  kGiven,        // reset(x0)
  kStillWindow,  // the stationary initialiser's window (57.9): roll, pitch, gyro bias
  kGaveUp,       // no still window within max_wait: tilt from the last samples' gravity direction
  kFirstSample,  // initialisation off: tilt from the first sample's accelerometer
};
// "not started", "given", "still window", "gave up: tilt from the last samples",
// "first sample: tilt from its accelerometer".
const char* startModeName(StartMode mode);

// What update() returns.
struct EstimatorOutput {
  // The base's attitude, velocity, position at the IMU time (the filter runs in the IMU frame;
  // settings.imu_extrinsic moves it back to the base at the sample's measured rate).
  EstimateSample x;
  BaseCovariance P;             // its covariance (meaningless when !has_covariance)
  bool has_covariance = false;  // false for estimators without one (leg odometry, dead reckoning)
  contact::ContactEstimate contacts;  // per foot: the flag and p_c the filter was given
  Health health;             // the filter's faults and the pipeline's (kNoContact), since the start
  bool initialised = false;  // the filter is running; x is its estimate
  bool initialising = false;  // waiting for a still window (57.9); x is not an estimate yet
  StartMode start = StartMode::kNotStarted;  // how the filter was started (kGaveUp: a poor tilt)
  // The sensor-health monitors of 57.9 after this sample (HealthMonitor): IMU dropout, stuck
  // encoder (that leg's feet are left out of the next samples' input), force drift, covariance
  // growth, P not positive definite; `uncertain` when any is active.
  engineering::MonitorReport monitors;
  bool joints_valid = true;  // as given with this sample
  bool forces_valid = false;
};

// The state at a requested time.
struct StateQuery {
  EstimateSample x;
  // t_query - x.t [s]: 0 when interpolated between two buffered states; after the newest state
  // the newest with its age (> 0), never extrapolated.
  double age = 0.0;
  bool interpolated = false;
};

class StateEstimator {
 public:
  // Past states kept for stateAt(): 0.5 s at 1 kHz.
  static constexpr std::size_t kDefaultHistory = 500;
  // The IMU period the monitors measure a dropout against (a 1 kHz loop).
  static constexpr double kDefaultImuPeriod = 0.001;

  // The filter: the first of settings.estimators ("invariant-ekf" when the list is empty, the
  // chapter's choice for proprioception alone), made by makeEstimator(name, settings) with the
  // settings' IMU densities, limits, priors, feet, gating and its own section. The contact source:
  // settings.pipeline.contact, a detector of contact::detectorNames() (with settings.schmitt for
  // "schmitt"; gait-clock with the settings' contact.gait), or "truth" for the robot's own flags
  // in ForceSample::contact. The legs: the
  // built-in quadruped when settings.robot.model is empty, else the robot's model file
  // (model::makeLegKinematics: generic joints, its feet); the feet go into the IMU frame of
  // settings.imu_extrinsic (the front end, estimation/log_frontend.hpp). Throws
  // std::invalid_argument for an unknown estimator or detector, history == 0 or imu_period <= 0,
  // and std::runtime_error naming the file for a robot model that cannot be read.
  explicit StateEstimator(const Settings& settings, std::size_t history = kDefaultHistory,
                          double imu_period = kDefaultImuPeriod);

  // One control-loop tick. Throws std::invalid_argument naming the field and the time for a
  // time not after the previous sample's, a non-finite number in a sample marked valid, or a
  // joint count other than the robot's; then nothing changes. The start: with
  // settings.initialisation.enabled (and no reset(x0)), the IMU samples go to the stationary
  // initialiser (57.9, engineering/stationary_init.hpp) until it finds a still window: until then
  // the output says initialising and nothing is buffered; then the filter starts from its roll,
  // pitch and gyro bias (Estimator::initialise) at rest at the origin, yaw 0. When it gives up
  // (max_wait without a still window) the loop goes on: the filter starts at that sample at rest
  // at the origin, yaw 0, roll and pitch from the gravity direction of the last samples (the
  // accelerometer low-passed over one block of the window, duration / kBlocks), and the output
  // says so (start == StartMode::kGaveUp). Without it, roll and pitch from the first sample's one
  // accelerometer reading: a poor tilt, 15.7 deg off on the standing physics trot (the WARN of
  // test_state_estimator), which the window's average takes below 1 deg. reset(x0) starts from x0
  // at the next sample instead.
  // The reference stays valid until the next update() or reset().
  const EstimatorOutput& update(const ImuSample& imu, const JointSample& joints,
                                const ForceSample& forces);

  // The state at time t: between two buffered states, p and v interpolated linearly and the
  // attitude by slerp (age 0, interpolated); at a buffered state, that state (age 0); after the
  // newest, the newest (age t - its time). With nearest = true, the buffered state nearest to t,
  // age t - its time (negative when it is later than t). Throws std::out_of_range when nothing
  // is buffered yet or t is before the oldest buffered state (naming both times), and
  // std::invalid_argument for a t that is not finite.
  StateQuery stateAt(double t, bool nearest = false) const;

  // Starts over: the next update() is a first sample.
  void reset();
  // Starts over from a known state of the base (its time is ignored: the next sample's is used).
  void reset(const EstimateSample& x0);

  const EstimatorOutput& output() const { return out_; }
  std::string estimatorName() const { return estimator_->name(); }
  std::string contactSource() const { return pipeline_.source(); }
  const io::LogLayout& layout() const { return layout_; }
  // The robot's joints and feet: 12 and 4 for the built-in quadruped, else its model's.
  int numJoints() const { return legs_ ? legs_->numJoints() : io::kNumJoints; }
  int numFeet() const { return layout_.num_feet; }
  // States in the buffer, and the oldest one's time (NaN when empty).
  std::size_t buffered() const { return count_; }
  double oldestTime() const;

 private:
  // The buffered state k places back from the newest (k < count_).
  const EstimateSample& past(std::size_t k) const;
  void check(const ImuSample& imu, const JointSample& joints, const ForceSample& forces) const;

  std::unique_ptr<model::LegKinematics> legs_;  // settings.robot's; null: the built-in quadruped
  io::LogLayout layout_;
  model::ImuExtrinsic extrinsic_;  // the IMU in the base frame: the filter's body is the IMU
  std::unique_ptr<Estimator> estimator_;
  ContactPipeline pipeline_;
  engineering::StationaryInitParams init_params_;
  engineering::StationaryInitialiser init_;
  std::optional<EstimateSample> start_;  // reset(x0)
  // The accelerometer low-passed while initialising (its gravity direction is the start's tilt
  // when the initialiser gives up); zero before the first sample.
  Eigen::Vector3d acc_lowpass_ = Eigen::Vector3d::Zero();
  bool running_ = false;  // the filter has been started
  io::LogRow row_;        // the samples as a log row
  engineering::HealthMonitor monitor_;
  StepInput trimmed_;  // the pipeline's input less the feet of invalid joints or stuck legs
  EstimatorOutput out_;
  std::optional<double> last_t_;      // the previous sample's time (also while initialising)
  std::vector<EstimateSample> ring_;  // sized once: the last ring_.size() states
  std::size_t head_ = 0;              // where the next state goes
  std::size_t count_ = 0;
};

}  // namespace legkit
