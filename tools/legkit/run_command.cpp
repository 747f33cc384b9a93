#include "run_command.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "estimation/estimators.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/consistency.hpp"
#include "eval/metrics.hpp"
#include "eval/monte_carlo.hpp"
#include "eval/runner.hpp"
#include "io/log_reader.hpp"
#include "io/log_writer.hpp"
#include "sim/simulator.hpp"

namespace legkit::tools {
namespace {

namespace fs = std::filesystem;

struct Row {
  eval::RunResult run;
  std::optional<eval::Metrics> metrics;  // only when the log has ground truth
};

// One row per log row: the estimate and, for a filter, its standard deviations in the
// BaseCovariance convention (sigma_theta*, sigma_v*, sigma_p*) and its NEES. A comment line gives
// the NEES degrees of freedom and its single-run 95 % bounds for the plots.
void writeEstimates(const fs::path& path, const eval::RunResult& run) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path.string());
  const bool filter = !run.sigma.empty();
  const bool nees = !run.nees.empty();
  if (nees) {
    const eval::ChiSquareBounds b = eval::aneesBounds(run.nees_dof, 1);
    f << "# nees_dof " << run.nees_dof << " lower " << b.lower << " upper " << b.upper << '\n';
  }
  f << std::setprecision(10) << "t,px,py,pz,qw,qx,qy,qz,vx,vy,vz";
  if (filter) {
    f << ",sigma_thx,sigma_thy,sigma_thz,sigma_vx,sigma_vy,sigma_vz,sigma_px,sigma_py,sigma_pz";
  }
  if (nees) f << ",nees";
  f << '\n';
  for (std::size_t k = 0; k < run.trajectory.size(); ++k) {
    const EstimateSample& e = run.trajectory[k];
    f << e.t << ',' << e.p.x() << ',' << e.p.y() << ',' << e.p.z() << ',' << e.q.w() << ','
      << e.q.x() << ',' << e.q.y() << ',' << e.q.z() << ',' << e.v.x() << ',' << e.v.y() << ','
      << e.v.z();
    if (filter) {
      for (int i = 0; i < 9; ++i) f << ',' << run.sigma[k](i);
    }
    if (nees) f << ',' << run.nees[k];
    f << '\n';
  }
}

std::string cell(double value, int precision) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(precision) << value;
  return os.str();
}

void printTable(std::ostream& out, const std::vector<Row>& rows) {
  const char* header[] = {"estimator",        "pos RMSE [m]", "vel RMSE [m/s]", "drift [%]",
                          "roll/pitch [deg]", "yaw [deg]",    "ANEES",          "us/step"};
  const int width[] = {20, 13, 15, 10, 17, 10, 7, 8};
  for (int i = 0; i < 8; ++i)
    out << std::setw(width[i]) << (i == 0 ? std::left : std::right) << header[i] << ' ';
  out << '\n';
  for (const Row& r : rows) {
    std::vector<std::string> cells = {r.run.name};
    if (r.metrics) {
      const eval::Metrics& m = *r.metrics;
      cells.insert(cells.end(),
                   {cell(m.position_rmse, 3), cell(m.velocity_rmse, 3), cell(m.drift_percent, 1),
                    cell(m.tilt_rmse_deg, 2), cell(m.yaw_rmse_deg, 2)});
    } else {
      cells.insert(cells.end(), 5, "-");
    }
    const double anees = eval::normalisedAnees(r.run);
    cells.push_back(std::isnan(anees) ? "-" : cell(anees, 2));
    cells.push_back(cell(r.run.us_per_step, 2));
    for (int i = 0; i < 8; ++i)
      out << std::setw(width[i]) << (i == 0 ? std::left : std::right) << cells[i] << ' ';
    out << '\n';
  }
}

nlohmann::json toJson(const std::vector<Row>& rows) {
  nlohmann::json all = nlohmann::json::array();
  for (const Row& r : rows) {
    nlohmann::json j = {{"estimator", r.run.name}, {"us_per_step", r.run.us_per_step}};
    const double anees = eval::normalisedAnees(r.run);
    j["anees"] = std::isnan(anees) ? nlohmann::json(nullptr) : nlohmann::json(anees);
    if (r.metrics) {
      j["position_rmse_m"] = r.metrics->position_rmse;
      j["velocity_rmse_mps"] = r.metrics->velocity_rmse;
      j["drift_percent"] = r.metrics->drift_percent;
      j["roll_pitch_rmse_deg"] = r.metrics->tilt_rmse_deg;
      j["yaw_rmse_deg"] = r.metrics->yaw_rmse_deg;
      j["ate_rmse_m"] = r.metrics->ate_rmse;
      for (const eval::RelativeError& e : r.metrics->rpe) {
        j["rpe"].push_back({{"distance_m", e.distance},
                            {"pairs", e.pairs},
                            {"translation_rmse_m", e.translation_rmse},
                            {"translation_percent", e.translation_percent},
                            {"rotation_rmse_deg", e.rotation_rmse_deg}});
      }
    }
    all.push_back(j);
  }
  return all;
}

}  // namespace

RunCommand::RunCommand(CLI::App& app)
    : command_(app.add_subcommand(
          "run", "The main job: simulate (or read a log), run every estimator, print one table")) {
  CLI::App& c = *command_;
  std::string names;
  for (const std::string& n : sim::scenarioNames()) names += (names.empty() ? "" : ", ") + n;
  c.add_option("--scenario", scenario_, "Simulated motion: " + names)->capture_default_str();
  c.add_option("--duration", duration_, "Simulated time [s]")->capture_default_str();
  c.add_option("--seed", seed_, "Random seed of the simulation")->capture_default_str();
  c.add_option("--log", log_, "Run on this recorded log (CSV, chapters/57.0) instead")
      ->check(CLI::ExistingFile);
  c.add_option("--out", out_dir_, "Output folder (default legkit-out/<scenario>-seed<seed>)");
  c.add_flag("--json", json_, "Print the summary as JSON (one object per estimator)");
  c.add_flag("!--no-plots", plots_, "Do not draw the PNG plots");
}

int RunCommand::run(std::ostream& out) const {
  io::Log log;
  std::string source;
  // The contacts' noise the filters are told: for a simulated log, the simulator's own, so that
  // ANEES measures the filters and not a mismatched sensor model; for a recorded log, the
  // front end's defaults (chapters/57.3).
  FrontendNoise noise;
  if (!log_.empty()) {
    log = io::readLog(log_);
    source = log_;
  } else {
    sim::SimOptions options;
    options.scenario = sim::scenarioByName(scenario_);
    options.duration = duration_;
    options.seed = seed_;
    log = sim::simulate(options).log;
    noise = eval::matchedFrontendNoise(options);
    std::ostringstream os;
    os << "simulated " << scenario_ << ", " << duration_ << " s, seed " << seed_
       << ", Go2-class sensors";
    source = os.str();
  }
  const fs::path dir = !out_dir_.empty() ? fs::path(out_dir_)
                       : !log_.empty()
                           ? fs::path("legkit-out") / fs::path(log_).stem()
                           : fs::path("legkit-out") / (scenario_ + "-seed" + std::to_string(seed_));
  fs::create_directories(dir);
  if (log_.empty()) io::writeLog((dir / "log.csv").string(), log);

  const LogFrontend frontend(log.layout, model::QuadrupedKinematics(), noise);
  const EstimateSample x0 = eval::initialState(log);
  std::vector<Row> rows;
  for (const std::string& name : estimatorNames()) {
    const std::unique_ptr<Estimator> e = makeEstimator(name);
    Row r{eval::runOnLog(*e, log, frontend, x0), std::nullopt};
    if (log.layout.ground_truth) r.metrics = eval::compare(log, r.run.trajectory);
    writeEstimates(dir / ("estimate_" + r.run.name + ".csv"), r.run);
    rows.push_back(std::move(r));
  }

  if (json_) {
    out << toJson(rows).dump(2) << '\n';
  } else {
    out << "legkit run: " << source << " (" << log.rows.size() << " samples)\n\n";
    printTable(out, rows);
    out << "\nANEES: the mean over the run of NEES / its degrees of freedom (9, or 6 for the "
           "linear KF, whose attitude is an input); about 1 for a consistent filter.\n";
    if (!log.layout.ground_truth) out << "\n(the log has no ground truth: errors not computed)\n";
    out << "\nwrote " << dir.string() << "/ (log, estimates";
  }
  if (plots_ && log.layout.ground_truth) {
    const std::string command = "/usr/bin/python3 '" LEGKIT_SOURCE_DIR
                                "/tools/plots/run_plots.py' '" +
                                dir.string() + "' > /dev/null";
    const bool drawn = std::system(command.c_str()) == 0;
    if (!json_) out << (drawn ? ", plots" : "; plots FAILED: is python3-matplotlib installed?");
  }
  if (!json_) out << ")\n";
  return 0;
}

}  // namespace legkit::tools
