// `legkit study contact`'s and `legkit study slip`'s results from their per-scenario rows (57.6,
// 57.7): what each study prints and writes (contact.csv, contact-trace.csv; slip.csv,
// slip-sources.csv, slip-terrain.csv, slip-trace.csv), made by one function for the
// single-machine study and for `legkit merge` of its shards (shard.hpp), and the rows a shard
// writes (rows.csv, every number with every bit) and the merge reads.
//
// The items a shard takes: contact's scenarios; slip's scenarios and, as the last item, the
// comparison of every filter on true against detected contacts (its own physics-trot run). Each
// item is one physics run and what is run on it, whatever the other items; the logistic model
// every shard trains is seeded by --seed alone (eval/contact_training.hpp).
#pragma once

#include <cmath>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "eval/contact_scores.hpp"
#include "shard.hpp"

namespace legkit::tools {

// The foot of the figures' traces: FR, the foot over the ice patch.
inline constexpr int kContactTraceFoot = 1;
inline constexpr const char* kContactLegs[4] = {"FL", "FR", "RL", "RR"};

// A scenario's run as the tables label it: its name, and when the robot fell.
struct ScenarioRun {
  std::string name;
  bool fell = false;
  double fell_time = 0.0;  // [s], when fell
};
// "<name>", or "<name> (fell at <t> s)".
std::string scenarioLabel(const ScenarioRun& run);

// ---- study contact -------------------------------------------------------------------------

// What the heading and the trace's header say: the run's options.
struct ContactHeading {
  unsigned seed = 1;
  double duration = 0.0;
  std::string filter;
  double f_high = 0.0, f_low = 0.0;  // the Schmitt trigger's thresholds [N]
};

// One detector on one scenario.
struct ContactDetectorRow {
  eval::ContactScores scores;
  double undecided_percent = 0.0;
  double position_rmse = 0.0, velocity_rmse = 0.0;
};

// One scenario: its run, each detector's row (in ContactRows::detectors' order) and, for the
// traced scenario (physics-trot), the trace of foot kContactTraceFoot over its window.
struct ContactScenario {
  ScenarioRun run;
  std::vector<ContactDetectorRow> rows;
  bool traced = false;
  std::vector<double> trace_t, trace_force, trace_fn, trace_truth;
  std::vector<std::vector<double>> trace_detected;  // per detector, per trace row
};

struct ContactRows {
  std::vector<std::string> detectors;
  std::vector<ContactScenario> scenarios;  // the shard's block, or all of them
};

// The rows with every bit (%.17g): "detectors,<names>", then per scenario
// "scenario,<name>,<fell>,<fell time>", a "score,<detector>,<16 numbers>" per detector and, when
// traced, "trace,<t>,<force>,<gt_fn>,<gt_contact>,<each detector's contact>" per trace row; last
// "end,<scenarios>".
void writeContactRows(std::ostream& out, const ContactRows& rows);
// Reads what writeContactRows wrote, expecting the scenarios `names` (the shard's block);
// InputError naming the file and line otherwise (a truncated file among them).
ContactRows readContactRows(const std::filesystem::path& path,
                            const std::vector<std::string>& names);
// Appends the next shard's scenarios; InputError when its detectors differ.
void appendContactRows(ContactRows& all, const ContactRows& next, const std::string& where);

// The study's tables on `out`, dir/contact.csv and dir/contact-trace.csv.
void reportContact(std::ostream& out, const std::filesystem::path& dir,
                   const ContactHeading& heading, const ContactRows& rows);
// Draws the study's figures (tools/plots/57.6-contact.py) and says so; kExitInput when the
// script failed, else kExitOk.
int plotContact(std::ostream& out, const std::filesystem::path& dir);

// ---- study slip ----------------------------------------------------------------------------

// A true slip (57.7): the contact point slides faster than kSlipSpeed for at least kSlipHold.
inline constexpr double kSlipSpeed = 0.1;  // [m/s]
inline constexpr double kSlipHold = 0.02;  // [s]
// A detected slip onset belongs to a true slip within this margin of it [s].
inline constexpr double kSlipMargin = 0.05;
// A detected onset this close to a sample of a slide too short to be a true slip is not false.
inline constexpr double kShortSlide = 0.02;  // [s]

struct SlipScores {
  int slips = 0;            // true slips, all feet
  int detected = 0;         // of them, detected within their margin
  double delay_mean = NAN;  // first detection - true onset [ms]
  double delay_p95 = NAN;   // nearest rank [ms]
  // Detected onsets outside every true slip's margin, per minute: at a short slide (the foot's
  // slip speed above kSlipSpeed within kShortSlide of the onset, for less than kSlipHold), or
  // false (no such sample).
  double short_slides_per_min = 0.0;
  double false_alarms_per_min = 0.0;
};

struct SlipHeading {
  unsigned seed = 1;
  double duration = 0.0;
  std::string contact;  // where the filters' contacts come from
};

// One filter with one slip reaction on one scenario.
struct SlipRun {
  std::string filter;
  std::string reaction;  // slip::slipReactionName
  double position_rmse = 0.0, velocity_rmse = 0.0;
  SlipScores scores;
};

// The terrain classifier at the end of a run (invariant-ekf, reaction none).
struct SlipTerrain {
  std::string terrain_class;
  double mu_hat = 0.0, mu_lower_bound = 0.0;
  int onsets = 0;
  double slip_rate = 0.0, slip_fraction = 0.0;
};

struct SlipTraceRow {
  double t = 0.0, mu = 0.0, slip_speed = 0.0, d2 = 0.0;
  bool slipping = false;
};

struct SlipScenario {
  ScenarioRun run;
  std::vector<double> friction;  // the ground's, then each patch's
  std::vector<SlipRun> runs;     // per filter, per reaction (none first)
  std::optional<SlipTerrain> terrain;
  // physics-ice with invariant-ekf, reaction none: foot kContactTraceFoot's slip check per row.
  bool traced = false;
  double threshold = 0.0;
  std::vector<SlipTraceRow> trace;
};

// Every filter on the dry trot, contacts from each source (no slip reaction).
struct SlipSources {
  double duration = 0.0;  // of the physics-trot run [s]
  std::vector<std::string> sources;
  // Per filter (SlipRows::filters' order), per source: position and velocity RMSE.
  std::vector<std::vector<std::pair<double, double>>> rmse;
};

struct SlipRows {
  std::vector<std::string> filters;
  std::vector<std::string> reactions;
  std::vector<SlipScenario> scenarios;
  std::optional<SlipSources> sources;  // the last item
};

// The rows with every bit (%.17g): "filters,..." and "reactions,...", then per scenario
// "scenario,<name>,<fell>,<fell time>,<frictions>" with its "run,...", "terrain,..." and
// "trace,..." lines, then "sources,..." and its "source,..." lines when the shard has the last
// item; last "end,<items>".
void writeSlipRows(std::ostream& out, const SlipRows& rows);
// Reads what writeSlipRows wrote, expecting the scenarios `names` and the sources when
// `sources`; InputError naming the file and line otherwise (a truncated file among them).
SlipRows readSlipRows(const std::filesystem::path& path, const std::vector<std::string>& names,
                      bool sources);
// Appends the next shard's items; InputError when its filters or reactions differ.
void appendSlipRows(SlipRows& all, const SlipRows& next, const std::string& where);

// The study's tables on `out` and dir/slip.csv, slip-sources.csv, slip-terrain.csv,
// slip-trace.csv.
void reportSlip(std::ostream& out, const std::filesystem::path& dir, const SlipHeading& heading,
                const SlipRows& rows);
// Draws the study's figure (tools/plots/57.7-slip.py) and says so; kExitInput when the script
// failed, else kExitOk.
int plotSlip(std::ostream& out, const std::filesystem::path& dir);

}  // namespace legkit::tools
