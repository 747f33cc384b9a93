// `legkit study faults` (section 57.9): the fault runs behind chapter 57.9's troubleshooting
// table. Each fault (eval/fault_injection.hpp) is written into a short physics trot and run with
// the health monitor, with its answers applied and without them; the table gives when each
// alarm was raised and the error against the truth. The same runs, with their bounds asserted,
// are tests/engineering/fault_injection_test.cpp. --shard i/N runs a block of the fault cases
// into --out; `legkit merge` makes the table from the shards (faults_report.hpp).
#pragma once

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>

namespace legkit::tools {

class StudyFaults {
 public:
  // Adds the subcommand `faults` to `study`.
  explicit StudyFaults(CLI::App& study);
  StudyFaults(const StudyFaults&) = delete;  // the options are bound to this object's members
  StudyFaults& operator=(const StudyFaults&) = delete;

  bool parsed() const { return static_cast<bool>(*faults_); }
  int run(std::ostream& out) const;

 private:
  CLI::App* faults_;
  unsigned seed_ = 7;
  std::string filter_ = "eskf";
  std::string shard_ = "1/1";  // `--shard i/N` (shard.hpp)
  std::string out_dir_;        // a shard's folder
};

}  // namespace legkit::tools
