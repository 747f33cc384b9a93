// Every setting of the kit's estimators in one place, read from one YAML file (`legkit run
// --config FILE`, `legkit config --print` writes the defaults with every key documented). The
// YAML mechanics (types, ranges, unknown keys, file:line:key errors) are io/yaml_reader.hpp's;
// what each key means is here.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "estimation/contact/detectors.hpp"
#include "estimation/contact_pipeline.hpp"
#include "estimation/engineering/gating.hpp"
#include "estimation/engineering/monitors.hpp"
#include "estimation/engineering/stationary_init.hpp"
#include "estimation/estimator.hpp"
#include "estimation/health.hpp"
#include "estimation/log_frontend.hpp"
#include "model/imu_extrinsic.hpp"
#include "model/imu_noise.hpp"

namespace legkit {

// The robot whose legs the log's joints describe.
struct RobotSettings {
  std::string model;              // "": the built-in Go2-class quadruped; else a URDF or MJCF file
  std::string base;               // the base body's name in that model
  std::vector<std::string> feet;  // foot frames (sites or bodies), in foot-id order
  std::vector<std::string>
      joints;  // model joints in joint<k>_ column order (empty: hinges in order)
};

struct Settings {
  std::string source;  // the file the settings came from, "" for the defaults

  model::ImuNoise imu =
      model::ImuNoise::go2();         // continuous densities (datasheet, or legkit allan)
  model::ImuExtrinsic imu_extrinsic;  // the IMU's pose in the base frame
  InputLimits limits;
  FrontendNoise frontend;
  RobotSettings robot;
  std::vector<std::string> estimators;  // which run, in this order (empty: every one)
  PipelineOptions pipeline;             // contact source, slip reaction, settling, rolling foot
  contact::SchmittParams schmitt = contact::go2SchmittParams();
  engineering::GatingParams gating;
  engineering::StationaryInitParams initialisation;
  engineering::MonitorParams monitors;
  // (the config owner adds: priors, foot densities, per-filter settings)
};

// The kit's defaults: what every estimator and `legkit run` use without a file.
Settings defaultSettings();
// Reads a settings file. Keys left out keep their defaults. Throws io::ConfigError naming the
// file, the line and the key for an unknown key, a wrong type or an out-of-range value.
Settings loadSettings(const std::string& path);
// The settings as YAML with a comment on every key; loadSettings() of it gives them back.
std::string settingsYaml(const Settings& settings);
// An estimator of estimatorNames() with its parameters from the settings.
std::unique_ptr<Estimator> makeEstimator(const std::string& name, const Settings& settings);

}  // namespace legkit
