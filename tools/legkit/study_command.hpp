// `legkit study`: the Monte Carlo studies that reproduce the chapter's claims, each writing its
// data (CSV) and its figure (PNG, drawn by tools/plots/study_plots.py) into an output folder.
//   legkit study consistency   ANEES of every filter over runs of the default trot, with the
//                              95 % chi-square bounds (section 57.5)
//   legkit study convergence   initial attitude error 0..90 degrees: converged or not and time
//                              to converge, linear KF, ESKF and InEKF (section 57.10)
//   legkit study sweep         the linear KF's noise parameters scaled over decades: accuracy
//                              and consistency, the bias-variance trade-off (exercise 57.4.2)
//   legkit study contact       the contact detectors against the physics' true contact (57.6)
//   legkit study slip          slip detection and reactions on ice (57.7), study_contact.hpp
//   legkit study faults        injected sensor faults, the monitors and their answers (57.9),
//                              study_faults.hpp
//   legkit study fusion        proprioception alone against the map-to-odom alignment, delayed
//                              pose updates and the fixed-lag smoother (57.8), study_fusion.hpp
// consistency, convergence and sweep take --shard i/N: a block of the runs, its per-run rows
// written for `legkit merge` (shard.hpp), which makes the study's table and files from them with
// the same code (consistency_report.hpp, convergence_report.hpp); contact and slip a block of
// their scenarios (contact_report.hpp), faults of its fault cases (faults_report.hpp). fusion is
// one run and refuses a --shard past 1/1 (study_fusion.cpp says why).
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

#include "shard.hpp"
#include "study_contact.hpp"
#include "study_faults.hpp"

namespace legkit::tools {

class StudyCommand {
 public:
  explicit StudyCommand(CLI::App& app);
  StudyCommand(const StudyCommand&) = delete;  // the options are bound to this object's members
  StudyCommand& operator=(const StudyCommand&) = delete;

  bool parsed() const { return static_cast<bool>(*command_); }
  int run(std::ostream& out) const;

 private:
  int consistency(std::ostream& out) const;
  int convergence(std::ostream& out) const;
  int sweep(std::ostream& out) const;
  // A shard's output (shard.hpp): its per-run rows (kStudyRows) and its manifest.
  struct ShardRun {
    int runs;
    double duration;
    Shard shard;
    Block block;
  };
  int writeShard(std::ostream& out, const std::string& study, const std::filesystem::path& dir,
                 const std::function<void(std::ostream&)>& rows, const ShardRun& run) const;
  // Draws a study's figure (when asked for); kExitInput when the script failed, else kExitOk.
  int plot(std::ostream& out, const std::string& study, const std::string& dir) const;

  CLI::App* command_;
  CLI::App* consistency_;
  CLI::App* convergence_;
  CLI::App* sweep_;
  int runs_ = 0;         // 0: the study's own default
  double duration_ = 0;  // 0: the study's own default [s]
  unsigned seed_ = 1;
  int threads_ = 0;
  std::string out_dir_;
  bool plots_ = true;
  bool correct_yaw_ = false;   // `study consistency --correct-yaw`: the plain filters (57.5)
  std::string shard_ = "1/1";  // `--shard i/N` of consistency and convergence (shard.hpp)
  StudyContact contact_;       // `study contact` and `study slip`
  StudyFaults faults_;         // `study faults` (57.9)
};

}  // namespace legkit::tools
