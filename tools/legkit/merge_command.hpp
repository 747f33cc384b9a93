// `legkit merge OUT SHARD_DIR...`: the shards of one sharded run (`legkit study consistency|
// convergence|sweep|contact|slip|faults --shard i/N`, `legkit eval --shard i/N`) combined into
// exactly what the single-machine run prints and writes, from their per-item rows through the same
// code (shard.hpp). Every shard must be there once and be of the same run (kind, options, seed,
// version): else an error naming the folders, exit 2, and nothing is written.
#pragma once

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace legkit::tools {

struct ShardInput;

class MergeCommand {
 public:
  explicit MergeCommand(CLI::App& app);
  MergeCommand(const MergeCommand&) = delete;  // the options are bound to this object's members
  MergeCommand& operator=(const MergeCommand&) = delete;

  bool parsed() const { return static_cast<bool>(*command_); }
  // The merged run's exit code; shards that cannot be merged throw InputError (exit 2).
  int run(std::ostream& out) const;

 private:
  // `study consistency` or `study convergence` (name).
  int study(std::ostream& out, const std::vector<ShardInput>& shards,
            const std::string& name) const;
  int eval(std::ostream& out, const std::vector<ShardInput>& shards) const;
  // `study contact`, `study slip` (contact_report.hpp) and `study faults` (faults_report.hpp).
  int contact(std::ostream& out, const std::vector<ShardInput>& shards) const;
  int slip(std::ostream& out, const std::vector<ShardInput>& shards) const;
  int faults(std::ostream& out, const std::vector<ShardInput>& shards) const;

  CLI::App* command_;
  std::string out_;
  std::vector<std::string> shards_;
  bool plots_ = true;
};

}  // namespace legkit::tools
