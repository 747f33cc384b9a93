// legkit-estimate: the estimator manager (estimation/state_estimator.hpp) on a recorded log, fed
// row by row as a robot's control loop would feed it (IMU, joints, foot forces), with a model-
// predictive controller querying it at its own rate. Prints the time per update, the MPC
// queries' ages and what those ages cost, and (with ground truth) the errors; --out writes the
// states. The log goes through the checks and the front end of `legkit run` (its time base, then
// estimation/log_conditioning.hpp, the robot against its columns: eval/log_run.hpp); the robot,
// its noise and the pipeline come from --config (the quadruped's joints, or generic joints with
// the settings' robot), the options override it. The exit codes are `legkit run`'s: 1 a wrong
// option (each names itself), 2 an input that cannot be used (naming the file and line, or the
// settings' key) or an output not written, 3 a run whose filter failed (naming the log's line),
// had to recover or could not use more than eval::kMaxRejectedShare of its input.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "estimation/contact/detectors.hpp"
#include "estimation/estimators.hpp"
#include "estimation/log_conditioning.hpp"
#include "estimation/settings.hpp"
#include "estimation/state_estimator.hpp"
#include "eval/log_run.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "io/log_reader.hpp"
#include "output.hpp"
#include "validators.hpp"

namespace {

using namespace legkit;
using tools::InputError;
using tools::OutputError;
using tools::UsageError;

// The log's truth position at time t >= rows[k].t (linear between the two rows around t; the
// last row's after the log's end).
Eigen::Vector3d truthPositionAt(const io::Log& log, std::size_t k, double t) {
  while (k + 1 < log.rows.size() && log.rows[k + 1].t <= t) ++k;
  const io::LogRow& a = log.rows[k];
  if (k + 1 == log.rows.size()) return a.gt_p;
  const io::LogRow& b = log.rows[k + 1];
  const double s = (t - a.t) / (b.t - a.t);
  return a.gt_p + s * (b.gt_p - a.gt_p);
}

struct Options {
  std::string log_path;
  std::string config;  // settings file ("": the defaults, with the options' own defaults below)
  std::optional<std::string> estimator;  // unset: the settings' first estimator
  std::optional<std::string> contact;    // unset: the settings' detector
  std::optional<double> settle;          // unset: the settings' settling
  std::optional<double> init_duration;   // [s] still window; 0: off; unset: the settings'
  // [s] without a still window before the manager gives up and starts from the last samples' tilt
  // (the settings' 10 s would take a whole simulated 10 s log; 0.8 s is within the simulated
  // scenarios' 1 s stand).
  double init_wait = 0.8;
  double mpc_rate = 100.0;        // [Hz]
  double mpc_latency = 0.0025;    // [s] the MPC's clock ahead of the newest IMU sample
  std::optional<double> max_gap;  // [s] unset: 10 median periods (checkTimeBase)
  std::string out;
};

// Where a setting came from, for its errors: the option when given, else the settings file's key.
std::string origin(bool option_given, const std::string& option, const std::string& config,
                   const std::string& key) {
  if (option_given || config.empty()) return option;
  return config + ": " + key;
}

int run(const Options& o) {
  // Without a settings file: the invariant EKF on the Schmitt trigger, no settling (the options'
  // defaults before settings files); with one, its values unless an option is given.
  if (!o.out.empty())
    tools::checkWritable(o.out, o.out + " (--out)");  // before the run, which may be long
  Settings settings;
  if (!o.config.empty()) {
    settings = loadSettings(o.config);
  } else {
    settings.estimators = {"invariant-ekf"};
    settings.pipeline.contact = "schmitt";
    settings.pipeline.settle_time = 0.0;
  }
  if (o.estimator) settings.estimators = {*o.estimator};
  if (o.contact) settings.pipeline.contact = *o.contact;
  if (o.settle) settings.pipeline.settle_time = *o.settle;
  io::Log log = io::readLog(o.log_path);
  const int generic = log.layout.num_joints;
  if (!log.layout.joints && generic == 0) {
    throw std::invalid_argument(
        o.log_path +
        ": the manager takes joints (the quadruped's q_, dq_ or generic joint<k>_q, "
        "joint<k>_dq with the settings' robot), and this log has foot columns only");
  }
  if (generic > 0 && settings.robot.model.empty()) {
    throw std::invalid_argument(o.log_path +
                                ": generic joint columns (joint<k>_q) need the "
                                "robot's model: --config with a robot: section");
  }
  // The checks `legkit run --log` makes, with its messages: the time base (file and line), the
  // front end's conditioning, the robot against the log's columns, the contact source.
  checkTimeBase(log, o.max_gap, "--max-gap");
  ConditioningReport conditioning;
  try {
    conditioning = condition(log, settings.conditioning);
  } catch (const std::invalid_argument& e) {
    throw InputError(o.log_path + ": " + e.what());
  }
  std::unique_ptr<model::LegKinematics> legs;
  try {
    legs = eval::logLegs(log.layout, settings.robot);
  } catch (const std::runtime_error& e) {
    throw InputError((o.config.empty() ? std::string() : o.config + ": robot.model: ") + e.what());
  }
  eval::checkLogRobot(log.layout, settings.robot, legs.get(), o.config, o.log_path);
  const std::string& contact = settings.pipeline.contact;
  const std::string contact_origin = origin(o.contact.has_value(), "--contact " + contact, o.config,
                                            "contact.detector: " + contact);
  try {
    eval::checkContactSource(contact, log.layout, o.log_path);
  } catch (const std::invalid_argument& e) {
    throw UsageError(contact_origin + ": " + e.what());
  }
  const int num_feet = legs ? legs->numFeet() : log.layout.num_feet;
  if (contact == "gait-clock" && !gaitSchedule(settings, num_feet)) {
    throw UsageError(contact_origin + ": " + eval::noGait());
  }
  if (o.init_duration == 0.0) settings.initialisation.enabled = false;
  if (o.init_duration > 0.0) settings.initialisation.duration = *o.init_duration;
  settings.initialisation.max_wait = o.init_wait;
  StateEstimator manager(settings);
  // As `legkit run` does: from the truth's first row when there is one (else the manager's own
  // start: at rest at the origin, tilt from the accelerometer).
  if (log.layout.ground_truth) {
    const io::LogRow& first = log.rows.front();
    manager.reset(EstimateSample{first.t, first.gt_q, first.gt_v, first.gt_p});
  }

  // The states are gathered here and written at the end through tools::writeAtomically, as
  // `legkit run` writes its files.
  std::ostringstream out;
  if (!o.out.empty()) {
    out << "t,initialised,qw,qx,qy,qz,vx,vy,vz,px,py,pz,sigma_px,sigma_py,sigma_pz";
    for (int f = 0; f < num_feet; ++f) out << ",contact_" << f << ",p_c_" << f;
    out << "\n" << std::setprecision(9);
  }

  ImuSample imu;
  JointSample joints;
  ForceSample forces;
  forces.valid = log.layout.force;
  std::vector<double> us;  // wall time per update
  us.reserve(log.rows.size());
  eval::Trajectory states;
  states.reserve(log.rows.size());
  const double mpc_period = 1.0 / o.mpc_rate;
  double next_mpc = log.rows.front().t;
  int queries = 0;
  std::optional<double> start_t;  // the filter's first sample
  double age_sum = 0.0, hold_error_sum = 0.0, hold_error_max = 0.0;
  // As runOnLog's: the filter threw on a row, or handed back an estimate or a covariance that
  // cannot be used: the run stops there, naming the log's line (exit 3).
  std::optional<eval::RunFailure> failure;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const io::LogRow& row = log.rows[k];
    imu = {row.t, row.gyro, row.acc};
    if (generic > 0) {
      joints.count = generic;
      joints.q = row.joint_q;
      joints.dq = row.joint_dq;
    } else {
      joints.q.head<io::kNumJoints>() = row.q;
      joints.dq.head<io::kNumJoints>() = row.dq;
    }
    for (int f = 0; f < num_feet; ++f) {  // the robot's feet, which checkLogRobot matched
      forces.force[f] = row.force[f];
      forces.contact[f] = row.contact[f];
    }
    const auto t0 = std::chrono::steady_clock::now();
    try {
      manager.update(imu, joints, forces);
    } catch (const std::exception& e) {
      failure = eval::failureAt(log, k, eval::threwReason(e));
      break;
    }
    us.push_back(
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
    const EstimatorOutput& x = manager.output();
    const std::string unusable =
        eval::unusableEstimate(x.x, x.initialised && x.has_covariance ? &x.P : nullptr);
    if (!unusable.empty()) {
      failure = eval::failureAt(log, k, unusable);
      break;
    }
    states.push_back(x.x);
    if (!o.out.empty()) {
      out << x.x.t << ',' << (x.initialised ? 1 : 0) << ',' << x.x.q.w() << ',' << x.x.q.x() << ','
          << x.x.q.y() << ',' << x.x.q.z() << ',' << x.x.v.x() << ',' << x.x.v.y() << ','
          << x.x.v.z() << ',' << x.x.p.x() << ',' << x.x.p.y() << ',' << x.x.p.z();
      for (int i = 6; i < 9; ++i) {
        out << ',' << (x.has_covariance ? std::sqrt(x.P.P(i, i)) : std::nan(""));
      }
      for (int f = 0; f < num_feet; ++f) {
        const contact::FootContact& c = x.contacts.feet[f];
        out << ',' << (c.usable() && c.contact ? 1 : 0) << ','
            << (c.usable() ? c.probability : 0.0);
      }
      out << "\n";
    }
    // The MPC's tick: it asks for the state at its own clock, mpc_latency after this sample.
    if (!x.initialised) {
      next_mpc = row.t;  // nothing to ask for while the still window is searched
      continue;
    }
    if (!start_t) start_t = row.t;
    if (row.t >= next_mpc) {
      next_mpc += mpc_period;
      const double t_query = row.t + o.mpc_latency;
      const StateQuery q = manager.stateAt(t_query);
      ++queries;
      age_sum += q.age;
      if (log.layout.ground_truth) {
        // What the age costs: how far the true base moved between the state's time and the query.
        const double e = (truthPositionAt(log, k, t_query) - row.gt_p).norm();
        hold_error_sum += e;
        hold_error_max = std::max(hold_error_max, e);
      }
    }
  }
  if (!o.out.empty()) {
    tools::writeAtomically(
        o.out, [&out](std::ostream& file) { file << out.str(); }, o.out + " (--out)");
  }
  if (failure) {
    std::cout << "log " << o.log_path << ": " << log.rows.size() << " rows\n"
              << "settings: " << (o.config.empty() ? "the defaults" : o.config) << "\n"
              << "front end: " << conditioning.describe() << "\n"
              << "FAILED " << manager.estimatorName() << ": " << eval::describe(*failure) << "\n";
    return tools::kExitUnhealthy;
  }

  std::vector<double> sorted = us;
  std::sort(sorted.begin(), sorted.end());
  double mean = 0.0;
  for (const double u : us) mean += u;
  mean /= static_cast<double>(us.size());
  std::cout << std::fixed << std::setprecision(3);
  std::cout << "log " << o.log_path << ": " << log.rows.size() << " rows, "
            << (log.rows.back().t - log.rows.front().t) << " s\n"
            << "settings: " << (o.config.empty() ? "the defaults" : o.config) << "\n"
            << "front end: " << conditioning.describe() << "\n"
            << "manager: " << manager.estimatorName() << " on contacts from "
            << manager.contactSource() << ", settle " << settings.pipeline.settle_time << " s\n"
            << "update: mean " << mean << " us, median " << sorted[sorted.size() / 2] << " us, p99 "
            << sorted[sorted.size() * 99 / 100] << " us, max " << sorted.back()
            << " us (wall time on this machine; bench_state_estimator measures it properly)\n";
  if (!start_t) {
    std::cout << "no still window found and the log ended before --init-wait: the filter never "
                 "started (--init 0 starts it at once)\n";
    return tools::kExitInput;
  }
  std::cout << "filter started at t = " << *start_t << " s ("
            << startModeName(manager.output().start) << ")\n";
  std::cout << "MPC at " << o.mpc_rate << " Hz, clock " << o.mpc_latency * 1e3
            << " ms after the IMU: " << queries << " queries, mean age " << age_sum / queries * 1e3
            << " ms";
  if (log.layout.ground_truth) {
    std::cout << "; the truth moved " << hold_error_sum / queries * 1e3 << " mm on average (max "
              << hold_error_max * 1e3 << " mm) over that age";
  }
  std::cout << "\n";
  if (log.layout.ground_truth) {
    const eval::Metrics m = eval::compare(log, states);
    std::cout << "against the truth: position RMSE " << m.position_rmse << " m, velocity RMSE "
              << m.velocity_rmse << " m/s, tilt RMSE " << m.tilt_rmse_deg << " deg, yaw RMSE "
              << m.yaw_rmse_deg << " deg (started from the truth's first row)\n";
  }
  const Health& h = manager.output().health;
  std::cout << "health: " << h.total() << " faults";
  if (h.total() > 0) std::cout << " (" << eval::describe(h) << ")";
  std::cout << "\n";
  if (!o.out.empty()) std::cout << "states written to " << o.out << "\n";
  // As legkit run: a filter that had to recover, or that could not use more than
  // eval::kMaxRejectedShare of its input, is a failed run (exit 3).
  if (!h.healthy()) {
    std::cout << "the filter had to recover " << h[Fault::kStateUnhealthy]
              << " time(s): its state is not to be trusted\n";
    return tools::kExitUnhealthy;
  }
  if (eval::voided(h, log.rows.size())) {
    std::cout << "VOID " << manager.estimatorName() << ": " << eval::rejectedInputs(h) << " of "
              << log.rows.size() << " samples' input rejected (more than "
              << 100.0 * eval::kMaxRejectedShare << " %): check the settings' limits and priors\n";
    return tools::kExitUnhealthy;
  }
  return tools::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  using legkit::tools::finiteRange;
  using legkit::tools::nonEmptyName;
  CLI::App app{"legkit-estimate: the estimator manager (57.11) on a log, row by row"};
  app.footer(
      "Exit codes (legkit run --log's): 0 done, the filter healthy; 1 the command line was wrong\n"
      "(an option out of its range: the error names it); 2 the input could not be used (the\n"
      "error names the file and line, or the settings' key) or an output not written; 3 the run\n"
      "failed at a row of the log (FAILED names it), the filter had to recover, or it could not\n"
      "use more than 5 % of its input (VOID with the counts).");
  Options o;
  app.add_option("log", o.log_path, "Log (CSV) with joint and foot-force columns")
      ->required()
      ->check(nonEmptyName());
  app.add_option("--config", o.config,
                 "Settings file (legkit config --print): the robot, its noise, the pipeline; the "
                 "options below override it")
      ->check(nonEmptyName());
  app.add_option("--estimator", o.estimator,
                 "Filter (default: the settings' first estimator, invariant-ekf without --config)")
      ->check(CLI::IsMember(legkit::estimatorNames()));
  std::vector<std::string> contacts = {"truth"};
  for (const std::string& name : legkit::contact::detectorNames()) contacts.push_back(name);
  app.add_option("--contact", o.contact,
                 "Contact detector, or truth for the log's flags (default: the settings', schmitt "
                 "without --config)")
      ->check(CLI::IsMember(contacts));
  app.add_option("--settle", o.settle,
                 "Touchdown settling [s] (default: the settings', 0 without --config; 1 s at most, "
                 "as in the settings file)")
      ->check(finiteRange(0.0, 1.0));
  // initialisation.duration's range in the settings file, and 0 for off.
  app.add_option("--init", o.init_duration,
                 "Stationary initialisation window [s] on a log without truth (0: off, else 0.01 "
                 "to 60; default: the settings' 2 s)")
      ->check(finiteRange(0.0, 60.0))
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            double value = 0.0;
            CLI::detail::lexical_cast(text, value);
            return value > 0.0 && value < 0.01 ? "must be 0 (off) or in [0.01, 60], got " + text
                                               : std::string();
          },
          ""));
  app.add_option("--init-wait", o.init_wait,
                 "Without a still window after this long [s], start from the tilt of the last "
                 "samples (initialisation.max_wait's range)")
      ->capture_default_str()
      ->check(finiteRange(0.0, 3600.0));
  app.add_option("--mpc-rate", o.mpc_rate, "MPC query rate [Hz]")
      ->capture_default_str()
      ->check(finiteRange(1.0, 1e4));
  app.add_option("--mpc-latency", o.mpc_latency, "MPC clock ahead of the newest IMU sample [s]")
      ->capture_default_str()
      ->check(finiteRange(0.0, 1.0));
  app.add_option("--max-gap", o.max_gap,
                 "Longest step allowed between samples of the log [s] (default 10 median "
                 "periods), as legkit run --max-gap")
      ->check(finiteRange(1e-6, 3600.0));
  app.add_option("--out", o.out, "Write the states (CSV)")->check(nonEmptyName());
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? legkit::tools::kExitOk : legkit::tools::kExitUsage;
  }
  int status = legkit::tools::kExitInput;
  try {
    status = run(o);
  } catch (const legkit::tools::UsageError& e) {
    std::cerr << "legkit-estimate: " << e.what() << "\n";
    return legkit::tools::kExitUsage;
  } catch (const std::exception& e) {  // the input or an output: LogError, InputError, ...
    std::cerr << "legkit-estimate: " << e.what() << "\n";
    return legkit::tools::kExitInput;
  }
  // A report that did not reach its reader is not done (stdout on a full disk).
  std::cout.flush();
  if (!std::cout) {
    std::cerr << "legkit-estimate: cannot write the standard output\n";
    return legkit::tools::kExitInput;
  }
  return status;
}
