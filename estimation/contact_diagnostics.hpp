// Per-foot contact diagnostics of a run (issue 22 item 7), kept by ContactPipeline: for each foot,
// which source decided it how often (the detectors of a fallback chain, the one detector, or the
// log's flags for "truth"), how often the deciding source changed and which problem most often
// handed the foot on, its stance share, touchdowns, samples held back by touchdown settling and
// samples found slipping. Counters in fixed arrays: ContactPipeline::step() keeps them without
// allocating.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "estimation/contact/contact_detector.hpp"
#include "estimation/contact/fallback_detector.hpp"

namespace legkit {

// The distinct problem strings counted per foot; a further distinct one counts in other_problems.
// A capacity, not a tuning: a foot is handed down the chain by at most a few kinds of problem in
// one run (the force sensor's: missing, negative, saturated, stuck; the momentum observer's
// settling; the kinematic detector's missing base or kinematics). On every physics scenario and
// the iCub log none was over (test_run_diagnostics_cli: one kind, "force negative"), and
// other_problems says when one is.
constexpr int kMaxProblemsPerFoot = 6;

struct FootContactDiagnostics {
  // decided[k]: samples on which source k (ContactDiagnostics::sources) decided the foot;
  // undecided: samples on which none could (a chain's last detector answered with its problem).
  // sum(decided) + undecided = ContactDiagnostics::samples.
  std::array<long, contact::kMaxChain> decided{};
  long undecided = 0;
  // Samples whose deciding source (a detector, or none) differs from the previous sample's.
  long handovers = 0;
  // Those of them that went down the chain (to a later detector, or to none): the previous
  // source had a problem, counted in `problems` below.
  long handovers_down = 0;
  long stance = 0;      // samples the source put the foot down (a usable "contact" answer)
  long touchdowns = 0;  // put down, after the run's first row
  long settled = 0;     // samples it reached the filter at p_c = 0 (touchdown settling)
  long slipping = 0;    // samples the slip check found it slipping
  // The problems that handed the foot down the chain (static strings, FootContact::problem), the
  // first kMaxProblemsPerFoot distinct ones with their counts.
  std::array<const char*, kMaxProblemsPerFoot> problems{};
  std::array<long, kMaxProblemsPerFoot> problem_counts{};
  long other_problems = 0;

  void countProblem(const char* problem) {
    for (int k = 0; k < kMaxProblemsPerFoot; ++k) {
      if (problems[k] == nullptr) problems[k] = problem;
      if (problems[k] == problem || std::string_view(problems[k]) == problem) {
        ++problem_counts[k];
        return;
      }
    }
    ++other_problems;
  }
  // The most frequent of `problems` (the first on a tie), nullptr when none.
  const char* topProblem() const {
    int best = -1;
    for (int k = 0; k < kMaxProblemsPerFoot && problems[k] != nullptr; ++k) {
      if (best < 0 || problem_counts[k] > problem_counts[best]) best = k;
    }
    return best < 0 ? nullptr : problems[best];
  }
  long topProblemCount() const {
    long best = 0;
    for (const long n : problem_counts) best = n > best ? n : best;
    return best;
  }
};

struct ContactDiagnostics {
  // The sources a foot can be decided by, in chain order: "truth", a detector's name, or the
  // detectors of a fallback chain.
  std::vector<std::string> sources;
  long samples = 0;  // rows stepped since reset()
  int num_feet = 0;
  std::array<FootContactDiagnostics, contact::kMaxFeet> feet{};
};

}  // namespace legkit
