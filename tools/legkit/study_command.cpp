#include "study_command.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <mutex>
#include <random>
#include <sstream>

#include "estimation/estimators.hpp"
#include "eval/bias_variance.hpp"
#include "eval/metrics.hpp"
#include "eval/monte_carlo.hpp"
#include "eval/runner.hpp"
#include "output.hpp"
#include "study_filters.hpp"
#include "study_fusion.hpp"
#include "validators.hpp"

namespace legkit::tools {
namespace {

namespace fs = std::filesystem;

// A study's table, kept in memory while the runs go on and written atomically at the end.
std::ostringstream newCsv() {
  std::ostringstream csv;
  csv << std::setprecision(8);
  return csv;
}

std::string fixed(double value, int precision) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(precision) << value;
  return os.str();
}

// Progress on standard error: redrawn in place on a terminal, plain lines into a file or pipe.
Progress stderrProgress() {
  return Progress(std::cerr, isatty(fileno(stderr)) != 0);
}

}  // namespace

StudyCommand::StudyCommand(CLI::App& app)
    : command_(app.add_subcommand("study", "Monte Carlo studies behind the chapters' figures")),
      contact_(*command_),
      faults_(*command_) {
  command_->require_subcommand(1);
  addStudyFusion(*command_);  // `study fusion` (57.8): its options live in its subcommand
  consistency_ = command_->add_subcommand(
      "consistency", "ANEES of every filter over runs of the default trot (section 57.5)");
  convergence_ = command_->add_subcommand(
      "convergence", "Initial attitude error 5-90 deg: convergence of LKF, ESKF, InEKF (57.10)");
  sweep_ = command_->add_subcommand(
      "sweep", "Linear KF noise parameters over decades: bias-variance trade-off (ex. 57.4.2)");
  for (CLI::App* c : {consistency_, convergence_, sweep_}) {
    // Unset they stay 0, the study's own; given, each is checked (0, -1 or NaN once fell back to
    // the default silently).
    c->add_option("--runs", runs_, "Monte Carlo runs (per setting); default: the study's own")
        ->check(wholeRange(1, 10000));
    c->add_option("--duration", duration_, "Simulated time per run [s]; default: the study's own")
        ->check(finiteRange(1e-3, kMaxSimulatedSeconds));
    c->add_option("--seed", seed_, "Seed of the first run (run j uses seed + j)")
        ->check(seedNumber())
        ->capture_default_str();
    // -1 once meant every core, silently; more than 256 workers is a typo, not a machine.
    c->add_option("--threads", threads_, "Worker threads (0: every core)")
        ->check(wholeRange(0, 256))
        ->capture_default_str();
    c->add_option("--out", out_dir_, "Output folder (default legkit-out/study-<name>)")
        ->check(nonEmptyName());
    c->add_flag("!--no-plots", plots_, "Do not draw the PNG figure");
  }
}

int StudyCommand::run(std::ostream& out) const {
  if (contact_.parsed()) return contact_.run(out);
  if (faults_.parsed()) return faults_.run(out);
  if (const CLI::App* fusion = command_->get_subcommand("fusion"); fusion->parsed()) {
    return runStudyFusion(*fusion, out);
  }
  try {
    if (*consistency_) return consistency(out);
    if (*convergence_) return convergence(out);
    return sweep(out);
  } catch (const eval::RunFailedError& e) {  // the input was fine: a filter failed in a run
    std::cerr << "legkit study: " << e.what() << "\n";
    return kExitUnhealthy;
  }
}

int StudyCommand::plot(std::ostream& out, const std::string& study, const std::string& dir) const {
  if (!plots_) return kExitOk;
  const std::string failed = tools::plot("study_plots.py", {study, dir});
  out << (failed.empty() ? "figure: " + dir + "/" + study + ".png" : failed) << '\n';
  return plotFailed(failed) ? kExitInput : kExitOk;
}

// ANEES_k of each filter (with its bounds) over `runs` runs of the default trot, every filter with
// its default parameters; each run's initial error and IMU biases drawn from eval::InitialPrior.
// The default horizon is long (12 runs of 300 s): a filter that slowly grows over-confident
// looks consistent for the first minute (chapter 57.10), so the table also gives the ANEES of
// the last tenth of the run.
int StudyCommand::consistency(std::ostream& out) const {
  const fs::path dir =
      out_dir_.empty() ? fs::path("legkit-out/study-consistency") : fs::path(out_dir_);
  makeOutputFolder(dir);  // before the runs: a bad --out fails at once
  eval::MonteCarloOptions options;
  options.runs = runs_ > 0 ? runs_ : 12;
  options.sim.duration = duration_ > 0 ? duration_ : 300.0;
  options.first_seed = seed_;
  options.threads = threads_;
  options.prior = eval::InitialPrior{};
  Progress progress = stderrProgress();
  options.on_progress = [&](int done, int total) { progress.run("consistency", done, total); };
  std::vector<eval::NamedEstimator> filters;
  filters.reserve(filterNames().size());
  for (const std::string& name : filterNames()) {
    filters.push_back({name, [name] { return makeEstimator(name); }});
  }
  const std::vector<eval::MonteCarloEstimate> result = eval::monteCarlo(options, filters);
  progress.clear();

  std::ostringstream csv = newCsv();
  csv << "# runs " << options.runs << '\n' << "filter,dof,lower,upper,t,anees\n";
  const std::size_t every = 10;  // 100 Hz is plenty for the figure
  for (const eval::MonteCarloEstimate& r : result) {
    for (std::size_t k = 0; k < r.anees.size(); k += every) {
      csv << r.name << ',' << r.dof << ',' << r.bounds.lower << ',' << r.bounds.upper << ','
          << r.t[k] << ',' << r.anees[k] << '\n';
    }
  }

  out << "Consistency on the default trot: " << options.runs << " runs x " << options.sim.duration
      << " s, initial errors and biases drawn from the filters' prior\n\n";
  std::vector<std::vector<std::string>> table = {{"filter", "dof", "ANEES/dof", "last 10 %",
                                                  "95 % bounds / dof", "inside [%]",
                                                  "pos RMSE [m]"}};
  for (const eval::MonteCarloEstimate& r : result) {
    double pos = 0.0;
    for (const eval::Metrics& m : r.runs) pos += m.position_rmse / r.runs.size();
    const std::size_t from = r.anees.size() - std::max<std::size_t>(1, r.anees.size() / 10);
    double late = 0.0;
    for (std::size_t k = from; k < r.anees.size(); ++k) late += r.anees[k];
    late /= static_cast<double>((r.anees.size() - from) * r.dof);
    table.push_back(
        {r.name, std::to_string(r.dof), fixed(r.mean_anees, 2), fixed(late, 2),
         "[" + fixed(r.bounds.lower / r.dof, 2) + ", " + fixed(r.bounds.upper / r.dof, 2) + "]",
         fixed(100.0 * r.fraction_inside, 1), fixed(pos, 3)});
  }
  printTable(out, table);
  out << "\n(ANEES/dof: the mean over time of ANEES_k / dof; last 10 %: the same over the last "
         "tenth of the run; inside: the share of samples k whose ANEES_k lies inside the "
         "bounds)\n";
  writeAtomically(dir / "consistency.csv", [&](std::ostream& f) { f << csv.str(); });
  return plot(out, "consistency", dir.string());
}

// Each filter started with its attitude turned by a given angle about a random axis (the same
// axes for every filter), its initial attitude sigma set to that angle. A run has converged when
// from some time t_c to the end its roll/pitch error stays below 2 degrees and its body-frame
// velocity error below 0.1 m/s, with t_c at least 5 s before the end. Yaw is unobservable and not
// judged; that is also why velocity is compared in the body frame: a heading error that is kept
// rotates the world-frame velocity (0.5 m/s x 15 deg = 0.13 m/s).
int StudyCommand::convergence(std::ostream& out) const {
  const std::vector<std::string> names = {"linear-kf", "eskf", "invariant-ekf"};
  std::vector<double> angles;
  for (int a = 5; a <= 90; a += 5) angles.push_back(a);
  const int runs = runs_ > 0 ? runs_ : 10;
  const double duration = duration_ > 0 ? duration_ : 20.0;
  constexpr double tilt_limit = 2.0 * M_PI / 180.0, velocity_limit = 0.1, settle = 5.0;

  const fs::path dir =
      out_dir_.empty() ? fs::path("legkit-out/study-convergence") : fs::path(out_dir_);
  makeOutputFolder(dir);
  std::ostringstream csv = newCsv();
  csv << "# runs " << runs << " duration " << duration << '\n'
      << "filter,angle_deg,runs,converged_fraction,median_time_s\n";
  // table[angle][filter] = (fraction, median time)
  std::vector<std::vector<std::pair<double, double>>> table(angles.size());
  Progress progress = stderrProgress();
  for (std::size_t a = 0; a < angles.size(); ++a) {
    const double angle = angles[a] * M_PI / 180.0;
    eval::MonteCarloOptions options;
    options.runs = runs;
    options.sim.duration = duration;
    options.first_seed = seed_;
    options.threads = threads_;
    const std::string what = "convergence, " + fixed(angles[a], 0) + " deg";
    options.on_progress = [&](int done, int total) { progress.run(what, done, total); };
    options.initial_state = [angle, this](const io::Log& log, int run) {
      std::mt19937 rng(seed_ * 7919u + static_cast<unsigned>(run));
      std::normal_distribution<double> n;
      const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
      EstimateSample x0 = eval::initialState(log);
      x0.q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis)) * x0.q;
      return x0;
    };
    std::vector<std::vector<double>> times(names.size());  // convergence times, converged runs
    std::mutex mutex;
    options.on_run = [&](int, std::size_t e, const io::Log& log, const eval::RunResult& run) {
      const double t_end = log.rows.back().t;
      double t_c = log.rows.front().t;  // the last time the limits were broken
      for (std::size_t k = 0; k < log.rows.size(); ++k) {
        const io::LogRow& row = log.rows[k];
        const EstimateSample& x = run.trajectory[k];
        const bool ok =
            eval::tiltError(x.q.toRotationMatrix(), row.gt_q.toRotationMatrix()) < tilt_limit &&
            (x.q.conjugate() * x.v - row.gt_q.conjugate() * row.gt_v).norm() < velocity_limit;
        if (!ok) t_c = row.t;
      }
      if (t_c <= t_end - settle) {
        const std::lock_guard<std::mutex> lock(mutex);
        times[e].push_back(t_c - log.rows.front().t);
      }
    };
    std::vector<eval::NamedEstimator> filters;
    filters.reserve(names.size());
    for (const std::string& name : names) {
      filters.push_back(
          {name, [name, angle] { return makeWithInitialAttitudeSigma(name, angle); }});
    }
    eval::monteCarlo(options, filters);
    for (std::size_t e = 0; e < names.size(); ++e) {
      std::vector<double>& t = times[e];
      std::sort(t.begin(), t.end());
      const double fraction = static_cast<double>(t.size()) / runs;
      const double median = t.empty() ? NAN : t[t.size() / 2];
      table[a].emplace_back(fraction, median);
      csv << names[e] << ',' << angles[a] << ',' << runs << ',' << fraction << ',' << median
          << '\n';
    }
  }
  progress.clear();

  out << "Convergence from a wrong initial attitude (" << runs << " runs x " << duration
      << " s of trot per angle; converged: roll/pitch < 2 deg and body velocity < 0.1 m/s from t_c "
         "on)\n\n";
  std::vector<std::vector<std::string>> rows = {{"angle"}, {"[deg]"}};
  for (const std::string& name : names) {
    rows[0].push_back(name);
    rows[1].push_back("converged, median t_c");
  }
  for (std::size_t a = 0; a < angles.size(); ++a) {
    rows.push_back({fixed(angles[a], 0)});
    for (const auto& [fraction, median] : table[a]) {
      rows.back().push_back(fixed(100.0 * fraction, 0) + " %, " +
                            (std::isnan(median) ? "-" : fixed(median, 2) + " s"));
    }
  }
  printTable(out, rows);
  writeAtomically(dir / "convergence.csv", [&](std::ostream& f) { f << csv.str(); });
  return plot(out, "convergence", dir.string());
}

// The linear KF with one noise variance at a time scaled from 1e-3 to 1e3 times its nominal
// value: mean position RMSE, the velocity error split into bias and variance
// (eval/bias_variance.hpp, 1 s window), and ANEES/dof over the runs.
int StudyCommand::sweep(std::ostream& out) const {
  const int runs = runs_ > 0 ? runs_ : 10;
  const double duration = duration_ > 0 ? duration_ : 20.0;
  constexpr double window = 1.0;  // [s], two strides of the default trot
  const fs::path dir = out_dir_.empty() ? fs::path("legkit-out/study-sweep") : fs::path(out_dir_);
  makeOutputFolder(dir);
  std::ostringstream csv = newCsv();
  csv << "# runs " << runs << " duration " << duration << " window " << window << '\n'
      << "parameter,scale,position_rmse,velocity_rmse,velocity_bias,velocity_variance,anees\n";
  const char* parameters[] = {"foot process noise", "accelerometer noise", "measurement noise"};
  out << "Linear KF parameter sweep (" << runs << " runs x " << duration << " s of trot each; "
      << "velocity error split over a " << window << " s window)\n\n";
  std::vector<std::vector<std::string>> table = {{"parameter", "scale", "pos RMSE [m]",
                                                  "vel RMSE [m/s]", "vel bias [m/s]",
                                                  "vel variance [m2/s2]", "ANEES/dof"}};
  Progress progress = stderrProgress();
  for (int p = 0; p < 3; ++p) {
    for (int i = -6; i <= 6; ++i) {
      const double scale = std::pow(10.0, 0.5 * i);
      LinearKfScales scales;
      (p == 0   ? scales.foot_process_noise
       : p == 1 ? scales.accel_noise
                : scales.measurement_noise) = scale;
      eval::MonteCarloOptions options;
      options.runs = runs;
      options.sim.duration = duration;
      options.first_seed = seed_;
      options.threads = threads_;
      options.frontend_noise = scaledFrontendNoise(eval::matchedFrontendNoise(options.sim), scales);
      const std::string what = std::string("sweep, ") + parameters[p] + " x " + fixed(scale, 3);
      options.on_progress = [&](int done, int total) { progress.run(what, done, total); };
      double bias2 = 0.0, variance = 0.0;
      std::mutex mutex;
      options.on_run = [&](int, std::size_t, const io::Log& log, const eval::RunResult& run) {
        const eval::BiasVariance bv = eval::velocityBiasVariance(log, run.trajectory, window);
        const std::lock_guard<std::mutex> lock(mutex);
        bias2 += bv.bias * bv.bias / runs;
        variance += bv.variance / runs;
      };
      const auto r =
          eval::monteCarlo(options, {{"linear-kf", [scales] { return makeLinearKf(scales); }}});
      double pos = 0.0, vel = 0.0;
      for (const eval::Metrics& m : r[0].runs) {
        pos += m.position_rmse / runs;
        vel += m.velocity_rmse / runs;
      }
      const double bias = std::sqrt(bias2);
      csv << parameters[p] << ',' << scale << ',' << pos << ',' << vel << ',' << bias << ','
          << variance << ',' << r[0].mean_anees << '\n';
      table.push_back({parameters[p], fixed(scale, 3), fixed(pos, 4), fixed(vel, 4), fixed(bias, 4),
                       fixed(variance, 6), fixed(r[0].mean_anees, 2)});
    }
  }
  progress.clear();
  printTable(out, table);
  writeAtomically(dir / "sweep.csv", [&](std::ostream& f) { f << csv.str(); });
  return plot(out, "sweep", dir.string());
}

}  // namespace legkit::tools
