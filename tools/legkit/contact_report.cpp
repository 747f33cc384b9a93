#include "contact_report.hpp"

#include <algorithm>
#include <array>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

#include "output.hpp"

namespace legkit::tools {
namespace {

constexpr double kNaN = NAN;

std::ostringstream newCsv() {
  std::ostringstream csv;
  csv << std::setprecision(8);
  return csv;
}

// A shard's rows file, line by line, each split at its commas; InputError naming file and line.
class RowsFile {
 public:
  explicit RowsFile(const std::filesystem::path& path) : path_(path), in_(path) {
    if (!in_) throw InputError(path.string() + ": cannot be read (the shard's per-item rows)");
  }
  // The next line's fields, or false at the end of the file.
  bool next() {
    std::string line;
    if (!std::getline(in_, line)) return false;
    ++number_;
    fields_ = splitCsv(line);
    return true;
  }
  const std::vector<std::string>& fields() const { return fields_; }
  const std::string& kind() const { return fields_.front(); }
  std::string where() const { return path_.string() + ":" + std::to_string(number_); }
  [[noreturn]] void fail(const std::string& what) const { throw InputError(where() + ": " + what); }
  // Requires `count` fields after the kind.
  void expect(const std::string& kind, std::size_t count) const {
    if (fields_.front() != kind || fields_.size() != count + 1) {
      fail("expected '" + kind + ",' and " + std::to_string(count) + " fields, got '" +
           fields_.front() + "' and " + std::to_string(fields_.size() - 1));
    }
  }
  double number(std::size_t i) const {
    return parseExact(fields_.at(i), where() + ": field " + std::to_string(i + 1));
  }
  int whole(std::size_t i) const {
    const double value = number(i);
    if (value != static_cast<int>(value)) {
      fail("field " + std::to_string(i + 1) + ": '" + fields_.at(i) + "' is not a whole number");
    }
    return static_cast<int>(value);
  }
  bool flag(std::size_t i) const {
    const int value = whole(i);
    if (value != 0 && value != 1) fail("field " + std::to_string(i + 1) + " is not 0 or 1");
    return value == 1;
  }
  const std::string& text(std::size_t i) const { return fields_.at(i); }
  // Requires the next line, else "truncated" naming what was expected.
  void require(const std::string& what) {
    if (!next()) {
      throw InputError(path_.string() + ": ends after line " + std::to_string(number_) +
                       ", where " + what + " was expected (a truncated file?)");
    }
  }
  // The last line "end,<items>".
  void end(std::size_t items) {
    require("'end," + std::to_string(items) + "'");
    expect("end", 1);
    if (whole(1) != static_cast<int>(items)) fail("'end' counts another number of items");
    if (next()) fail("a line after 'end'");
  }

 private:
  std::filesystem::path path_;
  std::ifstream in_;
  int number_ = 0;
  std::vector<std::string> fields_;
};

std::vector<std::string> namesLine(RowsFile& in, const std::string& kind) {
  in.require("'" + kind + ",...'");
  if (in.kind() != kind || in.fields().size() < 2) in.fail("expected '" + kind + ",<names>'");
  return {in.fields().begin() + 1, in.fields().end()};
}

// The line read, "scenario,<name>,<fell>,<fell time>[,...]": the run, the rest left to the caller.
ScenarioRun scenarioLine(const RowsFile& in, const std::string& name, std::size_t count) {
  in.expect("scenario", count);
  if (in.text(1) != name)
    in.fail("scenario '" + in.text(1) + "' where '" + name + "' was expected");
  return {name, in.flag(2), in.number(3)};
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += "," + n;
  return s;
}

}  // namespace

std::string scenarioLabel(const ScenarioRun& run) {
  std::string label = run.name;
  if (run.fell) label += " (fell at " + formatFixed(run.fell_time, 2) + " s)";
  return label;
}

// ---- study contact -------------------------------------------------------------------------

void writeContactRows(std::ostream& out, const ContactRows& rows) {
  out << "detectors" << joined(rows.detectors) << '\n';
  for (const ContactScenario& s : rows.scenarios) {
    out << "scenario," << s.run.name << ',' << s.run.fell << ',' << exact(s.run.fell_time) << '\n';
    for (std::size_t d = 0; d < rows.detectors.size(); ++d) {
      const ContactDetectorRow& r = s.rows[d];
      const eval::ContactScores& c = r.scores;
      out << "score," << rows.detectors[d];
      for (const double x :
           {c.precision, c.recall, c.f1, c.touchdown_delay_mean, c.touchdown_delay_p95,
            c.liftoff_delay_mean, c.liftoff_delay_p95, c.chatter_per_min}) {
        out << ',' << exact(x);
      }
      out << ',' << c.touchdowns << ',' << c.liftoffs << ',' << c.missed_touchdowns << ','
          << c.missed_liftoffs << ',' << c.spurious_toggles << ',' << exact(r.undecided_percent)
          << ',' << exact(r.position_rmse) << ',' << exact(r.velocity_rmse) << '\n';
    }
    if (!s.traced) continue;
    for (std::size_t k = 0; k < s.trace_t.size(); ++k) {
      out << "trace," << exact(s.trace_t[k]) << ',' << exact(s.trace_force[k]) << ','
          << exact(s.trace_fn[k]) << ',' << exact(s.trace_truth[k]);
      for (const std::vector<double>& c : s.trace_detected) out << ',' << exact(c[k]);
      out << '\n';
    }
  }
  out << "end," << rows.scenarios.size() << '\n';
}

ContactRows readContactRows(const std::filesystem::path& path,
                            const std::vector<std::string>& names) {
  RowsFile in(path);
  ContactRows rows;
  rows.detectors = namesLine(in, "detectors");
  const std::size_t n = rows.detectors.size();
  bool pending = false;  // a line read ahead (the one after a scenario's trace)
  for (const std::string& name : names) {
    if (!pending) in.require("'scenario," + name + ",...'");
    pending = false;
    in.expect("scenario", 3);
    if (in.text(1) != name) {
      in.fail("scenario '" + in.text(1) + "' where '" + name + "' was expected");
    }
    ContactScenario s;
    s.run = {name, in.flag(2), in.number(3)};
    for (const std::string& detector : rows.detectors) {
      in.require("'score," + detector + ",...'");
      in.expect("score", 17);
      if (in.text(1) != detector) {
        in.fail("detector '" + in.text(1) + "' where '" + detector + "' was expected");
      }
      ContactDetectorRow r;
      eval::ContactScores& c = r.scores;
      c.precision = in.number(2);
      c.recall = in.number(3);
      c.f1 = in.number(4);
      c.touchdown_delay_mean = in.number(5);
      c.touchdown_delay_p95 = in.number(6);
      c.liftoff_delay_mean = in.number(7);
      c.liftoff_delay_p95 = in.number(8);
      c.chatter_per_min = in.number(9);
      c.touchdowns = in.whole(10);
      c.liftoffs = in.whole(11);
      c.missed_touchdowns = in.whole(12);
      c.missed_liftoffs = in.whole(13);
      c.spurious_toggles = in.whole(14);
      r.undecided_percent = in.number(15);
      r.position_rmse = in.number(16);
      r.velocity_rmse = in.number(17);
      s.rows.push_back(r);
    }
    s.trace_detected.resize(n);
    while (in.next()) {
      if (in.kind() != "trace") {
        pending = true;
        break;
      }
      in.expect("trace", 4 + n);
      s.traced = true;
      s.trace_t.push_back(in.number(1));
      s.trace_force.push_back(in.number(2));
      s.trace_fn.push_back(in.number(3));
      s.trace_truth.push_back(in.number(4));
      for (std::size_t d = 0; d < n; ++d) s.trace_detected[d].push_back(in.number(5 + d));
    }
    if (!s.traced) s.trace_detected.clear();
    rows.scenarios.push_back(std::move(s));
  }
  if (!pending) in.require("'end," + std::to_string(names.size()) + "'");
  in.expect("end", 1);
  if (in.whole(1) != static_cast<int>(names.size())) in.fail("'end' counts other scenarios");
  if (in.next()) in.fail("a line after 'end'");
  return rows;
}

void appendContactRows(ContactRows& all, const ContactRows& next, const std::string& where) {
  if (all.detectors.empty()) {
    all = next;
    return;
  }
  if (next.detectors != all.detectors) throw InputError(where + ": other detectors than shard 1's");
  all.scenarios.insert(all.scenarios.end(), next.scenarios.begin(), next.scenarios.end());
}

void reportContact(std::ostream& out, const std::filesystem::path& dir,
                   const ContactHeading& heading, const ContactRows& rows) {
  const std::vector<std::string>& detectors = rows.detectors;
  std::ostringstream csv = newCsv(), trace = newCsv();
  csv << "# seed " << heading.seed << " duration " << heading.duration << " filter "
      << heading.filter << '\n'
      << "scenario,detector,fell,precision,recall,f1,touchdown_delay_mean_ms,"
         "touchdown_delay_p95_ms,liftoff_delay_mean_ms,liftoff_delay_p95_ms,chatter_per_min,"
         "touchdowns,liftoffs,missed_touchdowns,missed_liftoffs,spurious_toggles,"
         "undecided_percent,position_rmse,velocity_rmse\n";
  std::vector<std::vector<std::string>> table = {
      {"scenario", "detector", "precision", "recall", "F1", "TD delay", "TD p95", "LO delay",
       "LO p95", "chatter", "undecided", "pos RMSE"},
      {"", "", "", "", "", "[ms]", "[ms]", "[ms]", "[ms]", "[1/min]", "[%]", "[m]"}};
  // Per detector over the scenarios: sums of F1, touchdown delay, lift-off delay, chatter.
  std::map<std::string, std::array<double, 4>> sums;
  std::map<std::string, std::array<int, 4>> counts;
  trace << "# physics-trot foot " << kContactLegs[kContactTraceFoot] << " f_high " << heading.f_high
        << " f_low " << heading.f_low << '\n';
  std::vector<std::vector<double>> trace_columns;  // per detector: contact, per row
  std::vector<double> trace_t, trace_force, trace_fn, trace_truth;

  for (const ContactScenario& sc : rows.scenarios) {
    const std::string& name = sc.run.name;
    if (sc.traced) {
      trace_t.insert(trace_t.end(), sc.trace_t.begin(), sc.trace_t.end());
      trace_force.insert(trace_force.end(), sc.trace_force.begin(), sc.trace_force.end());
      trace_fn.insert(trace_fn.end(), sc.trace_fn.begin(), sc.trace_fn.end());
      trace_truth.insert(trace_truth.end(), sc.trace_truth.begin(), sc.trace_truth.end());
      trace_columns.insert(trace_columns.end(), sc.trace_detected.begin(), sc.trace_detected.end());
    }
    for (std::size_t d = 0; d < detectors.size(); ++d) {
      const std::string& detector = detectors[d];
      const eval::ContactScores& s = sc.rows[d].scores;
      const double undecided = sc.rows[d].undecided_percent;
      const double position_rmse = sc.rows[d].position_rmse;
      const double velocity_rmse = sc.rows[d].velocity_rmse;
      csv << name << ',' << detector << ',' << sc.run.fell << ',' << s.precision << ',' << s.recall
          << ',' << s.f1 << ',' << s.touchdown_delay_mean << ',' << s.touchdown_delay_p95 << ','
          << s.liftoff_delay_mean << ',' << s.liftoff_delay_p95 << ',' << s.chatter_per_min << ','
          << s.touchdowns << ',' << s.liftoffs << ',' << s.missed_touchdowns << ','
          << s.missed_liftoffs << ',' << s.spurious_toggles << ',' << undecided << ','
          << position_rmse << ',' << velocity_rmse << '\n';
      table.push_back({d == 0 ? scenarioLabel(sc.run) : "", detector, formatFixed(s.precision, 3),
                       formatFixed(s.recall, 3), formatFixed(s.f1, 3),
                       formatFixed(s.touchdown_delay_mean, 1),
                       formatFixed(s.touchdown_delay_p95, 1), formatFixed(s.liftoff_delay_mean, 1),
                       formatFixed(s.liftoff_delay_p95, 1), formatFixed(s.chatter_per_min, 1),
                       formatFixed(undecided, 1), formatFixed(position_rmse, 3)});
      const std::array<double, 4> values = {s.f1, s.touchdown_delay_mean, s.liftoff_delay_mean,
                                            s.chatter_per_min};
      for (int j = 0; j < 4; ++j) {
        if (std::isnan(values[j])) continue;
        sums[detector][j] += values[j];
        ++counts[detector][j];
      }
    }
  }

  trace << "t,force,gt_fn,gt_contact";
  for (const std::string& d : detectors) trace << ',' << d;
  trace << '\n';
  for (std::size_t k = 0; k < trace_t.size(); ++k) {
    trace << trace_t[k] << ',' << trace_force[k] << ',' << trace_fn[k] << ',' << trace_truth[k];
    for (const std::vector<double>& c : trace_columns) trace << ',' << c[k];
    trace << '\n';
  }

  out << "Contact detectors against the physics' true contact (" << heading.duration
      << " s per scenario, seed " << heading.seed << "; each detector sees the estimate of "
      << heading.filter
      << " running on its own contacts; TD touchdown, LO lift-off: delay of the detected toggle "
         "matched within +-100 ms, mean and 95th percentile; chatter: detected toggles matching "
         "no true one; undecided: samples where the detector could not answer)\n\n";
  printTable(out, table);
  out << "\nPer detector, mean over the scenarios:\n\n";
  std::vector<std::vector<std::string>> summary = {
      {"detector", "F1", "TD delay [ms]", "LO delay [ms]", "chatter [1/min]"}};
  for (const std::string& d : detectors) {
    summary.push_back({d});
    for (int j = 0; j < 4; ++j) {
      summary.back().push_back(
          formatFixed(counts[d][j] ? sums[d][j] / counts[d][j] : kNaN, j == 0 ? 3 : 1));
    }
  }
  printTable(out, summary);
  writeAtomically(dir / "contact.csv", [&](std::ostream& f) { f << csv.str(); });
  writeAtomically(dir / "contact-trace.csv", [&](std::ostream& f) { f << trace.str(); });
  out << "tables: " << (dir / "contact.csv").string() << ", "
      << (dir / "contact-trace.csv").string() << '\n';
}

int plotContact(std::ostream& out, const std::filesystem::path& dir) {
  const std::string failed = plot("57.6-contact.py", {dir.string()});
  out << (failed.empty() ? "figures: " + (dir / "57.6-contact-trace.png").string() + ", " +
                               (dir / "57.6-contact-f1-delay.png").string()
                         : failed)
      << '\n';
  return plotFailed(failed) ? kExitInput : kExitOk;
}

// ---- study slip ----------------------------------------------------------------------------

void writeSlipRows(std::ostream& out, const SlipRows& rows) {
  out << "filters" << joined(rows.filters) << "\nreactions" << joined(rows.reactions) << '\n';
  for (const SlipScenario& s : rows.scenarios) {
    out << "scenario," << s.run.name << ',' << s.run.fell << ',' << exact(s.run.fell_time) << ','
        << s.friction.size();
    for (const double mu : s.friction) out << ',' << exact(mu);
    out << '\n';
    for (const SlipRun& r : s.runs) {
      const SlipScores& c = r.scores;
      out << "run," << r.filter << ',' << r.reaction << ',' << exact(r.position_rmse) << ','
          << exact(r.velocity_rmse) << ',' << c.slips << ',' << c.detected << ','
          << exact(c.delay_mean) << ',' << exact(c.delay_p95) << ','
          << exact(c.short_slides_per_min) << ',' << exact(c.false_alarms_per_min) << '\n';
    }
    if (s.terrain) {
      const SlipTerrain& t = *s.terrain;
      out << "terrain," << t.terrain_class << ',' << exact(t.mu_hat) << ','
          << exact(t.mu_lower_bound) << ',' << t.onsets << ',' << exact(t.slip_rate) << ','
          << exact(t.slip_fraction) << '\n';
    }
    if (s.traced) {
      out << "trace," << exact(s.threshold) << ',' << s.trace.size() << '\n';
      for (const SlipTraceRow& r : s.trace) {
        out << "tracerow," << exact(r.t) << ',' << exact(r.mu) << ',' << exact(r.slip_speed) << ','
            << exact(r.d2) << ',' << r.slipping << '\n';
      }
    }
  }
  std::size_t items = rows.scenarios.size();
  if (rows.sources) {
    ++items;
    const SlipSources& s = *rows.sources;
    out << "sources," << exact(s.duration) << joined(s.sources) << '\n';
    for (std::size_t f = 0; f < rows.filters.size(); ++f) {
      for (std::size_t i = 0; i < s.sources.size(); ++i) {
        out << "source," << s.sources[i] << ',' << rows.filters[f] << ','
            << exact(s.rmse[f][i].first) << ',' << exact(s.rmse[f][i].second) << '\n';
      }
    }
  }
  out << "end," << items << '\n';
}

SlipRows readSlipRows(const std::filesystem::path& path, const std::vector<std::string>& names,
                      bool sources) {
  RowsFile in(path);
  SlipRows rows;
  rows.filters = namesLine(in, "filters");
  rows.reactions = namesLine(in, "reactions");
  for (const std::string& name : names) {
    in.require("'scenario," + name + ",...'");
    if (in.kind() != "scenario" || in.fields().size() < 5) {
      in.fail("expected 'scenario," + name + ",<fell>,<fell time>,<frictions>...'");
    }
    const int frictions = in.whole(4);
    if (frictions < 1 || static_cast<std::size_t>(frictions) + 5 != in.fields().size()) {
      in.fail("field 5: " + in.text(4) + " frictions, the line has another number");
    }
    SlipScenario s;
    s.run = scenarioLine(in, name, 4 + frictions);
    for (int i = 0; i < frictions; ++i) s.friction.push_back(in.number(5 + i));
    for (const std::string& filter : rows.filters) {
      for (const std::string& reaction : rows.reactions) {
        in.require("'run," + filter + "," + reaction + ",...'");
        in.expect("run", 10);
        if (in.text(1) != filter || in.text(2) != reaction) {
          in.fail("run of " + in.text(1) + ", " + in.text(2) + " where " + filter + ", " +
                  reaction + " was expected");
        }
        SlipRun r{filter, reaction, in.number(3), in.number(4), {}};
        r.scores = {in.whole(5),  in.whole(6),  in.number(7),
                    in.number(8), in.number(9), in.number(10)};
        s.runs.push_back(r);
      }
    }
    // The terrain classifier watched invariant-ekf without a reaction; physics-ice's is traced.
    if (std::find(rows.filters.begin(), rows.filters.end(), "invariant-ekf") !=
        rows.filters.end()) {
      in.require("'terrain,...'");
      in.expect("terrain", 6);
      s.terrain = SlipTerrain{in.text(1),  in.number(2), in.number(3),
                              in.whole(4), in.number(5), in.number(6)};
      if (name == "physics-ice") {
        in.require("'trace,...'");
        in.expect("trace", 2);
        s.traced = true;
        s.threshold = in.number(1);
        const int count = in.whole(2);
        for (int k = 0; k < count; ++k) {
          in.require("'tracerow,...'");
          in.expect("tracerow", 5);
          s.trace.push_back({in.number(1), in.number(2), in.number(3), in.number(4), in.flag(5)});
        }
      }
    }
    rows.scenarios.push_back(std::move(s));
  }
  if (sources) {
    in.require("'sources,...'");
    if (in.kind() != "sources" || in.fields().size() < 3) {
      in.fail("expected 'sources,<duration>,<sources>'");
    }
    SlipSources s;
    s.duration = in.number(1);
    s.sources.assign(in.fields().begin() + 2, in.fields().end());
    for (const std::string& filter : rows.filters) {
      s.rmse.emplace_back();
      for (const std::string& source : s.sources) {
        in.require("'source," + source + "," + filter + ",...'");
        in.expect("source", 4);
        if (in.text(1) != source || in.text(2) != filter) {
          in.fail("source " + in.text(1) + ", " + in.text(2) + " where " + source + ", " + filter +
                  " was expected");
        }
        s.rmse.back().emplace_back(in.number(3), in.number(4));
      }
    }
    rows.sources = std::move(s);
  }
  in.end(names.size() + (sources ? 1 : 0));
  return rows;
}

void appendSlipRows(SlipRows& all, const SlipRows& next, const std::string& where) {
  if (all.filters.empty()) {
    all = next;
    return;
  }
  if (next.filters != all.filters) throw InputError(where + ": other filters than shard 1's");
  if (next.reactions != all.reactions) throw InputError(where + ": other reactions than shard 1's");
  if (all.sources) throw InputError(where + ": items after the last one");
  all.scenarios.insert(all.scenarios.end(), next.scenarios.begin(), next.scenarios.end());
  all.sources = next.sources;
}

void reportSlip(std::ostream& out, const std::filesystem::path& dir, const SlipHeading& heading,
                const SlipRows& rows) {
  const std::vector<std::string>& filters = rows.filters;
  std::ostringstream csv = newCsv(), trace = newCsv();
  csv << "# seed " << heading.seed << " duration " << heading.duration << " contact "
      << heading.contact << '\n'
      << "scenario,filter,reaction,position_rmse,velocity_rmse,slips,detected,delay_mean_ms,"
         "delay_p95_ms,short_slides_per_min,false_alarms_per_min\n";
  std::vector<std::vector<std::string>> detection = {
      {"scenario", "filter", "true slips", "detected", "delay [ms]", "p95 [ms]",
       "at short slides [1/min]", "false alarms [1/min]"}};
  std::vector<std::vector<std::string>> accuracy = {
      {"scenario", "filter", "pos RMSE [m]:", "", "", "", "vel RMSE [m/s]:", "", "", ""},
      {"", "", "none", "inflate", "drop", "imu-only", "none", "inflate", "drop", "imu-only"}};
  std::ostringstream terrain_csv = newCsv();
  terrain_csv << "# seed " << heading.seed << " duration " << heading.duration << " contact "
              << heading.contact << " filter invariant-ekf\n"
              << "scenario,true_mu,class,mu_hat,mu_lower_bound,onsets,slip_rate,slip_fraction\n";
  std::vector<std::vector<std::string>> terrain_table = {{"scenario", "true mu", "class", "mu_hat",
                                                          "mu lower bound", "onsets",
                                                          "slip rate [1/s]", "slipping [%]"}};
  for (const SlipScenario& sc : rows.scenarios) {
    const std::string& name = sc.run.name;
    const std::string label = scenarioLabel(sc.run);
    std::size_t at = 0;  // the next of sc.runs
    for (const std::string& f : filters) {
      std::vector<std::string> row = {f == filters.front() ? label : "", f};
      std::vector<std::string> velocity;
      for (std::size_t reaction = 0; reaction < rows.reactions.size(); ++reaction) {
        const SlipRun& r = sc.runs.at(at++);
        const bool watched = reaction == 0 && f == "invariant-ekf";
        if (watched && sc.terrain) {
          const SlipTerrain& c = *sc.terrain;
          std::string mu = formatFixed(sc.friction.front(), 2);
          for (std::size_t p = 1; p < sc.friction.size(); ++p) {
            mu += " (" + formatFixed(sc.friction[p], 2) + " patch)";
          }
          terrain_csv << name << ',' << mu << ',' << c.terrain_class << ',' << c.mu_hat << ','
                      << c.mu_lower_bound << ',' << c.onsets << ',' << c.slip_rate << ','
                      << c.slip_fraction << '\n';
          terrain_table.push_back({label, mu, c.terrain_class, formatFixed(c.mu_hat, 3),
                                   formatFixed(c.mu_lower_bound, 3), std::to_string(c.onsets),
                                   formatFixed(c.slip_rate, 2),
                                   formatFixed(100.0 * c.slip_fraction, 1)});
        }
        const SlipScores& s = r.scores;
        csv << name << ',' << f << ',' << r.reaction << ',' << r.position_rmse << ','
            << r.velocity_rmse << ',' << s.slips << ',' << s.detected << ',' << s.delay_mean << ','
            << s.delay_p95 << ',' << s.short_slides_per_min << ',' << s.false_alarms_per_min
            << '\n';
        row.push_back(formatFixed(r.position_rmse, 3));
        velocity.push_back(formatFixed(r.velocity_rmse, 3));
        if (reaction != 0) continue;
        // Detection is scored without a reaction: what the detector sees of an untouched filter.
        detection.push_back({f == filters.front() ? label : "", f, std::to_string(s.slips),
                             std::to_string(s.detected), formatFixed(s.delay_mean, 1),
                             formatFixed(s.delay_p95, 1), formatFixed(s.short_slides_per_min, 1),
                             formatFixed(s.false_alarms_per_min, 1)});
        if (watched && sc.traced) {
          trace << "# physics-ice foot " << kContactLegs[kContactTraceFoot] << " filter " << f
                << " threshold " << sc.threshold << '\n'
                << "t,mu,slip_speed,d2,slipping\n";
          for (const SlipTraceRow& t : sc.trace) {
            trace << t.t << ',' << t.mu << ',' << t.slip_speed << ',' << t.d2 << ',' << t.slipping
                  << '\n';
          }
        }
      }
      row.insert(row.end(), velocity.begin(), velocity.end());
      accuracy.push_back(row);
    }
  }

  // Every filter on the dry trot, true contacts against detected ones (no slip reaction).
  const SlipSources& sources = rows.sources.value();
  std::vector<std::vector<std::string>> sources_table = {{"filter"}, {""}};
  for (const std::string& s : sources.sources) {
    sources_table[0].push_back(s);
    sources_table[1].push_back("pos [m], vel [m/s]");
  }
  std::ostringstream sources_csv = newCsv();
  sources_csv << "# physics-trot seed " << heading.seed << " duration " << sources.duration << '\n'
              << "source,filter,position_rmse,velocity_rmse\n";
  for (std::size_t f = 0; f < filters.size(); ++f) {
    sources_table.push_back({filters[f]});
    for (std::size_t i = 0; i < sources.sources.size(); ++i) {
      const auto [position_rmse, velocity_rmse] = sources.rmse[f][i];
      sources_csv << sources.sources[i] << ',' << filters[f] << ',' << position_rmse << ','
                  << velocity_rmse << '\n';
      sources_table.back().push_back(formatFixed(position_rmse, 3) + ", " +
                                     formatFixed(velocity_rmse, 3));
    }
  }

  out << "Slip detection (" << heading.duration << " s per scenario, seed " << heading.seed
      << ", contacts from " << heading.contact << "; a true slip: the contact point slides faster "
      << "than " << kSlipSpeed << " m/s for " << 1e3 * kSlipHold << " ms or more; delay: first "
      << "detection within " << 1e3 * kSlipMargin << " ms of it; other detected onsets are at a "
      << "short slide when the foot slid faster than " << kSlipSpeed << " m/s within "
      << 1e3 * kShortSlide << " ms of it, else false alarms; scored with the reaction 'none')\n\n";
  printTable(out, detection);
  out << "\nEvery filter with each slip reaction:\n\n";
  printTable(out, accuracy);
  out << "\nTerrain classes at the end of each run (invariant-ekf, reaction none; forces from the "
         "joint torques: a ratio counts 30 ms into a loaded stance, a slip onset once its slip has "
         "held 5 ms; slip rate per second and share of stance foot-time slipping):\n\n";
  printTable(out, terrain_table);
  out << "\nEvery filter on physics-trot, true against detected contacts (no slip reaction):\n\n";
  printTable(out, sources_table);
  writeAtomically(dir / "slip.csv", [&](std::ostream& f) { f << csv.str(); });
  writeAtomically(dir / "slip-sources.csv", [&](std::ostream& f) { f << sources_csv.str(); });
  writeAtomically(dir / "slip-terrain.csv", [&](std::ostream& f) { f << terrain_csv.str(); });
  writeAtomically(dir / "slip-trace.csv", [&](std::ostream& f) { f << trace.str(); });
  out << "tables: " << (dir / "slip.csv").string() << ", " << (dir / "slip-sources.csv").string()
      << ", " << (dir / "slip-terrain.csv").string() << ", " << (dir / "slip-trace.csv").string()
      << '\n';
}

int plotSlip(std::ostream& out, const std::filesystem::path& dir) {
  const std::string failed = plot("57.7-slip.py", {dir.string()});
  out << (failed.empty() ? "figure: " + (dir / "57.7-slip.png").string() : failed) << '\n';
  return plotFailed(failed) ? kExitInput : kExitOk;
}

}  // namespace legkit::tools
