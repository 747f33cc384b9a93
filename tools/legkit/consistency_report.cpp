#include "consistency_report.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "output.hpp"
#include "shard.hpp"

namespace legkit::tools {
namespace {

std::vector<double> numbers(const std::vector<std::string>& fields, std::size_t from,
                            const std::string& where) {
  std::vector<double> values;
  values.reserve(fields.size() - std::min(from, fields.size()));
  for (std::size_t i = from; i < fields.size(); ++i) {
    values.push_back(parseExact(fields[i], where + ": field " + std::to_string(i + 1)));
  }
  return values;
}

int wholeField(const std::string& field, const std::string& where) {
  const double value = parseExact(field, where);
  if (value != static_cast<int>(value)) {
    throw InputError(where + ": '" + field + "' is not a whole number");
  }
  return static_cast<int>(value);
}

}  // namespace

void writeMonteCarloRows(std::ostream& out, const MonteCarloRows& rows) {
  out << "t";
  for (const double t : rows.t) out << ',' << exact(t);
  out << "\nnames";
  for (const std::string& name : rows.names) out << ',' << name;
  out << '\n';
  const std::size_t count = rows.runs.empty() ? 0 : rows.runs.front().size();
  for (std::size_t j = 0; j < count; ++j) {
    for (std::size_t e = 0; e < rows.names.size(); ++e) {
      const eval::RunSummary& r = rows.runs[e][j];
      const std::vector<double>& extra = rows.extra[e][j];
      out << "run," << rows.first + static_cast<int>(j) << ',' << rows.names[e] << ',' << r.nees_dof
          << ',' << exact(r.metrics.position_rmse) << ',' << exact(r.metrics.velocity_rmse) << ','
          << exact(r.us_per_step) << ',' << extra.size();
      for (const double x : extra) out << ',' << exact(x);
      for (const double n : r.nees) out << ',' << exact(n);
      out << '\n';
    }
  }
}

MonteCarloRows readMonteCarloRows(const std::filesystem::path& path, const Block& block) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot be read (the shard's per-run rows)");
  MonteCarloRows rows;
  rows.first = block.begin;
  std::string line;
  int number = 0;
  std::size_t read = 0;  // run lines read
  while (std::getline(in, line)) {
    const std::string where = path.string() + ":" + std::to_string(++number);
    const std::vector<std::string> f = splitCsv(line);
    if (number == 1) {
      if (f.front() != "t") throw InputError(where + ": expected the times, 't,...'");
      rows.t = numbers(f, 1, where);
      continue;
    }
    if (number == 2) {
      if (f.front() != "names" || f.size() < 2) {
        throw InputError(where + ": expected the names, 'names,<name>,...'");
      }
      rows.names.assign(f.begin() + 1, f.end());
      rows.runs.resize(rows.names.size());
      rows.extra.resize(rows.names.size());
      continue;
    }
    if (f.size() < 8 || f[0] != "run") {
      throw InputError(where + ": expected 'run,<j>,<name>,<dof>,<position_rmse>,...'");
    }
    const std::size_t e = read % rows.names.size();
    const int expected = block.begin + static_cast<int>(read / rows.names.size());
    const int run = wholeField(f[1], where + ": field 2");
    if (run != expected || expected >= block.end) {
      throw InputError(
          where + ": run " + f[1] + " where " +
          (expected < block.end ? "run " + std::to_string(expected) : std::string("the end")) +
          " was expected (this shard holds runs " + std::to_string(block.begin) + ".." +
          std::to_string(block.end - 1) + ")");
    }
    if (f[2] != rows.names[e]) {
      throw InputError(where + ": '" + f[2] + "' where '" + rows.names[e] + "' was expected");
    }
    eval::RunSummary r;
    r.nees_dof = wholeField(f[3], where + ": field 4");
    r.metrics.position_rmse = parseExact(f[4], where + ": field 5");
    r.metrics.velocity_rmse = parseExact(f[5], where + ": field 6");
    r.us_per_step = parseExact(f[6], where + ": field 7");
    const int extras = wholeField(f[7], where + ": field 8");
    if (extras < 0 || static_cast<std::size_t>(extras) > f.size() - 8) {
      throw InputError(where + ": field 8: " + f[7] + " extra numbers, the line has fewer");
    }
    const std::vector<double> values = numbers(f, 8, where);
    rows.extra[e].emplace_back(values.begin(), values.begin() + extras);
    r.nees.assign(values.begin() + extras, values.end());
    if (!r.nees.empty() && r.nees.size() != rows.t.size()) {
      throw InputError(where + ": " + std::to_string(r.nees.size()) + " NEES values, " +
                       std::to_string(rows.t.size()) + " expected (one per row time)");
    }
    rows.runs[e].push_back(std::move(r));
    ++read;
  }
  const std::size_t expected_lines =
      rows.names.size() * static_cast<std::size_t>(block.end - block.begin);
  if (number < 2 || read != expected_lines) {
    throw InputError(path.string() + ": " + std::to_string(read) + " run lines, " +
                     std::to_string(expected_lines) + " expected for runs " +
                     std::to_string(block.begin) + ".." + std::to_string(block.end - 1) +
                     " (a truncated file?)");
  }
  return rows;
}

void appendMonteCarloRows(MonteCarloRows& all, const MonteCarloRows& next,
                          const std::string& where) {
  if (all.names.empty()) {
    all = next;
    return;
  }
  if (next.names != all.names) throw InputError(where + ": other names than shard 1's");
  if (next.t != all.t) throw InputError(where + ": other row times than shard 1's");
  for (std::size_t e = 0; e < all.names.size(); ++e) {
    all.runs[e].insert(all.runs[e].end(), next.runs[e].begin(), next.runs[e].end());
    all.extra[e].insert(all.extra[e].end(), next.extra[e].begin(), next.extra[e].end());
  }
}

void reportConsistency(std::ostream& out, const std::filesystem::path& dir,
                       const MonteCarloRows& rows, double duration, bool correct_yaw) {
  std::vector<eval::MonteCarloEstimate> result;
  for (std::size_t e = 0; e < rows.names.size(); ++e) {
    result.push_back(eval::reduceRuns(rows.names[e], rows.t, rows.runs[e]));
  }
  const std::size_t runs = rows.runs.empty() ? 0 : rows.runs.front().size();
  std::ostringstream csv;
  csv << std::setprecision(8);
  csv << "# runs " << runs << '\n' << "filter,dof,lower,upper,t,anees\n";
  const std::size_t every = 10;  // 100 Hz is plenty for the figure
  for (const eval::MonteCarloEstimate& r : result) {
    for (std::size_t k = 0; k < r.anees.size(); k += every) {
      csv << r.name << ',' << r.dof << ',' << r.bounds.lower << ',' << r.bounds.upper << ','
          << r.t[k] << ',' << r.anees[k] << '\n';
    }
  }

  out << "Consistency on the default trot: " << runs << " runs x " << duration
      << " s, initial errors and biases drawn from the filters' prior, "
      << (correct_yaw ? "plain filters (stance feet correct the heading)"
                      : "the heading rule (stance feet leave the heading to the gyro)")
      << "\n\n";
  std::vector<std::vector<std::string>> table = {{"filter", "dof", "ANEES/dof", "last 10 %",
                                                  "95 % bounds / dof", "inside [%]", "pos RMSE [m]",
                                                  "yaw RMSE [deg]"}};
  for (std::size_t e = 0; e < result.size(); ++e) {
    const eval::MonteCarloEstimate& r = result[e];
    double pos = 0.0, yaw = 0.0;
    for (const eval::Metrics& m : r.runs) pos += m.position_rmse / r.runs.size();
    for (const std::vector<double>& x : rows.extra[e]) {
      if (x.size() != 1)
        throw InputError("consistency rows of " + r.name + ": a run without its yaw RMSE");
      yaw += x[0] / rows.extra[e].size();
    }
    const std::size_t from = r.anees.size() - std::max<std::size_t>(1, r.anees.size() / 10);
    double late = 0.0;
    for (std::size_t k = from; k < r.anees.size(); ++k) late += r.anees[k];
    late /= static_cast<double>((r.anees.size() - from) * r.dof);
    table.push_back(
        {r.name, std::to_string(r.dof), formatFixed(r.mean_anees, 2), formatFixed(late, 2),
         "[" + formatFixed(r.bounds.lower / r.dof, 2) + ", " +
             formatFixed(r.bounds.upper / r.dof, 2) + "]",
         formatFixed(100.0 * r.fraction_inside, 1), formatFixed(pos, 3), formatFixed(yaw, 2)});
  }
  printTable(out, table);
  out << "\n(ANEES/dof: the mean over time of ANEES_k / dof; last 10 %: the same over the last "
         "tenth of the run; inside: the share of samples k whose ANEES_k lies inside the "
         "bounds)\n";
  writeAtomically(dir / "consistency.csv", [&](std::ostream& f) { f << csv.str(); });
}

double sweepScale(int i) {
  return std::pow(10.0, 0.5 * (i - 6));
}

std::string sweepSetting(int parameter, int i) {
  return std::string(kSweepParameters[parameter]) + " x " + formatFixed(sweepScale(i), 3);
}

void reportSweep(std::ostream& out, const std::filesystem::path& dir, const MonteCarloRows& rows,
                 double duration) {
  const double window = kSweepWindow;
  const int runs = rows.runs.empty() ? 0 : static_cast<int>(rows.runs.front().size());
  std::ostringstream csv;
  csv << std::setprecision(8);
  csv << "# runs " << runs << " duration " << duration << " window " << window << '\n'
      << "parameter,scale,position_rmse,velocity_rmse,velocity_bias,velocity_variance,anees\n";
  out << "Linear KF parameter sweep (" << runs << " runs x " << duration << " s of trot each; "
      << "velocity error split over a " << window << " s window)\n\n";
  std::vector<std::vector<std::string>> table = {{"parameter", "scale", "pos RMSE [m]",
                                                  "vel RMSE [m/s]", "vel bias [m/s]",
                                                  "vel variance [m2/s2]", "ANEES/dof"}};
  for (int p = 0; p < 3; ++p) {
    for (int i = 0; i < kSweepScales; ++i) {
      const std::size_t e = static_cast<std::size_t>(p * kSweepScales + i);
      const double scale = sweepScale(i);
      double pos = 0.0, vel = 0.0, bias2 = 0.0, variance = 0.0;
      for (int j = 0; j < runs; ++j) {  // in run order, whatever the threads or shards
        const eval::Metrics& m = rows.runs[e][j].metrics;
        pos += m.position_rmse / runs;
        vel += m.velocity_rmse / runs;
        const double bias = rows.extra[e][j].at(0);
        bias2 += bias * bias / runs;
        variance += rows.extra[e][j].at(1) / runs;
      }
      const double anees = eval::reduceRuns(rows.names[e], rows.t, rows.runs[e]).mean_anees;
      const double bias = std::sqrt(bias2);
      csv << kSweepParameters[p] << ',' << scale << ',' << pos << ',' << vel << ',' << bias << ','
          << variance << ',' << anees << '\n';
      table.push_back({kSweepParameters[p], formatFixed(scale, 3), formatFixed(pos, 4),
                       formatFixed(vel, 4), formatFixed(bias, 4), formatFixed(variance, 6),
                       formatFixed(anees, 2)});
    }
  }
  printTable(out, table);
  writeAtomically(dir / "sweep.csv", [&](std::ostream& f) { f << csv.str(); });
}

}  // namespace legkit::tools
