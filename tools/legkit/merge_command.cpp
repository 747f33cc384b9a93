#include "merge_command.hpp"

#include <filesystem>
#include <iostream>

#include "consistency_report.hpp"
#include "contact_report.hpp"
#include "convergence_report.hpp"
#include "eval_report.hpp"
#include "faults_report.hpp"
#include "output.hpp"
#include "shard.hpp"
#include "validators.hpp"

namespace legkit::tools {
namespace {

namespace fs = std::filesystem;

int items(const ShardInput& last) {
  return last.block.end;
}

// The shards end at the last of `total` items, else InputError.
void requireAll(const std::vector<ShardInput>& shards, int total, const std::string& what) {
  if (items(shards.back()) != total) {
    throw InputError(shards.back().dir + ": the shards end at " + what + " " +
                     std::to_string(items(shards.back())) + " of " + std::to_string(total) +
                     "; nothing merged");
  }
}

// The scenarios of shard s's block: options["scenarios"][begin, end) (to end at most `limit`).
std::vector<std::string> blockNames(const nlohmann::json& options, const ShardInput& s, int limit) {
  std::vector<std::string> names;
  const auto all = options.at("scenarios").get<std::vector<std::string>>();
  for (int i = s.block.begin; i < std::min(s.block.end, limit); ++i) names.push_back(all.at(i));
  return names;
}

}  // namespace

MergeCommand::MergeCommand(CLI::App& app)
    : command_(
          app.add_subcommand("merge",
                             "Combine the shards of a sharded study or eval (--shard i/N) into the "
                             "single-machine result")) {
  command_->add_option("out", out_, "Output folder of the merged result")
      ->required()
      ->check(nonEmptyName());
  command_->add_option("shards", shards_, "The N shards' output folders, in any order")
      ->required()
      ->check(nonEmptyName());
  command_->add_flag("!--no-plots", plots_, "Do not draw a study's PNG figure");
}

int MergeCommand::run(std::ostream& out) const {
  std::vector<ShardInput> inputs;
  for (const std::string& dir : shards_) inputs.push_back(readShard(dir));
  const std::vector<ShardInput> shards = checkShards(std::move(inputs));
  const std::string kind = shards.front().manifest.at("kind").get<std::string>();
  if (kind == "study consistency") return study(out, shards, "consistency");
  if (kind == "study convergence") return study(out, shards, "convergence");
  if (kind == "study sweep") return study(out, shards, "sweep");
  if (kind == "eval") return eval(out, shards);
  if (kind == "study contact") return contact(out, shards);
  if (kind == "study slip") return slip(out, shards);
  if (kind == "study faults") return faults(out, shards);
  throw InputError(shards.front().dir + ": shards of '" + kind +
                   "', which this legkit cannot merge");
}

int MergeCommand::study(std::ostream& out, const std::vector<ShardInput>& shards,
                        const std::string& name) const {
  const nlohmann::json& options = shards.front().manifest.at("options");
  const int runs = options.at("runs").get<int>();
  if (items(shards.back()) != runs) {
    throw InputError(shards.back().dir + ": the shards end at run " +
                     std::to_string(items(shards.back())) + " of " + std::to_string(runs) +
                     "; nothing merged");
  }
  const double duration = options.at("duration").get<double>();
  if (name == "consistency" || name == "sweep") {
    MonteCarloRows all;
    for (const ShardInput& s : shards) {
      appendMonteCarloRows(all, readMonteCarloRows(fs::path(s.dir) / kStudyRows, s.block), s.dir);
    }
    makeOutputFolder(out_);
    if (name == "sweep") {
      reportSweep(out, out_, all, duration);
    } else {
      reportConsistency(out, out_, all, duration, options.at("correct_yaw").get<bool>());
    }
  } else {
    ConvergenceRows all;
    for (const ShardInput& s : shards) {
      appendConvergenceRows(all, readConvergenceRows(fs::path(s.dir) / kStudyRows, s.block), s.dir);
    }
    makeOutputFolder(out_);
    reportConvergence(out, out_, all, duration);
  }
  if (!plots_) return kExitOk;
  const std::string failed = plot("study_plots.py", {name, out_});
  out << (failed.empty() ? "figure: " + out_ + "/" + name + ".png" : failed) << '\n';
  return plotFailed(failed) ? kExitInput : kExitOk;
}

int MergeCommand::eval(std::ostream& out, const std::vector<ShardInput>& shards) const {
  const nlohmann::json& options = shards.front().manifest.at("options");
  const nlohmann::json& logs = options.at("logs");
  if (items(shards.back()) != static_cast<int>(logs.size())) {
    throw InputError(shards.back().dir + ": the shards end at log " +
                     std::to_string(items(shards.back())) + " of " + std::to_string(logs.size()) +
                     "; nothing merged");
  }
  std::vector<EvalLogRow> rows;
  for (const ShardInput& s : shards) {
    const std::string where = s.dir + "/" + kShardManifest;
    const std::vector<EvalLogRow> part = evalRowsFromJson(
        s.manifest.contains("rows") ? s.manifest.at("rows") : nlohmann::json(), where);
    if (static_cast<int>(part.size()) != s.block.end - s.block.begin) {
      throw InputError(where + ": " + std::to_string(part.size()) + " logs, its block has " +
                       std::to_string(s.block.end - s.block.begin) + "; nothing merged");
    }
    for (std::size_t k = 0; k < part.size(); ++k) {
      if (part[k].log != logs.at(s.block.begin + k).get<std::string>()) {
        throw InputError(where + ": log '" + part[k].log + "' where '" +
                         logs.at(s.block.begin + k).get<std::string>() +
                         "' was expected; nothing merged");
      }
    }
    rows.insert(rows.end(), part.begin(), part.end());
  }
  makeOutputFolder(out_);
  return reportEval(out, std::cerr, out_, evalHeading(options), rows);
}

int MergeCommand::contact(std::ostream& out, const std::vector<ShardInput>& shards) const {
  const nlohmann::json& options = shards.front().manifest.at("options");
  const int total = static_cast<int>(options.at("scenarios").size());
  requireAll(shards, total, "scenario");
  const std::string where = shards.front().dir + "/" + kShardManifest;
  const ContactHeading heading{
      options.at("seed").get<unsigned>(), options.at("duration").get<double>(),
      options.at("filter").get<std::string>(),
      parseExact(options.at("f_high").get<std::string>(), where + ": f_high"),
      parseExact(options.at("f_low").get<std::string>(), where + ": f_low")};
  ContactRows all;
  for (const ShardInput& s : shards) {
    appendContactRows(
        all, readContactRows(fs::path(s.dir) / kStudyRows, blockNames(options, s, total)), s.dir);
  }
  makeOutputFolder(out_);
  reportContact(out, out_, heading, all);
  return plots_ ? plotContact(out, out_) : kExitOk;
}

int MergeCommand::slip(std::ostream& out, const std::vector<ShardInput>& shards) const {
  const nlohmann::json& options = shards.front().manifest.at("options");
  const int scenarios = static_cast<int>(options.at("scenarios").size());
  requireAll(shards, scenarios + 1, "item");
  SlipRows all;
  for (const ShardInput& s : shards) {
    appendSlipRows(all,
                   readSlipRows(fs::path(s.dir) / kStudyRows, blockNames(options, s, scenarios),
                                s.block.end == scenarios + 1),
                   s.dir);
  }
  makeOutputFolder(out_);
  reportSlip(out, out_,
             {options.at("seed").get<unsigned>(), options.at("duration").get<double>(),
              options.at("contact").get<std::string>()},
             all);
  return plots_ ? plotSlip(out, out_) : kExitOk;
}

int MergeCommand::faults(std::ostream& out, const std::vector<ShardInput>& shards) const {
  const nlohmann::json& options = shards.front().manifest.at("options");
  const auto cases = options.at("cases").get<std::vector<std::string>>();
  requireAll(shards, static_cast<int>(cases.size()), "case");
  std::vector<FaultCaseResult> rows;
  for (const ShardInput& s : shards) {
    const std::string where = s.dir + "/" + kShardManifest;
    const std::vector<FaultCaseResult> part = faultRowsFromJson(
        s.manifest.contains("rows") ? s.manifest.at("rows") : nlohmann::json(), where);
    if (static_cast<int>(part.size()) != s.block.end - s.block.begin) {
      throw InputError(where + ": " + std::to_string(part.size()) + " cases, its block has " +
                       std::to_string(s.block.end - s.block.begin) + "; nothing merged");
    }
    for (std::size_t k = 0; k < part.size(); ++k) {
      if (part[k].name != cases.at(s.block.begin + k)) {
        throw InputError(where + ": case '" + part[k].name + "' where '" +
                         cases.at(s.block.begin + k) + "' was expected; nothing merged");
      }
    }
    rows.insert(rows.end(), part.begin(), part.end());
  }
  makeOutputFolder(out_);  // the study writes no files: the merged folder stays empty
  reportFaults(out,
               {options.at("filter").get<std::string>(), options.at("duration").get<double>(),
                options.at("seed").get<unsigned>()},
               rows);
  return kExitOk;
}

}  // namespace legkit::tools
