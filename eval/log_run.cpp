#include "eval/log_run.hpp"

#include <stdexcept>

#include "estimation/contact_pipeline.hpp"
#include "estimation/estimators.hpp"
#include "estimation/log_conditioning.hpp"
#include "model/mujoco_kinematics.hpp"
#include "model/quadruped.hpp"

namespace legkit::eval {

std::unique_ptr<model::LegKinematics> logLegs(const io::LogLayout& layout,
                                              const RobotSettings& robot) {
  // A model is read even for a log without joint columns, so that its own faults are reported
  // before checkLogRobot's mismatch.
  if (layout.num_joints == 0 && robot.model.empty()) return nullptr;
  return model::makeLegKinematics(robot.model, robot.base, robot.feet, robot.joints);
}

void checkLogRobot(const io::LogLayout& layout, const RobotSettings& robot,
                   const model::LegKinematics* legs, const std::string& config,
                   const std::string& source) {
  if (!robot.model.empty() && layout.num_joints == 0) {
    throw std::invalid_argument(config + ": robot.model: " + source +
                                " has no generic joint columns (joint<k>_q) for the robot's legs");
  }
  const auto mismatch = [&](const char* key, int robot_count, int logged, const char* columns) {
    const std::string counts = std::to_string(robot_count) + " " + key + ", " + source + " has " +
                               std::to_string(logged) + " (" + columns + " columns)";
    if (config.empty()) {
      throw std::invalid_argument("the built-in Go2 (no --config) has " + counts +
                                  ": name the robot in --config (robot.model)");
    }
    throw std::invalid_argument(config + ": robot." + key + ": " + counts);
  };
  if (legs && legs->numJoints() != layout.num_joints) {
    mismatch("joints", legs->numJoints(), layout.num_joints, "joint<k>_q");
  }
  if (legs && legs->numFeet() != layout.num_feet) {
    mismatch("feet", legs->numFeet(), layout.num_feet, "foot<k>_");
  }
}

void checkContactSource(const std::string& contact, const io::LogLayout& layout,
                        const std::string& source) {
  if (contact == "truth" && !layout.contact) {
    throw std::invalid_argument(source + " has no contact columns; choose a detector");
  }
}

LogFrontend logFrontend(const io::LogLayout& layout, const model::LegKinematics* legs,
                        const FrontendNoise& noise, const model::ImuExtrinsic& extrinsic) {
  return legs ? LogFrontend(layout, *legs, noise, extrinsic)
              : LogFrontend(layout, model::QuadrupedKinematics(), noise, extrinsic);
}

std::string noGait() {
  return "contact detector gait-clock needs a gait schedule: give the robot's planned gait in the "
         "settings, contact.gait (period, duty, offsets, start; `legkit config --print` lists "
         "them)";
}

RunStart runStart(const io::Log& log, const Settings& settings) {
  if (settings.gyro_bias_start != GyroBiasStart::kStillWindow) return {};
  RunStart start{stillStart(log, settings.initialisation), ""};
  start.note = describeStart(start.still);
  return start;
}

RunResult runWithSettings(const io::Log& recorded, const Settings& settings,
                          const std::string& estimator, const contact::DetectorContext& context,
                          const std::optional<EstimateSample>& x0) {
  checkTimeBase(recorded, std::nullopt, "max_gap");
  io::Log log = recorded;
  condition(log, settings.conditioning);
  PipelineOptions options = settings.pipeline;
  options.limits = settings.limits;
  try {
    checkContactSource(options.contact, log.layout, "the log");
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("contact 'truth': ") + e.what());
  }
  const std::unique_ptr<model::LegKinematics> legs = logLegs(log.layout, settings.robot);
  checkLogRobot(log.layout, settings.robot, legs.get(), "the settings", "the log");
  const LogFrontend frontend =
      logFrontend(log.layout, legs.get(), frontendNoise(settings), settings.imu_extrinsic);
  const int num_feet = legs ? legs->numFeet() : log.layout.num_feet;
  contact::DetectorContext robot =
      detectorContext(settings, robotMass(settings, legs.get()), num_feet);
  robot.gait = context.gait ? context.gait : gaitSchedule(settings, num_feet);
  robot.logistic = context.logistic;
  if (options.contact == "gait-clock" && !robot.gait) throw std::invalid_argument(noGait());
  ContactPipeline pipeline(frontend, options, robot);
  const std::unique_ptr<Estimator> e = makeEstimator(estimator, settings);
  const double window = settings.truth_velocity_window;
  const RunStart start = runStart(log, settings);
  RunResult run =
      runOnLog(*e, log, pipeline, x0 ? *x0 : initialState(log, window), window, start.gyroBias());
  run.start = start.note;
  for (std::size_t k = 0; k < run.trajectory.size(); ++k) run.trajectory[k].t = recorded.rows[k].t;
  return run;
}

}  // namespace legkit::eval
