#include "run_command.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <vector>

#include "estimation/contact/detectors.hpp"
#include "estimation/contact_pipeline.hpp"
#include "estimation/estimators.hpp"
#include "estimation/log_conditioning.hpp"
#include "estimation/log_frontend.hpp"
#include "estimation/settings.hpp"
#include "estimation/slip/slip_guard.hpp"
#include "eval/consistency.hpp"
#include "eval/contact_training.hpp"
#include "eval/log_run.hpp"
#include "eval/metrics.hpp"
#include "eval/monte_carlo.hpp"
#include "eval/runner.hpp"
#include "io/log_reader.hpp"
#include "io/log_writer.hpp"
#include "output.hpp"
#include "scenarios.hpp"
#include "sim/physics_simulator.hpp"
#include "sim/simulator.hpp"
#include "validators.hpp"

namespace legkit::tools {
namespace {

namespace fs = std::filesystem;

// One row per kept row (estimateRows): the estimate and, for a filter, its standard deviations in
// the BaseCovariance convention (sigma_theta*, sigma_v*, sigma_p*) and its NEES. A comment line
// gives the NEES degrees of freedom and its single-run 95 % bounds for the plots.
// `stamps`, when not empty, are the log's own stamps of its rows (the estimates are one per row),
// written in place of the smoothed ones the estimators ran on. Then contact_0..contact_<n-1>, the
// feet of `num_feet` the estimator was given in stance at that row (1) or not (0).
void writeEstimates(std::ostream& f, const eval::RunResult& run, double rate,
                    const std::vector<double>& stamps, int num_feet) {
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
  for (int foot = 0; foot < num_feet; ++foot) f << ",contact_" << foot;
  f << '\n';
  for (const std::size_t k : estimateRows(run.trajectory, rate)) {
    const EstimateSample& e = run.trajectory[k];
    f << (stamps.empty() ? e.t : stamps[k]) << ',' << e.p.x() << ',' << e.p.y() << ',' << e.p.z()
      << ',' << e.q.w() << ',' << e.q.x() << ',' << e.q.y() << ',' << e.q.z() << ',' << e.v.x()
      << ',' << e.v.y() << ',' << e.v.z();
    if (filter) {
      for (int i = 0; i < 9; ++i) f << ',' << run.sigma[k](i);
    }
    if (nees) f << ',' << run.nees[k];
    for (int foot = 0; foot < num_feet; ++foot) f << ',' << run.given_contact[k][foot];
    f << '\n';
  }
}

// TUM trajectory format (Sturm et al. 2012), as evo reads it: "t tx ty tz qx qy qz qw" for each
// of `rows`, at the stamps of the estimate files (writeEstimates).
void writeTum(std::ostream& f, const std::vector<EstimateSample>& samples,
              const std::vector<std::size_t>& rows, const std::vector<double>& stamps) {
  f << std::fixed << std::setprecision(9);
  for (const std::size_t k : rows) {
    const EstimateSample& s = samples[k];
    f << (stamps.empty() ? s.t : stamps[k]) << ' ' << s.p.x() << ' ' << s.p.y() << ' ' << s.p.z()
      << ' ' << s.q.x() << ' ' << s.q.y() << ' ' << s.q.z() << ' ' << s.q.w() << '\n';
  }
}

// The log's truth in TUM format: the rows an estimate file keeps, less the masked ones.
void writeTumTruth(std::ostream& f, const io::Log& log, double rate,
                   const std::vector<double>& stamps) {
  std::vector<EstimateSample> truth;
  for (const io::LogRow& row : log.rows) truth.push_back({row.t, row.gt_q, row.gt_v, row.gt_p});
  std::vector<std::size_t> rows = estimateRows(truth, rate);
  const auto masked = [&](std::size_t k) { return log.layout.gt_valid && !log.rows[k].gt_valid; };
  rows.erase(std::remove_if(rows.begin(), rows.end(), masked), rows.end());
  writeTum(f, truth, rows, stamps);
}

// "all", 0 (both: every sample) or a rate in [1e-3, 1e6] Hz: a row every 1000 s at the least
// (a simulated run is at most an hour), every microsecond at the most (above the log's own rate
// it keeps every sample anyway; 1e308 was once taken as it was).
std::string parseEstimateRate(const std::string& text, double& rate) {
  if (text == "all") {
    rate = 0.0;
    return "";
  }
  std::size_t used = 0;
  try {
    rate = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(rate) ||
      !(rate == 0.0 || (rate >= 1e-3 && rate <= 1e6))) {
    return "expected 0 or 'all' (every sample) or a rate in [0.001, 1e6] Hz, got " +
           detail::shown(text);
  }
  return "";
}

std::string number(double value) {
  std::ostringstream os;
  os << value;
  return os.str();
}

std::string cell(double value, int precision) {
  if (std::isnan(value)) return "n/c";  // not computed (eval/metrics.hpp): no pairs, no distance
  std::ostringstream os;
  os << std::fixed << std::setprecision(precision) << value;
  return os.str();
}

// The distances RPE is computed over [m]: summary.json has each, the table the first.
constexpr std::array<double, 2> kRpeDistances = {1.0, 5.0};

// The table's RPE: the translation error over kRpeDistances[0] in % of it (n/c if not computed).
std::string rpeCell(const eval::Metrics& m) {
  const auto e = std::find_if(m.rpe.begin(), m.rpe.end(), [](const eval::RelativeError& r) {
    return r.distance == kRpeDistances.front();
  });
  return cell(e == m.rpe.end() ? eval::kNotComputed : e->translation_percent, 1);
}

// Each run's detected contacts against the log's true contact (the rows the run covered).
std::optional<eval::ContactScores> contactScores(const io::Log& log, const eval::RunResult& run) {
  const std::size_t n = run.detected_contact.size();
  if (!log.layout.contact_truth || n < 2) return std::nullopt;
  std::vector<double> t(n);
  std::vector<eval::FootFlags> truth(n);
  for (std::size_t k = 0; k < n; ++k) {
    t[k] = log.rows[k].t;
    truth[k] = {};
    for (int foot = 0; foot < log.layout.num_feet; ++foot) {
      truth[k][foot] = log.rows[k].gt_feet[foot].contact;
    }
  }
  return eval::scoreContacts(t, run.detected_contact, truth, log.layout.num_feet);
}

// "truth (the log's contact flags)" or "<detector>", then the slip reaction and the rolling foot.
std::string describeContacts(const ContactPipeline& pipeline, bool joints) {
  const PipelineOptions& o = pipeline.options();
  std::string s = o.contact == "truth" ? "the log's contact flags (--contact truth)"
                                       : "detected by " + pipeline.source();
  s += "; slip handling: " + std::string(slip::slipReactionName(o.slip));
  if (joints) s += o.rolling_foot ? "; rolling foot: on" : "; rolling foot: off";
  s += o.settle_time > 0.0 ? "; touchdown settling: " + number(1e3 * o.settle_time) + " ms"
                           : "; touchdown settling: off";
  return s;
}

// The name of foot id `foot` in a row's run ("foot <id>" when the row has no names).
std::string footName(const RunRow& r, int foot) {
  return foot < static_cast<int>(r.foot_names.size()) ? r.foot_names[foot]
                                                      : "foot " + std::to_string(foot);
}

double share(long part, long whole) {
  return whole > 0 ? static_cast<double>(part) / static_cast<double>(whole) : 0.0;
}

// summary.json's "feet" of one run: per foot its contact diagnostics (ContactDiagnostics).
nlohmann::json contactFeetJson(const RunRow& r) {
  const ContactDiagnostics& d = r.run.contact_diagnostics;
  nlohmann::json feet = nlohmann::json::array();
  for (int foot = 0; foot < d.num_feet; ++foot) {
    const FootContactDiagnostics& f = d.feet[foot];
    nlohmann::json decided = nlohmann::json::object();
    for (std::size_t k = 0; k < d.sources.size(); ++k) {
      decided[d.sources[k]] = share(f.decided[k], d.samples);
    }
    const char* problem = f.topProblem();
    feet.push_back(
        {{"foot", foot},
         {"name", footName(r, foot)},
         {"contact",
          {{"samples", d.samples},
           {"decided_by", decided},
           {"undecided", share(f.undecided, d.samples)},
           {"handovers", f.handovers},
           {"handovers_down", f.handovers_down},
           {"handover_problem", problem ? nlohmann::json(problem) : nlohmann::json(nullptr)},
           {"handover_problem_count", f.topProblemCount()},
           {"stance_share", share(f.stance, d.samples)},
           {"touchdowns", f.touchdowns},
           {"settled_samples", f.settled},
           {"slipping_samples", f.slipping}}}});
  }
  return feet;
}

}  // namespace

std::optional<NisCheck> checkNis(const eval::RunResult& run) {
  if (!run.stance_nis || run.stance_nis->dimensions == 0) return std::nullopt;
  NisCheck c;
  c.updates = run.stance_nis->updates;
  c.dimensions = run.stance_nis->dimensions;
  c.mean = run.stance_nis->meanPerDimension();
  const double D = static_cast<double>(c.dimensions);
  c.upper = std::max(kNisOverConfident, eval::chiSquareQuantile(0.999, D) / D);
  c.lower = std::min(kNisOverCautious, eval::chiSquareQuantile(0.001, D) / D);
  c.verdict = c.mean > c.upper   ? "over-confident"
              : c.mean < c.lower ? "over-cautious"
                                 : "consistent";
  return c;
}

std::vector<std::string> nisWarnings(const std::vector<RunRow>& rows) {
  std::vector<std::string> warnings;
  for (const RunRow& r : rows) {
    const std::optional<NisCheck> c = checkNis(r.run);
    // Only the over-confident side is said: the front end's white floor (foot_point_sigma, 5 mm)
    // makes every measured log "over-cautious" (innovation_windows.hpp); summary.json keeps the
    // verdict either way.
    if (!c || !(c->mean > c->upper)) continue;
    std::ostringstream os;
    os << "legkit run: warning: " << r.run.name << ": stance-foot innovations " << cell(c->mean, 1)
       << "x larger than their covariance says (mean NIS per dimension over " << c->updates
       << " windows; 1 is consistent, above " << cell(c->upper, 1)
       << " over-confident): the noise settings do not fit this log (feet.stance_density, the "
       << "frontend and imu noise): run `legkit tune` on it";
    warnings.push_back(os.str());
  }
  return warnings;
}

nlohmann::json toJson(const std::vector<RunRow>& rows) {
  nlohmann::json all = nlohmann::json::array();
  for (const RunRow& r : rows) {
    nlohmann::json j = {
        {"estimator", r.run.name}, {"us_per_step", r.run.us_per_step}, {"healthy", r.run.ok()}};
    if (r.run.failed()) j["failure"] = eval::describe(*r.run.failure);
    nlohmann::json health = nlohmann::json::object();
    for (int f = 0; f < static_cast<int>(Fault::kCount); ++f) {
      const std::uint64_t n = r.run.health.count[static_cast<std::size_t>(f)];
      if (n > 0) health[faultName(static_cast<Fault>(f))] = n;
    }
    j["health"] = health;
    const double anees = eval::normalisedAnees(r.run);
    j["anees"] = std::isnan(anees) ? nlohmann::json(nullptr) : nlohmann::json(anees);
    j["contact_source"] = r.run.contact_source;
    j["pipeline_us_per_step"] = r.run.pipeline_us_per_step;
    j["slip_reaction"] = r.run.slip_reaction;
    if (const std::optional<NisCheck> nis = checkNis(r.run)) {
      j["stance_nis"] = {{"mean_per_dimension", nis->mean}, {"updates", nis->updates},
                         {"dimensions", nis->dimensions},   {"upper_bound", nis->upper},
                         {"lower_bound", nis->lower},       {"verdict", nis->verdict}};
    } else {
      j["stance_nis"] = nullptr;
    }
    if (!r.run.contact_diagnostics.sources.empty()) j["feet"] = contactFeetJson(r);
    j["rows_with_a_slipping_foot"] =
        std::count_if(r.run.slip.begin(), r.run.slip.end(),
                      [](const eval::SlipSummary& s) { return s.slipping > 0; });
    if (r.contact_scores) {
      const eval::ContactScores& c = *r.contact_scores;
      const auto number = [](double x) {
        return std::isnan(x) ? nlohmann::json(nullptr) : nlohmann::json(x);
      };
      j["contact_scores"] = {{"precision", number(c.precision)},
                             {"recall", number(c.recall)},
                             {"f1", number(c.f1)},
                             {"touchdown_delay_mean_ms", number(c.touchdown_delay_mean)},
                             {"touchdown_delay_p95_ms", number(c.touchdown_delay_p95)},
                             {"liftoff_delay_mean_ms", number(c.liftoff_delay_mean)},
                             {"liftoff_delay_p95_ms", number(c.liftoff_delay_p95)},
                             {"chatter_per_min", number(c.chatter_per_min)},
                             {"touchdowns", c.touchdowns},
                             {"liftoffs", c.liftoffs},
                             {"missed_touchdowns", c.missed_touchdowns},
                             {"missed_liftoffs", c.missed_liftoffs}};
    }
    if (r.metrics) {
      j["position_rmse_m"] = r.metrics->position_rmse;
      j["velocity_rmse_mps"] = r.metrics->velocity_rmse;
      j["drift_percent"] = r.metrics->drift_percent;
      j["roll_pitch_rmse_deg"] = r.metrics->tilt_rmse_deg;
      j["yaw_rmse_deg"] = r.metrics->yaw_rmse_deg;
      j["ate_rmse_m"] = r.metrics->ate_rmse;
      j["ate_se3_rmse_m"] = r.metrics->ate_se3_rmse;
      j["ate_4dof_rmse_m"] = r.metrics->ate_4dof_rmse;
      j["distance_m"] = r.metrics->distance;
      j["scored_rows"] = r.metrics->scored_rows;
      j["masked_rows"] = r.metrics->masked_rows;
      j["truth_velocity"] = r.metrics->velocity_method;
      for (const eval::RelativeError& e : r.metrics->rpe) {
        j["rpe"].push_back({{"distance_m", e.distance},
                            {"computed", e.computed},
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

std::vector<std::size_t> estimateRows(const std::vector<EstimateSample>& trajectory, double rate) {
  std::vector<std::size_t> rows;
  if (trajectory.empty()) return rows;
  const double t0 = trajectory.front().t;
  // The period a row falls in; a part per million of a period absorbs timestamps printed as
  // 0.0099999999 for 0.01.
  const auto period = [&](double t) { return std::floor((t - t0) * rate + 1e-6); };
  for (std::size_t k = 0; k < trajectory.size(); ++k) {
    if (rate <= 0.0 || k == 0 || k + 1 == trajectory.size() ||
        period(trajectory[k].t) > period(trajectory[rows.back()].t)) {
      rows.push_back(k);
    }
  }
  return rows;
}

void printRunTable(std::ostream& out, const std::vector<RunRow>& rows) {
  const std::string rpe = "RPE " + number(kRpeDistances.front()) + "m";
  std::vector<std::vector<std::string>> table = {{"estimator", "pos RMSE [m]", "vel RMSE [m/s]",
                                                  "drift [%]", "roll/pitch [deg]", "yaw [deg]",
                                                  "ATE se3 [m]", rpe + " [%]", "ANEES", "us/step"}};
  for (const RunRow& r : rows) {
    std::vector<std::string> cells = {r.run.name};
    if (r.run.failed()) {
      cells.insert(cells.end(), {"FAILED", "-", "-", "-", "-", "-", "-", "-", "-"});
    } else if (r.metrics) {
      const eval::Metrics& m = *r.metrics;
      cells.insert(cells.end(), {cell(m.position_rmse, 3), cell(m.velocity_rmse, 3),
                                 cell(m.drift_percent, 1), cell(m.tilt_rmse_deg, 2),
                                 cell(m.yaw_rmse_deg, 2), cell(m.ate_se3_rmse, 3), rpeCell(m)});
    } else {
      cells.insert(cells.end(), 7, "-");
    }
    if (!r.run.failed()) {
      const double anees = eval::normalisedAnees(r.run);
      cells.push_back(std::isnan(anees) ? "-" : cell(anees, 2));
      cells.push_back(cell(r.run.us_per_step, 2));
    }
    table.push_back(cells);
  }
  printTable(out, table);
  // The truth behind the metrics depends only on the log: the first scored estimator says it.
  const auto scored =
      std::find_if(rows.begin(), rows.end(), [](const RunRow& r) { return r.metrics.has_value(); });
  if (scored != rows.end()) {
    out << "ATE se3: after the least-squares SE(3) alignment on the truth, as evo_ape -a "
           "(4-DoF and first-pose ATEs in summary.json)\n"
        << rpe << ": translation error over each " << number(kRpeDistances.front())
        << " m travelled by the truth, in % of it\n";
  }
  if (scored != rows.end() &&
      (scored->metrics->masked_rows > 0 || scored->metrics->velocity_differentiated)) {
    out << "truth: " << scored->metrics->masked_rows
        << " rows masked (gt_valid = 0); velocity: " << scored->metrics->velocity_method << '\n';
  }
  // What went wrong, under the table: failures first, then what the estimators rejected.
  for (const RunRow& r : rows) {
    if (r.run.failed())
      out << "FAILED " << r.run.name << ": " << eval::describe(*r.run.failure) << '\n';
    else if (eval::voided(r.run.health, r.run.trajectory.size()))
      out << "VOID " << r.run.name << ": " << eval::rejectedInputs(r.run.health) << " of "
          << r.run.trajectory.size() << " samples' input rejected (more than "
          << number(100.0 * eval::kMaxRejectedShare) << " %): check the settings' limits and "
          << "priors\n";
  }
  for (const RunRow& r : rows) {
    const std::string health = eval::describe(r.run.health);
    if (!health.empty()) out << "health of " << r.run.name << ": " << health << '\n';
  }
}

void printContactTable(std::ostream& out, const std::vector<RunRow>& rows) {
  std::vector<const RunRow*> scored;
  for (const RunRow& r : rows) {
    if (r.contact_scores) scored.push_back(&r);
  }
  if (scored.empty()) return;
  bool same = true;
  for (const RunRow* r : scored) {
    same = same && r->run.detected_contact == scored.front()->run.detected_contact;
  }
  std::vector<std::vector<std::string>> table = {
      {"contacts of", "precision", "recall", "F1", "touchdown delay mean/p95 [ms]",
       "lift-off delay mean/p95 [ms]", "chatter [/min]"}};
  const auto delays = [](double mean, double p95) {
    return (std::isnan(mean) ? std::string("-") : cell(mean, 1)) + " / " +
           (std::isnan(p95) ? std::string("-") : cell(p95, 1));
  };
  for (const RunRow* r : scored) {
    const eval::ContactScores& c = *r->contact_scores;
    table.push_back(
        {same ? std::string("every estimator") : r->run.name, cell(c.precision, 3),
         cell(c.recall, 3), cell(c.f1, 3), delays(c.touchdown_delay_mean, c.touchdown_delay_p95),
         delays(c.liftoff_delay_mean, c.liftoff_delay_p95), cell(c.chatter_per_min, 1)});
    if (same) break;
  }
  out << "contact detection (" << scored.front()->run.contact_source
      << ") against the physics' true contact:\n";
  printTable(out, table);
}

void printContactFeet(std::ostream& out, const std::vector<RunRow>& rows) {
  // The first filter's run (dead reckoning's estimate makes every foot "slip"), else the first.
  const auto has = [](const RunRow& r) {
    return !r.run.contact_diagnostics.sources.empty() && r.run.contact_diagnostics.samples > 0;
  };
  auto first = std::find_if(rows.begin(), rows.end(),
                            [&](const RunRow& r) { return has(r) && !r.run.sigma.empty(); });
  if (first == rows.end()) first = std::find_if(rows.begin(), rows.end(), has);
  if (first == rows.end()) return;
  const ContactDiagnostics& d = first->run.contact_diagnostics;
  bool same = true;
  for (const RunRow& r : rows) {
    const ContactDiagnostics& e = r.run.contact_diagnostics;
    if (e.sources.empty()) continue;
    for (int foot = 0; foot < contact::kMaxFeet; ++foot) {
      const FootContactDiagnostics &a = d.feet[foot], &b = e.feet[foot];
      same = same && e.samples == d.samples && a.decided == b.decided && a.stance == b.stance &&
             a.handovers == b.handovers && a.settled == b.settled && a.slipping == b.slipping;
    }
  }
  const auto percent = [](long part, long whole) { return cell(100.0 * share(part, whole), 1); };
  std::vector<std::vector<std::string>> table = {{"foot", "decided by [% of samples]", "hand-overs",
                                                  "stance [%]", "touchdowns", "settled", "slipping",
                                                  "commonest hand-over"}};
  for (int foot = 0; foot < d.num_feet; ++foot) {
    const FootContactDiagnostics& f = d.feet[foot];
    std::string decided;
    for (std::size_t k = 0; k < d.sources.size(); ++k) {
      if (f.decided[k] == 0) continue;
      decided +=
          (decided.empty() ? "" : ", ") + d.sources[k] + " " + percent(f.decided[k], d.samples);
    }
    if (f.undecided > 0) {
      decided +=
          (decided.empty() ? "" : ", ") + std::string("none ") + percent(f.undecided, d.samples);
    }
    const char* problem = f.topProblem();
    table.push_back(
        {footName(*first, foot), decided, std::to_string(f.handovers), percent(f.stance, d.samples),
         std::to_string(f.touchdowns), std::to_string(f.settled), std::to_string(f.slipping),
         problem ? std::string(problem) + " (" + std::to_string(f.topProblemCount()) + ")"
                 : std::string("-")});
  }
  out << "contacts per foot ("
      << (same ? std::string("every estimator's run")
               : first->run.name + "'s run; each run's in summary.json")
      << "; settled and slipping in samples):\n";
  printTable(out, table);
}

RunCommand::RunCommand(CLI::App& app)
    : command_(app.add_subcommand(
          "run", "The main job: simulate (or read a log), run every estimator, print one table")) {
  CLI::App& c = *command_;
  scenario_option_ = c.add_option("--scenario", scenario_,
                                  "Simulated motion, " + scenarioHelp() +
                                      " (with --log or --dataset: no effect, a warning)")
                         ->check(CLI::IsMember(allScenarioNames()))
                         ->capture_default_str();
  duration_option_ = c.add_option("--duration", duration_,
                                  "Simulated time [s] (default 60; a physics scenario's own "
                                  "length, e.g. 10 s for physics-stand; with --log or --dataset: "
                                  "no effect, a warning)")
                         ->check(finiteRange(1e-3, kMaxSimulatedSeconds));
  seed_option_ = c.add_option("--seed", seed_,
                              "Random seed of the simulation and of the probabilistic "
                              "detector's training runs (with --log or --dataset it seeds only "
                              "the training: otherwise no effect, a warning)")
                     ->check(seedNumber())
                     ->capture_default_str();
  // Not CLI::ExistingFile: a log that cannot be read is an input error (exit 2), whatever the
  // reason, with the reader's own message.
  CLI::Option* log =
      c.add_option("--log", log_, "Run on this recorded log (CSV, chapters/57.0) instead")
          ->check(nonEmptyName());  // '' once simulated a 60 s trot instead
  // A recorded log shipped with the kit: its log and its settings file (a --config given as well
  // replaces the settings).
  c.add_option("--dataset", dataset_,
               "Run on a recorded log shipped with the kit, with its settings: icub-walking "
               "(data/icub-walking, config/robots/icub.yaml)")
      ->check(CLI::IsMember({"icub-walking"}))
      ->excludes(log)
      ->each([this](const std::string&) {
        log_ = LEGKIT_SOURCE_DIR "/data/icub-walking/walking.csv";
        if (config_.empty()) config_ = LEGKIT_SOURCE_DIR "/config/robots/icub.yaml";
      });
  c.add_option("--max-gap", max_gap_,
               "Longest step allowed between samples of --log [s] (default 10 median periods)")
      ->check(finiteRange(1e-6, 3600.0));
  c.add_option("--out", out_dir_, "Output folder (default legkit-out/<scenario>-seed<seed>)")
      ->check(nonEmptyName());
  c.add_option_function<std::string>(
       "--estimate-rate",
       [this](const std::string& text) {
         const std::string error = parseEstimateRate(text, estimate_rate_);
         if (!error.empty()) throw CLI::ValidationError("--estimate-rate", error);
       },
       "Rate of the estimate_*.csv files [Hz] (default 100); 0 or 'all': every sample. The "
       "metrics always use every sample")
      ->type_name("HZ|all");
  std::vector<std::string> contacts = {"truth"};
  for (const std::string& name : contact::detectorNames()) contacts.push_back(name);
  c.add_option("--contact", contact_,
               "Contact source: 'truth' (the log's contact flags) or a detector (default: " +
                   std::string(kDefaultContact) + "; 'truth' on the analytic scenarios)")
      ->check(CLI::IsMember(contacts));
  c.add_option("--slip", slip_,
               "What the filters do with a foot found slipping (default: " +
                   std::string(kDefaultSlip) + "; 'none' on the analytic scenarios)")
      ->check(CLI::IsMember({"none", "inflate", "drop", "imu-only"}));
  rolling_option_ =
      c.add_flag("!--no-rolling-foot", rolling_foot_,
                 "Stance feet at the foot sphere's centre, not at the ground point it touched (the "
                 "analytic scenarios' feet do not roll: always off there)");
  settle_option_ =
      c.add_option(
           "--settle", settle_,
           "Touchdown settling time [s]: a foot just put down is left out of the filters "
           "for this long (default " +
               number(kDefaultSettle) +
               "; 0 on the analytic scenarios; 0: off; 1 s at most, as in the settings file)")
          ->check(finiteRange(0.0, 1.0));
  // Not CLI::ExistingFile: a file that cannot be read is an input error (exit 2).
  c.add_option("--config", config_,
               "Settings file (`legkit config --print` writes the defaults): the estimators that "
               "run and their noise, priors and limits, the front-end noise, the contact pipeline, "
               "the detector's thresholds and a recorded log's planned gait (contact.gait, for "
               "--contact gait-clock). Options given on this command line override it")
      ->check(nonEmptyName());
  c.add_flag("--json", json_, "Print the summary as JSON (one object per estimator)");
  c.add_flag("--tum", tum_,
             "Also write each estimate_<name>.tum and the log's truth.tum in TUM format (t tx ty "
             "tz qx qy qz qw, the rows and stamps of the estimate files), for evo and the like");
  c.add_flag("!--no-plots", plots_, "Do not draw the PNG plots");
}

int RunCommand::run(std::ostream& out, const std::string& command_line) const {
  io::Log log;
  std::string source;
  // The contacts' noise the filters are told: for a simulated log, the simulator's own, so that
  // ANEES measures the filters and not a mismatched sensor model; for a recorded log, the
  // front end's defaults (chapters/57.3).
  FrontendNoise noise;
  // The settings file, when given: it replaces the defaults below, the command line's options
  // override it.
  const std::optional<Settings> settings =
      config_.empty() ? std::nullopt : std::optional<Settings>(loadSettings(config_));
  // A physics run whose robot fell (or whose simulation diverged): when and why (its log ends
  // there).
  std::string fall;
  // A recorded log's conditioning (estimation/log_conditioning.hpp) and its own stamps, which the
  // estimate files keep.
  std::optional<ConditioningReport> conditioning;
  std::vector<double> logged_stamps;
  if (!log_.empty()) {
    log = io::readLog(log_);
    for (const io::LogRow& row : log.rows) logged_stamps.push_back(row.t);
    try {
      checkTimeBase(log, max_gap_ > 0 ? std::optional<double>(max_gap_) : std::nullopt,
                    "--max-gap");
    } catch (const std::invalid_argument& e) {
      throw InputError(e.what());  // names the file and line
    }
    try {
      conditioning = condition(log, settings ? settings->conditioning : LogConditioning{});
    } catch (const std::invalid_argument& e) {
      throw InputError(log_ + ": " + e.what());
    }
    source = log_;
  } else if (isPhysicsScenario(scenario_)) {
    sim::PhysicsOptions options;
    options.scenario = sim::physicsScenarioByName(scenario_);
    options.duration = duration_option_->count() > 0 ? duration_ : options.scenario.duration;
    options.seed = seed_;
    checkPushesInRun(options);
    sim::PhysicsResult result = sim::simulatePhysics(options);
    if (result.status.fell) {
      fall = describeFall(result.status);
      if (result.log.rows.empty()) throw InputError(scenario_ + ": " + fall + "; nothing written");
    }
    log = std::move(result.log);
    noise = matchedFrontendNoise(options);
    std::ostringstream os;
    os << "simulated " << scenario_ << " (MuJoCo physics), " << options.duration << " s, seed "
       << seed_ << ", Go2-class sensors";
    source = os.str();
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
  // The contact pipeline every estimator runs on; the analytic scenarios keep their true flags.
  // A recorded log of foot columns without force columns has nothing a detector reads: its own
  // flags, when it has them, are the better default.
  const bool analytic = log_.empty() && !isPhysicsScenario(scenario_);
  const bool undetectable = !log.layout.joints && !log.layout.force && log.layout.contact;
  PipelineOptions pipeline_options;
  if (settings) {
    noise = frontendNoise(*settings);
    pipeline_options = settings->pipeline;
    pipeline_options.limits = settings->limits;
    if (!contact_.empty()) pipeline_options.contact = contact_;
    if (!slip_.empty()) pipeline_options.slip = *slip::slipReactionByName(slip_);
    if (rolling_option_->count() > 0) pipeline_options.rolling_foot = rolling_foot_;
    if (settle_option_->count() > 0) pipeline_options.settle_time = settle_;
    pipeline_options.rolling_foot = pipeline_options.rolling_foot && !analytic;
  } else {
    pipeline_options.contact = !contact_.empty()          ? contact_
                               : analytic || undetectable ? "truth"
                                                          : kDefaultContact;
    pipeline_options.slip = *slip::slipReactionByName(!slip_.empty() ? slip_
                                                      : analytic     ? "none"
                                                                     : kDefaultSlip);
    pipeline_options.rolling_foot = rolling_foot_ && !analytic;
    pipeline_options.settle_time = settle_option_->count() > 0 ? settle_
                                   : analytic                  ? 0.0
                                                               : kDefaultSettle;
  }
  // The options of a simulated run given with a recorded log: said, not silently ignored.
  if (!log_.empty()) {
    const auto unused = [](const std::string& option, const std::string& why) {
      std::cerr << "legkit run: warning: " << option << " has no effect on a recorded log (" << why
                << ")\n";
    };
    if (scenario_option_->count() > 0) unused("--scenario", "it chooses the simulated motion");
    if (duration_option_->count() > 0) unused("--duration", "the whole log is run");
    if (seed_option_->count() > 0 && pipeline_options.contact != "probabilistic") {
      unused("--seed",
             "it seeds the simulation, and on a log only --contact probabilistic's "
             "training runs");
    }
  }
  try {
    eval::checkContactSource(pipeline_options.contact, log.layout, source);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--contact truth: ") + e.what());
  }
  // The front end: the settings' IMU extrinsic, and for a log of generic joints the legs of the
  // settings' robot section (the analytic Go2 without a model file).
  const model::ImuExtrinsic extrinsic = settings ? settings->imu_extrinsic : model::ImuExtrinsic{};
  const RobotSettings robot = settings ? settings->robot : RobotSettings{};
  std::unique_ptr<model::LegKinematics> legs;
  try {
    legs = eval::logLegs(log.layout, robot);
  } catch (const std::runtime_error& e) {
    throw InputError((settings ? config_ + ": robot.model: " : std::string()) + e.what());
  }
  // The robot's counts against the log's columns, naming both files and the key (the front end's
  // own check names neither).
  try {
    eval::checkLogRobot(log.layout, robot, legs.get(), settings ? config_ : std::string(), source);
  } catch (const std::invalid_argument& e) {
    throw InputError(e.what());
  }
  const LogFrontend frontend = eval::logFrontend(log.layout, legs.get(), noise, extrinsic);
  const int num_feet = legs ? legs->numFeet() : log.layout.num_feet;
  // The detectors' forces scaled to the robot's weight, then the settings' own (contact.schmitt).
  const Settings& given = settings ? *settings : defaultSettings();
  const double mass = robotMass(given, legs.get());
  contact::DetectorContext context = detectorContext(given, mass, num_feet);
  if (log_.empty() && !analytic) {
    context.gait = eval::plannedGait(sim::physicsScenarioByName(scenario_));
  }
  // The logistic contact probability has no stored coefficients: the kit trains it from the seed
  // (simulated physics runs with seeds seed + 1000.., never this run's).
  std::optional<double> training_s;
  if (pipeline_options.contact == "probabilistic") {
    const auto start = std::chrono::steady_clock::now();
    context.logistic = eval::trainContactModel(seed_);
    training_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  // A recorded log's planned gait comes from the settings (contact.gait).
  if (!log_.empty() && settings) {
    try {
      context.gait = gaitSchedule(*settings, num_feet);
    } catch (const std::invalid_argument& e) {
      throw InputError(e.what());
    }
  }
  if (pipeline_options.contact == "gait-clock" && !context.gait) {
    throw UsageError("--contact gait-clock: " + eval::noGait());
  }
  std::optional<ContactPipeline> made;
  try {
    made.emplace(frontend, pipeline_options, context);
  } catch (const std::invalid_argument& e) {  // a detector this log or robot cannot feed
    throw UsageError("--contact " + pipeline_options.contact + ": " + e.what());
  }
  ContactPipeline& pipeline = *made;
  const std::string contacts = describeContacts(pipeline, log.layout.joints);

  const fs::path dir = !out_dir_.empty() ? fs::path(out_dir_)
                       : !log_.empty()
                           ? fs::path("legkit-out") / fs::path(log_).stem()
                           : fs::path("legkit-out") / (scenario_ + "-seed" + std::to_string(seed_));
  // The folder is complete only once summary.json, the manifest of what this run wrote, is in
  // it: the previous one goes first (and the files it listed), this one is written last.
  OutputFolder folder(dir, "summary.json");
  const fs::path log_path = log_.empty() ? folder.path("log.csv") : fs::path(log_);
  if (log_.empty()) folder.write("log.csv", [&](std::ostream& f) { io::writeLog(f, log); });
  if (tum_ && log.layout.ground_truth) {
    folder.write("truth.tum",
                 [&](std::ostream& f) { writeTumTruth(f, log, estimate_rate_, logged_stamps); });
  }

  // A pose-only truth's velocity: its central difference over this window [s].
  eval::TruthOptions truth_options;
  if (settings) truth_options.velocity_window = settings->truth_velocity_window;
  const EstimateSample x0 = eval::initialState(log, truth_options.velocity_window);
  // initialisation.gyro_bias: still-window starts every estimator's gyro bias from the log's
  // still start; without a still window the run says so and starts at zero.
  const eval::RunStart start = settings ? eval::runStart(log, *settings) : eval::RunStart{};
  const std::optional<eval::StillStart>& still = start.still;
  std::vector<RunRow> rows;
  // The feet's names for the per-foot contact diagnostics: the robot's, or the quadruped's legs.
  std::vector<std::string> foot_names;
  for (int foot = 0; foot < num_feet; ++foot) {
    foot_names.push_back(legs                       ? legs->footName(foot)
                         : num_feet == io::kNumLegs ? std::string(io::kLegNames[foot])
                                                    : "foot " + std::to_string(foot));
  }
  // The analytic scenarios' legs are exact: the estimators' own leg noise, not a robot's.
  const Settings estimator_settings = settings   ? *settings
                                      : analytic ? withExactLegs(defaultSettings())
                                                 : defaultSettings();
  const std::vector<std::string> names =
      estimator_settings.estimators.empty() ? estimatorNames() : estimator_settings.estimators;
  for (const std::string& name : names) {
    const std::unique_ptr<Estimator> e = makeEstimator(name, estimator_settings);
    RunRow r{eval::runOnLog(*e, log, pipeline, x0, truth_options.velocity_window, start.gyroBias()),
             std::nullopt, std::nullopt, foot_names};
    if (log.layout.ground_truth && !r.run.failed()) {
      r.metrics = eval::compare(log, r.run.trajectory, {kRpeDistances.begin(), kRpeDistances.end()},
                                truth_options);
    }
    r.contact_scores = contactScores(log, r.run);
    folder.write("estimate_" + r.run.name + ".csv", [&](std::ostream& f) {
      writeEstimates(f, r.run, estimate_rate_, logged_stamps, num_feet);
    });
    if (tum_) {
      folder.write("estimate_" + r.run.name + ".tum", [&](std::ostream& f) {
        writeTum(f, r.run.trajectory, estimateRows(r.run.trajectory, estimate_rate_),
                 logged_stamps);
      });
    }
    rows.push_back(std::move(r));
  }
  bool all_ok = true;
  for (const RunRow& r : rows) all_ok = all_ok && r.run.ok();
  std::string plot_failure;  // empty: drawn (or not asked for)
  if (plots_) {
    const fs::file_time_type drawing = fs::file_time_type::clock::now();
    plot_failure = plot("run_plots.py", {dir.string(), "--log", log_path.string()});
    folder.adopt(".png", drawing);
  }
  // A plot that failed is an output not written (2); it outranks an unhealthy estimator (3).
  const int status = plotFailed(plot_failure) ? kExitInput
                     : all_ok && fall.empty() ? kExitOk
                                              : kExitUnhealthy;
  nlohmann::json summary = {
      {"legkit_version", LEGKIT_VERSION},
      {"command", command_line},
      {"source", source},
      {"config", settings ? nlohmann::json(config_) : nlohmann::json(nullptr)},
      {"contacts",
       {{"source", pipeline.source()},
        {"slip", slip::slipReactionName(pipeline_options.slip)},
        {"rolling_foot", pipeline_options.rolling_foot},
        {"settle_time_s", pipeline_options.settle_time},
        {"training_s", training_s ? nlohmann::json(*training_s) : nlohmann::json(nullptr)},
        {"no_contact_bound_s", pipeline_options.no_contact_bound}}},
      {"frontend",
       conditioning ? nlohmann::json(conditioning->describe()) : nlohmann::json(nullptr)},
      {"start",
       {{"gyro_bias", still ? nlohmann::json({still->b_g.x(), still->b_g.y(), still->b_g.z()})
                            : nlohmann::json(nullptr)},
        {"still_window_end_s", still ? nlohmann::json(still->t_end) : nlohmann::json(nullptr)},
        {"note", start.note.empty() ? nlohmann::json(nullptr) : nlohmann::json(start.note)}}},
      {"samples", log.rows.size()},
      {"estimate_rate_hz",
       estimate_rate_ > 0.0 ? nlohmann::json(estimate_rate_) : nlohmann::json("all")},
      {"exit_status", status},
      {"fell", fall.empty() ? nlohmann::json(nullptr) : nlohmann::json(fall)},
      {"plots", !plots_                ? "not drawn (--no-plots)"
                : plot_failure.empty() ? "drawn"
                                       : plot_failure},
      {"estimators", toJson(rows)}};
  folder.writeManifest(std::move(summary));

  if (json_) {
    out << toJson(rows).dump(2) << '\n';
  } else {
    out << "legkit run: " << source << " (" << log.rows.size() << " samples)\n";
    if (settings) out << "settings: " << config_ << "\n";
    out << "contacts: " << contacts << "\n";
    if (conditioning) out << "front end: " << conditioning->describe() << "\n";
    if (!start.note.empty()) out << "start: " << start.note << "\n";
    if (training_s) {
      out << "logistic contact model trained on simulated physics runs (seeds " << seed_ + 1000
          << ".." << seed_ + 1002 << ") in " << cell(*training_s, 1) << " s\n";
    }
    out << '\n';
    if (!fall.empty()) out << "STOPPED: " << fall << "; the table covers the log up to then\n\n";
    printRunTable(out, rows);
    if (log.layout.contact_truth) {
      out << '\n';
      printContactTable(out, rows);
    }
    out << '\n';
    printContactFeet(out, rows);
    out << "\nANEES: the mean over the run of NEES / its degrees of freedom (9, or 6 for the "
           "linear KF, whose attitude is an input); about 1 for a consistent filter.\n";
    std::string nis;
    for (const RunRow& r : rows) {
      if (const std::optional<NisCheck> c = checkNis(r.run)) {
        nis += (nis.empty() ? "" : ", ") + r.run.name + " " + cell(c->mean, 2);
      }
    }
    if (!nis.empty()) {
      out << "stance-foot NIS (r^T S^-1 r of each stance foot's innovations summed over 50 "
             "samples, mean per dimension; about 1 when the noise settings fit the log): "
          << nis << '\n';
    }
    if (!log.layout.ground_truth) out << "\n(the log has no ground truth: errors not computed)\n";
    out << "\nwrote " << dir.string() << "/ (" << (log_.empty() ? "log, " : "") << "estimates "
        << (estimate_rate_ > 0.0 ? "at " + number(estimate_rate_) + " Hz" : "at every sample")
        << (tum_ ? ", TUM files" : "") << (plots_ && plot_failure.empty() ? ", plots" : "")
        << ", summary.json)\n";
  }
  // Noise settings that do not fit the log (issue 22 item 3): said on stderr, after the table.
  for (const std::string& warning : nisWarnings(rows)) std::cerr << warning << '\n';
  if (!plot_failure.empty()) std::cerr << "legkit run: " << plot_failure << '\n';
  if (!fall.empty()) std::cerr << "legkit run: " << scenario_ << ": " << fall << '\n';
  return status;
}

}  // namespace legkit::tools
