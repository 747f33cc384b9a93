#include "tune_command.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "estimation/estimators.hpp"
#include "estimation/settings.hpp"
#include "eval/tuning.hpp"
#include "io/log_reader.hpp"
#include "output.hpp"
#include "validators.hpp"

namespace legkit::tools {
namespace {

namespace fs = std::filesystem;

// value in %.<digits>g, "-" for NaN.
std::string number(double value, int digits = 3) {
  return formatG(value, digits);
}

}  // namespace

TuneCommand::TuneCommand(CLI::App& app)
    : command_(app.add_subcommand(
          "tune",
          "Noise settings fitted to a recorded log, reported on a part the fit never saw")) {
  CLI::App& c = *command_;
  c.add_option("log", log_, "The recorded log (the kit's CSV format)")
      ->check(nonEmptyName())
      ->required();
  c.add_option("--config", config_, "Settings file to start from (default: the kit's)")
      ->check(nonEmptyName());  // '' once started from the defaults
  c.add_option("--estimator", estimator_, "The filter whose score is fitted")
      ->check(CLI::IsMember(estimatorNames()))
      ->capture_default_str();
  c.add_option("--fit-share", fit_share_, "Share of the rows fitted (the rest is reported)")
      ->check(finiteRange(0.05, 0.95))
      ->capture_default_str();
  c.add_option("--out", out_, "The tuned settings file (default legkit-out/<log>-tuned.yaml)")
      ->check(nonEmptyName());
}

int TuneCommand::run(std::ostream& out) const {
  const Settings settings = config_.empty() ? defaultSettings() : loadSettings(config_);
  if (settings.pipeline.contact == "probabilistic") {
    throw UsageError(
        "tune: contact detector probabilistic is trained per run; tune with "
        "another detector (contact.detector) and keep the result");
  }
  const io::Log log = io::readLog(log_);
  eval::TuneOptions options;
  options.estimator = estimator_;
  options.fit_share = fit_share_;
  eval::TuneReport report;
  try {
    report = eval::tune(log, settings, contact::DetectorContext{}, options);
  } catch (const std::invalid_argument& e) {
    throw InputError(log_ + ": " + e.what());
  }

  out << "legkit tune " << log_ << (config_.empty() ? "" : " on " + config_) << ": fitted on "
      << report.fit_rows << " rows, reported on the " << report.held_out_rows
      << " from t = " << number(report.split_t, 4) << " s, the " << estimator_ << "'s "
      << (report.with_truth ? "log-likelihood of the truth" : "stance-foot NIS (no truth)")
      << "\n\n";
  std::vector<std::vector<std::string>> table = {{"parameter", "before", "after", "how"}};
  for (const eval::TunedParameter& p : report.parameters) {
    table.push_back({p.key, number(p.before), p.fitted ? number(p.after) : "=", p.how});
  }
  printTable(out, table);
  out << "\nOn the part the fit never saw (before -> after):\n";
  table = {{"estimator", "position RMSE [m]", "ANEES", "stance NIS/dim"}};
  for (const eval::HeldOutScore& h : report.held_out) {
    table.push_back({h.estimator,
                     number(h.position_rmse_before) + " -> " + number(h.position_rmse_after),
                     number(h.anees_before) + " -> " + number(h.anees_after),
                     number(h.nis_before) + " -> " + number(h.nis_after)});
  }
  printTable(out, table);

  // The whole tuned file; its robot model absolute, as the file may live elsewhere.
  Settings tuned = report.settings;
  if (!tuned.robot.model.empty()) tuned.robot.model = fs::absolute(tuned.robot.model).string();
  const fs::path file =
      !out_.empty() ? fs::path(out_)
                    : fs::path("legkit-out") / (fs::path(log_).stem().string() + "-tuned.yaml");
  if (!file.parent_path().empty()) fs::create_directories(file.parent_path());
  writeAtomically(file, [&](std::ostream& f) {
    f << "# legkit tune " << log_ << (config_.empty() ? "" : " --config " + config_) << "\n"
      << settingsYaml(tuned);
  });
  out << "\nChanged keys:\n";
  for (const eval::TunedParameter& p : report.parameters) {
    if (p.fitted) out << "  " << p.key << ": " << number(p.after, 4) << "\n";
  }
  out << "The tuned settings: " << file.string() << " (legkit run --log " << log_ << " --config "
      << file.string() << ")\n";
  return kExitOk;
}

}  // namespace legkit::tools
