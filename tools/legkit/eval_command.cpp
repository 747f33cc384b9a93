#include "eval_command.hpp"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <optional>

#include "estimation/estimators.hpp"
#include "estimation/settings.hpp"
#include "eval/contact_training.hpp"
#include "eval/log_run.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "eval_report.hpp"
#include "io/log_reader.hpp"
#include "output.hpp"
#include "shard.hpp"
#include "validators.hpp"

namespace legkit::tools {
namespace {

namespace fs = std::filesystem;

constexpr double kRpeDistance = 1.0;  // [m], the RPE of `legkit run`'s table

// The folder's logs: its regular *.csv files, sorted by name.
std::vector<std::string> logNames(const std::string& dir) {
  std::error_code error;
  if (!fs::is_directory(dir, error)) throw InputError(dir + ": not a folder (legkit eval DIR)");
  std::vector<std::string> names;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, error)) {
    if (entry.is_regular_file() && entry.path().extension() == ".csv") {
      names.push_back(entry.path().filename().string());
    }
  }
  if (error) throw InputError(dir + ": cannot be listed (" + error.message() + ")");
  if (names.empty()) throw InputError(dir + ": no *.csv logs in it");
  std::sort(names.begin(), names.end());
  return names;
}

// `start`: the run's still start (eval::describeStart), when the settings ask for one.
EvalEstimatorRow evaluate(const io::Log& log, const Settings& settings, const std::string& name,
                          const contact::DetectorContext& context, std::string& start) {
  const eval::RunResult run = eval::runWithSettings(log, settings, name, context);
  start = run.start;
  EvalEstimatorRow r{name, run.ok(), "", NAN, NAN, NAN, NAN, eval::normalisedAnees(run)};
  if (run.failed()) {
    r.failure = eval::describe(*run.failure);
  } else if (!run.ok()) {
    r.failure = eval::describe(run.health);
  }
  if (log.layout.ground_truth && !run.failed()) {
    eval::TruthOptions truth;
    truth.velocity_window = settings.truth_velocity_window;
    const eval::Metrics m = eval::compare(log, run.trajectory, {kRpeDistance}, truth);
    r.position_rmse = m.position_rmse;
    r.ate_se3 = m.ate_se3_rmse;
    r.rpe_percent = m.rpe.front().translation_percent;
    r.rpe_deg = m.rpe.front().rotation_rmse_deg;
  }
  return r;
}

// The folder's own name, for the default output folder.
std::string folderName(const std::string& dir) {
  fs::path p = fs::path(dir).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  const std::string name = p.filename().string();
  return name.empty() || name == "." || name == ".." ? "logs" : name;
}

// One log through every estimator; an error reading or running it is the row's, naming the file.
EvalLogRow evaluateLog(const fs::path& path, const Settings& settings,
                       const std::vector<std::string>& names,
                       const contact::DetectorContext& context) {
  EvalLogRow row{path.filename().string(), "", 0, {}};
  std::string start;  // the still start, when the settings ask for one (every estimator's)
  try {
    const io::Log log = io::readLog(path.string());
    row.samples = static_cast<int>(log.rows.size());
    for (const std::string& name : names)
      row.estimators.push_back(evaluate(log, settings, name, context, start));
  } catch (const std::exception& e) {
    const std::string what = e.what();
    row.error = what.rfind(path.string(), 0) == 0 ? what : path.string() + ": " + what;
    row.estimators.clear();
  }
  std::cerr << "legkit eval: " << row.log << (row.error.empty() ? " done" : " FAILED");
  if (!start.empty()) std::cerr << "; start: " << start;
  std::cerr << '\n';
  return row;
}

}  // namespace

EvalCommand::EvalCommand(CLI::App& app)
    : command_(app.add_subcommand(
          "eval",
          "Every log (*.csv) of a folder through the settings' estimators: ATE, RPE, "
          "ANEES per log and overall")) {
  command_->add_option("dir", dir_, "Folder of logs (every *.csv in it, in name order)")
      ->required()
      ->check(nonEmptyName());
  command_->add_option("--config", config_, "Settings file (robot, noise, estimators)")
      ->required()
      ->check(nonEmptyName());
  command_
      ->add_option("--shard", shard_,
                   "Evaluate shard i of N (a block of the logs) into --out; `legkit merge` "
                   "combines the N shards into exactly the single-machine result")
      ->check(shardSpec())
      ->capture_default_str();
  command_
      ->add_option(
          "--out", out_,
          "Output folder (default legkit-out/eval-<folder name>, -shard-<i>-of-<N> for a shard)")
      ->check(nonEmptyName());
}

int EvalCommand::run(std::ostream& out) const {
  const Shard shard = parseShard(shard_);
  const std::vector<std::string> logs = logNames(dir_);
  const Block block = shardBlock(shard, static_cast<int>(logs.size()), "logs");
  const Settings settings = loadSettings(config_);
  const std::vector<std::string> names =
      settings.estimators.empty() ? estimatorNames() : settings.estimators;
  // Shards on one machine must not share a folder.
  const std::string suffix = shard.whole() ? std::string()
                                           : "-shard-" + std::to_string(shard.index) + "-of-" +
                                                 std::to_string(shard.count);
  const fs::path dir = !out_.empty()
                           ? fs::path(out_)
                           : fs::path("legkit-out") / ("eval-" + folderName(dir_) + suffix);
  makeOutputFolder(dir);  // before the runs: a bad --out fails at once
  contact::DetectorContext context;
  if (settings.pipeline.contact == "probabilistic") context.logistic = eval::trainContactModel(1);
  std::vector<EvalLogRow> rows;
  for (int i = block.begin; i < block.end; ++i) {
    rows.push_back(evaluateLog(fs::path(dir_) / logs[i], settings, names, context));
  }
  const nlohmann::json options = {{"dir", dir_},
                                  {"config", config_},
                                  {"config_digest", fileDigest(config_)},
                                  {"logs", logs},
                                  {"estimators", names}};
  if (shard.whole()) {
    return reportEval(out, std::cerr, dir, evalHeading(options), rows);
  }
  OutputFolder output(dir, kShardManifest);
  nlohmann::json manifest = shardManifest("eval", options, shard, block);
  manifest["rows"] = toJson(rows);
  output.writeManifest(std::move(manifest));
  out << "legkit eval, shard " << shard.text() << ": logs " << block.begin + 1 << ".." << block.end
      << " of " << logs.size() << " in " << dir.string()
      << "/; `legkit merge OUT SHARD_DIR...` makes the table and eval.csv from all " << shard.count
      << " shards\n";
  for (const EvalLogRow& row : rows) {
    if (!row.error.empty()) std::cerr << "legkit eval: FAILED " << row.error << '\n';
  }
  return evalStatus(rows);
}

}  // namespace legkit::tools
