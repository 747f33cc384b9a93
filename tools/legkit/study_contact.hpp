// `legkit study contact` and `legkit study slip` (sections 57.6 and 57.7), on physics logs whose
// true contact and slip (gt_feet) score what the kit detects.
//   legkit study contact   every contact detector on every physics scenario: precision, recall,
//                          F1, touchdown and lift-off delays, chatter (eval/contact_scores.hpp)
//   legkit study slip      the slip detector on the ice scenarios and the dry trot: detection
//                          delay, false alarms, and every filter with each slip reaction; every
//                          filter on true versus detected contacts
// Each writes its tables (CSV) and the data of its figures into an output folder and draws the
// figures with tools/plots/57.6-contact.py and 57.7-slip.py. Both take --shard i/N: contact a
// block of its scenarios, slip a block of its scenarios and the contact-source comparison after
// them; `legkit merge` makes the tables from the shards' rows (contact_report.hpp).
#pragma once

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace legkit::tools {

class StudyContact {
 public:
  // Adds the subcommands `contact` and `slip` to `study`.
  explicit StudyContact(CLI::App& study);
  StudyContact(const StudyContact&) = delete;  // the options are bound to this object's members
  StudyContact& operator=(const StudyContact&) = delete;

  bool parsed() const { return static_cast<bool>(*contact_) || static_cast<bool>(*slip_); }
  int run(std::ostream& out) const;

 private:
  int contact(std::ostream& out) const;
  int slip(std::ostream& out) const;

  CLI::App* contact_;
  CLI::App* slip_;
  unsigned seed_ = 1;
  double duration_ = 0;  // 0: the study's own default [s]
  std::string out_dir_;
  bool plots_ = true;
  std::string filter_ = "invariant-ekf";     // the estimator whose estimate the detectors see
  std::string contact_source_ = "fallback";  // slip study: where its filters' contacts come from
  std::vector<std::string> scenarios_;       // empty: the study's own list
  std::vector<std::string> filters_;         // slip study; empty: every filter
  std::string shard_ = "1/1";                // `--shard i/N` (shard.hpp)
};

}  // namespace legkit::tools
