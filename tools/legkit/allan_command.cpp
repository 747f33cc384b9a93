#include "allan_command.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <sstream>

#include "io/log_error.hpp"
#include "model/imu_model.hpp"
#include "output.hpp"
#include "validators.hpp"

namespace legkit::tools {
namespace {

namespace fs = std::filesystem;

// value in %.<digits>g, "-" for NaN.
std::string number(double value, int digits = 4) {
  return formatG(value, digits);
}

// A Go2 IMU (model::ImuNoise::go2()) lying level and still, through the kit's sensor model.
imu::ImuRecording simulatedGo2(double seconds, double rate, unsigned seed) {
  const double dt = 1.0 / rate;
  const auto samples = static_cast<std::size_t>(std::llround(seconds * rate));
  if (samples < 8) throw UsageError("--simulate: fewer than 8 samples at --rate");
  std::mt19937_64 gen(seed);
  model::ImuBias bias;
  imu::ImuRecording rec;
  rec.tau0 = dt;
  rec.source = "simulated Go2 IMU at rest, " + number(seconds) + " s at " + number(rate) +
               " Hz, seed " + std::to_string(seed);
  rec.values.reserve(samples * imu::ImuRecording::kAxes);
  for (std::size_t k = 0; k < samples; ++k) {
    const model::ImuReading r =
        model::synthesiseReading(model::ImuNoise::go2(), dt, Eigen::Matrix3d::Identity(),
                                 Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), bias, gen);
    rec.values.insert(rec.values.end(), r.w_m.data(), r.w_m.data() + 3);
    rec.values.insert(rec.values.end(), r.a_m.data(), r.a_m.data() + 3);
  }
  return rec;
}

// "relative standard error" as +-%
std::string percent(double relative) {
  return std::isnan(relative) ? "-" : "+-" + number(100.0 * relative, 2) + "%";
}

}  // namespace

std::string imuNoiseYaml(const imu::AllanAnalysis& analysis, const std::string& source) {
  const model::ImuNoise noise = analysis.noise();
  std::ostringstream y;
  y << "# legkit allan: " << source << "\n"
    << "# " << analysis.samples << " samples every " << number(analysis.tau0, 6)
    << " s; per sensor the largest of its three axes.\n"
    << "# The chapter's advice: start a filter at 2-5 times these and tighten while its\n"
    << "# innovations stay consistent (chapters/57.10-allan-variance.md).\n"
    << "imu:\n";
  const auto key = [&y](const char* name, double value, const char* unit, const char* line) {
    if (std::isnan(value)) {
      y << "  # " << name << ": not measured: no " << line
        << " region in the curve (a longer record shows it)\n";
    } else {
      y << "  " << name << ": " << number(value, 6) << "  # " << unit << "\n";
    }
  };
  key("gyro_noise_density", noise.gyro_noise_density, "rad/s/sqrt(Hz)", "-1/2");
  key("accel_noise_density", noise.accel_noise_density, "m/s^2/sqrt(Hz)", "-1/2");
  key("gyro_bias_random_walk", noise.gyro_bias_random_walk, "rad/s^2/sqrt(Hz)", "+1/2");
  key("accel_bias_random_walk", noise.accel_bias_random_walk, "m/s^3/sqrt(Hz)", "+1/2");
  return y.str();
}

AllanCommand::AllanCommand(CLI::App& app)
    : command_(app.add_subcommand(
          "allan",
          "Allan deviation of a resting IMU: the noise parameters for the settings file")) {
  CLI::App& c = *command_;
  // Not CLI::ExistingFile: a file that cannot be read is an input error (exit 2).
  CLI::Option* file =
      c.add_option("file", file_,
                   "The recording: the kit's log CSV (t, gyro_*, acc_*, ...) or a plain CSV with "
                   "the header t,gx,gy,gz,ax,ay,az [s, rad/s, m/s^2]; steps within 0.5..1.5 of "
                   "the median step")
          ->check(nonEmptyName());  // '' once said "give a FILE or --simulate"
  CLI::Option* simulate =
      c.add_option("--simulate", simulate_,
                   "Instead of a file: this many seconds of the kit's Go2 IMU model at rest")
          ->check(finiteRange(1e-3, 86400.0));
  file->excludes(simulate);
  c.add_option("--rate", rate_, "Sample rate of --simulate [Hz]")
      ->check(finiteRange(1.0, 1e4))
      ->capture_default_str();
  c.add_option("--seed", seed_, "Random seed of --simulate")
      ->check(seedNumber())
      ->capture_default_str();
  c.add_option("--out", out_dir_,
               "Output folder (default legkit-out/allan-<file name> or allan-go2-seed<seed>)")
      ->check(nonEmptyName());
  c.add_option("--ratio", options_.ratio,
               "Of successive averaging factors m: 2 octaves 1, 2, 4, ...; 1.2589 about ten per "
               "decade (three times the work)")
      ->check(finiteRange(1.01, 10.0))
      ->capture_default_str();
  c.add_option("--slope-tolerance", options_.slope_tolerance,
               "A point belongs to the -1/2 or +1/2 line when its local slope is this close")
      ->check(finiteRange(0.01, 0.5))
      ->capture_default_str();
  c.add_flag("!--no-plots", plots_, "Do not draw allan.png");
}

int AllanCommand::run(std::ostream& out) const {
  if (file_.empty() && simulate_ == 0.0)
    throw UsageError("allan: give a recording FILE or --simulate SECONDS");
  // The record is kept whole, 48 bytes a sample: 2e7 samples (a day at 230 Hz) is about 1 GB
  // with the analysis' working copy; --simulate 86400 at 10 kHz would have been 41 GB.
  constexpr double kMaxSamples = 2e7;
  if (file_.empty() && simulate_ * rate_ > kMaxSamples) {
    std::ostringstream os;
    os << "--simulate " << simulate_ << " s at --rate " << rate_ << " Hz: " << simulate_ * rate_
       << " samples, at most " << kMaxSamples << " (48 bytes each): fewer seconds or a lower rate";
    throw UsageError(os.str());
  }
  const auto start = std::chrono::steady_clock::now();
  const imu::ImuRecording recording =
      file_.empty() ? simulatedGo2(simulate_, rate_, seed_) : imu::readImuRecording(file_);
  const auto read = std::chrono::steady_clock::now();
  const imu::AllanAnalysis analysis = imu::analyseImu(recording, options_);
  const auto done = std::chrono::steady_clock::now();
  const auto seconds = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };

  out << recording.source << ": " << analysis.samples << " samples, tau0 "
      << number(analysis.tau0, 6) << " s (" << number(analysis.samples * analysis.tau0) << " s); "
      << (file_.empty() ? "simulated" : "read") << " in " << number(seconds(start, read), 2)
      << " s, analysed in " << number(seconds(read, done), 2) << " s\n\n";
  std::vector<std::vector<std::string>> table = {{"axis", "N_w (sigma at 1 s)", "", "tau range [s]",
                                                  "K (sigma at 3 s)", "", "tau range [s]",
                                                  "B (min/0.664)", "at tau [s]"}};
  for (int a = 0; a < imu::ImuRecording::kAxes; ++a) {
    const imu::AxisNoise& axis = analysis.axes[a];
    const auto range = [](const imu::SlopeLine& l) {
      return l.found() ? number(l.tau_first, 3) + ".." + number(l.tau_last, 3) : "not found";
    };
    table.push_back({imu::ImuRecording::kAxisNames[a], number(axis.white.level),
                     percent(axis.white.relative_error), range(axis.white),
                     number(axis.random_walk.level), percent(axis.random_walk.relative_error),
                     range(axis.random_walk), number(axis.bias_instability),
                     number(axis.tau_min, 3)});
  }
  printTable(out, table);
  out << "(units: gyro N_w rad/s/sqrt(Hz), K rad/s^2/sqrt(Hz), B rad/s; accelerometer m/s^2 "
         "in place of rad/s; +-: the line's relative standard error from the points' bounds)\n\n";
  const std::string yaml =
      imuNoiseYaml(analysis, file_.empty() ? recording.source : "legkit allan " + file_);
  // A walking robot's log reads a gyro bias random walk of 0.84 rad/s^2/sqrt(Hz) (its motion),
  // where the settings file allows 0.1: its numbers are not written anywhere, nor printed as a
  // settings section.
  if (const std::string why = analysis.moved(); !why.empty()) {
    throw io::LogError(recording.source, 0, "",
                       "not a resting IMU's record: " + why + "; nothing written");
  }
  out << yaml;

  const fs::path dir = !out_dir_.empty() ? fs::path(out_dir_)
                       : file_.empty()
                           ? fs::path("legkit-out") / ("allan-go2-seed" + std::to_string(seed_))
                           : fs::path("legkit-out") / ("allan-" + fs::path(file_).stem().string());
  makeOutputFolder(dir);
  writeAtomically(dir / "allan.csv", [&](std::ostream& f) {
    f << "axis,tau,m,adev,lo,hi\n";
    for (int a = 0; a < imu::ImuRecording::kAxes; ++a)
      for (const imu::AllanPoint& p : analysis.axes[a].curve)
        f << imu::ImuRecording::kAxisNames[a] << ',' << number(p.tau, 10) << ',' << p.m << ','
          << number(p.adev, 10) << ',' << number(p.lo, 10) << ',' << number(p.hi, 10) << '\n';
  });
  writeAtomically(dir / "allan-lines.csv", [&](std::ostream& f) {
    f << "axis,line,slope,tau_read,level,tau_first,tau_last,points,relative_error\n";
    for (int a = 0; a < imu::ImuRecording::kAxes; ++a) {
      const imu::AxisNoise& axis = analysis.axes[a];
      for (const imu::SlopeLine* l : {&axis.white, &axis.random_walk})
        f << imu::ImuRecording::kAxisNames[a] << ',' << (l == &axis.white ? "white" : "random_walk")
          << ',' << l->slope << ',' << l->tau_read << ',' << number(l->level, 10) << ','
          << number(l->tau_first, 10) << ',' << number(l->tau_last, 10) << ',' << l->points << ','
          << number(l->relative_error, 6) << '\n';
      f << imu::ImuRecording::kAxisNames[a] << ",bias_instability,0," << number(axis.tau_min, 10)
        << ',' << number(axis.bias_instability * 0.664, 10) << ",-,-,"
        << (std::isnan(axis.tau_min) ? 0 : 1) << ",-\n";
    }
  });
  writeAtomically(dir / "imu-noise.yaml", [&](std::ostream& f) { f << yaml; });
  out << "\nwritten: " << (dir / "allan.csv").string() << ", allan-lines.csv, imu-noise.yaml";
  if (plots_) {
    const std::string failed = plot("57.10-allan.py", {dir.string()});
    out << (failed.empty() ? ", allan.png\n" : "\n" + failed + "\n");
    if (plotFailed(failed)) return kExitInput;
  } else {
    out << "\n";
  }
  return kExitOk;
}

}  // namespace legkit::tools
