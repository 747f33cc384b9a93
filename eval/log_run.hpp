#pragma once
// A recorded log through the settings' front end and contact pipeline: what `legkit run --log F
// --config S` (tools/legkit/run_command.cpp) and legkit.estimators.run from Python share, so that
// the two cannot drift apart.
#include <memory>
#include <optional>
#include <string>

#include "estimation/contact/detectors.hpp"
#include "estimation/estimate.hpp"
#include "estimation/log_frontend.hpp"
#include "estimation/settings.hpp"
#include "eval/runner.hpp"
#include "io/log.hpp"
#include "model/imu_extrinsic.hpp"
#include "model/leg_kinematics.hpp"

namespace legkit::eval {

// The legs of a log's generic joints (layout.num_joints > 0) or of a robot.model: the robot's
// model through model::makeLegKinematics, whose std::runtime_error names the file. Null for a
// log of the built-in quadruped's joints or of foot columns without a robot.model.
std::unique_ptr<model::LegKinematics> logLegs(const io::LogLayout& layout,
                                              const RobotSettings& robot);

// The settings' robot against a recorded log's joint columns, checked before a run (as `legkit
// run --log` and legkit-estimate check it): a robot model (robot.model) needs generic joint
// columns (joint<k>_q), and the model's joints and feet (`legs`: logLegs()) must be the log's.
// Throws std::invalid_argument naming the settings file `config` and the key, and the log
// `source`; without a settings file (`config` empty), the built-in Go2's counts and what to give.
void checkLogRobot(const io::LogLayout& layout, const RobotSettings& robot,
                   const model::LegKinematics* legs, const std::string& config,
                   const std::string& source);

// "truth" as the contact source takes the log's own flags: a log without contact columns
// (contact_<leg>, foot<k>_contact) throws std::invalid_argument "<source> has no contact columns;
// choose a detector". Any other source passes.
void checkContactSource(const std::string& contact, const io::LogLayout& layout,
                        const std::string& source);

// The front end of a log on `legs` (logLegs; null: the built-in quadruped's kinematics), which
// must outlive it.
LogFrontend logFrontend(const io::LogLayout& layout, const model::LegKinematics* legs,
                        const FrontendNoise& noise, const model::ImuExtrinsic& extrinsic);

// What a recorded log run on detector gait-clock without a planned gait is told: the setting
// that gives one.
std::string noGait();

// The start initialisation.gyro_bias asks for on `log` (settings.hpp): with still-window the
// log's still window (stillStart) and describeStart's line; with zero neither.
struct RunStart {
  std::optional<StillStart> still;  // the window, when asked for and found
  std::string note;                 // describeStart's line; empty when the settings say zero
  // The gyro bias every estimator starts from (runOnLog): the window's, or nullopt (zero).
  std::optional<Eigen::Vector3d> gyroBias() const {
    return still ? std::optional<Eigen::Vector3d>(still->b_g) : std::nullopt;
  }
};
RunStart runStart(const io::Log& log, const Settings& settings);

// One estimator over a whole recorded log as `legkit run --log F --config S` runs it: the time
// base checked (std::invalid_argument naming the row), the settings' front end (stamps, joint
// velocities), noise, limits, contact pipeline (the detectors' forces scaled to the robot's
// weight, then the settings' own: detectorContext; the gait and the logistic model of `context`,
// the gait when it has none from the settings' contact.gait), robot and IMU extrinsic, from x0
// (default: initialState) and the gyro bias initialisation.gyro_bias gives (runStart), a
// pose-only truth differentiated over frontend.truth_velocity_window.
// The trajectory keeps the log's own stamps, as the estimate files do (the estimator ran on the
// conditioned ones), so that it lines up with the log row for row.
RunResult runWithSettings(const io::Log& recorded, const Settings& settings,
                          const std::string& estimator, const contact::DetectorContext& context,
                          const std::optional<EstimateSample>& x0 = std::nullopt);

}  // namespace legkit::eval
