#include "convergence_report.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "output.hpp"
#include "shard.hpp"

namespace legkit::tools {
ConvergenceRows convergenceRows(int first, int count, std::vector<double> angles,
                                std::vector<std::string> filters) {
  ConvergenceRows rows{first, count, std::move(angles), std::move(filters), {}};
  rows.time.assign(rows.angles.size(),
                   std::vector<std::vector<double>>(rows.filters.size(),
                                                    std::vector<double>(count, std::nan(""))));
  return rows;
}

void writeConvergenceRows(std::ostream& out, const ConvergenceRows& rows) {
  out << "angles";
  for (const double a : rows.angles) out << ',' << exact(a);
  out << "\nfilters";
  for (const std::string& name : rows.filters) out << ',' << name;
  out << '\n';
  for (std::size_t a = 0; a < rows.angles.size(); ++a) {
    for (int j = 0; j < rows.count; ++j) {
      for (std::size_t e = 0; e < rows.filters.size(); ++e) {
        out << "run," << rows.first + j << ',' << exact(rows.angles[a]) << ',' << rows.filters[e]
            << ',' << exact(rows.time[a][e][j]) << '\n';
      }
    }
  }
}

ConvergenceRows readConvergenceRows(const std::filesystem::path& path, const Block& block) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot be read (the shard's per-run rows)");
  std::string line;
  std::vector<std::string> head[2];
  for (int i = 0; i < 2; ++i) {
    const char* key = i == 0 ? "angles" : "filters";
    if (!std::getline(in, line) || (head[i] = splitCsv(line)).size() < 2 || head[i][0] != key) {
      throw InputError(path.string() + ":" + std::to_string(i + 1) + ": expected '" + key +
                       ",...'");
    }
  }
  std::vector<double> angles;
  for (std::size_t i = 1; i < head[0].size(); ++i) {
    angles.push_back(parseExact(head[0][i], path.string() + ":1"));
  }
  ConvergenceRows rows = convergenceRows(block.begin, block.end - block.begin, angles,
                                         {head[1].begin() + 1, head[1].end()});
  const std::size_t per_angle = static_cast<std::size_t>(rows.count) * rows.filters.size();
  const std::size_t expected = rows.angles.size() * per_angle;
  std::size_t read = 0;
  for (int number = 3; std::getline(in, line); ++number, ++read) {
    const std::string where = path.string() + ":" + std::to_string(number);
    const std::vector<std::string> f = splitCsv(line);
    const std::size_t a = read / per_angle;
    const int j = static_cast<int>(read % per_angle / rows.filters.size());
    const std::size_t e = read % rows.filters.size();
    if (read >= expected || f.size() != 5 || f[0] != "run" ||
        f[1] != std::to_string(rows.first + j) || f[2] != exact(rows.angles[a]) ||
        f[3] != rows.filters[e]) {
      throw InputError(where + ": expected " +
                       (read >= expected
                            ? std::string("the end of the file")
                            : "'run," + std::to_string(rows.first + j) + "," +
                                  exact(rows.angles[a]) + "," + rows.filters[e] + ",<time>'"));
    }
    rows.time[a][e][j] = parseExact(f[4], where + ": field 5");
  }
  if (read != expected) {
    throw InputError(path.string() + ": " + std::to_string(read) + " run lines, " +
                     std::to_string(expected) + " expected (a truncated file?)");
  }
  return rows;
}

void appendConvergenceRows(ConvergenceRows& all, const ConvergenceRows& next,
                           const std::string& where) {
  if (all.filters.empty()) {
    all = next;
    return;
  }
  if (next.angles != all.angles || next.filters != all.filters) {
    throw InputError(where + ": other angles or filters than shard 1's");
  }
  for (std::size_t a = 0; a < all.angles.size(); ++a) {
    for (std::size_t e = 0; e < all.filters.size(); ++e) {
      all.time[a][e].insert(all.time[a][e].end(), next.time[a][e].begin(), next.time[a][e].end());
    }
  }
  all.count += next.count;
}

void reportConvergence(std::ostream& out, const std::filesystem::path& dir,
                       const ConvergenceRows& rows, double duration) {
  const int runs = rows.count;
  std::ostringstream csv;
  csv << std::setprecision(8);
  csv << "# runs " << runs << " duration " << duration << '\n'
      << "filter,angle_deg,runs,converged_fraction,median_time_s\n";
  // table[angle][filter] = (fraction, median time)
  std::vector<std::vector<std::pair<double, double>>> table(rows.angles.size());
  for (std::size_t a = 0; a < rows.angles.size(); ++a) {
    for (std::size_t e = 0; e < rows.filters.size(); ++e) {
      std::vector<double> t;  // convergence times of the converged runs
      for (const double time : rows.time[a][e]) {
        if (!std::isnan(time)) t.push_back(time);
      }
      std::sort(t.begin(), t.end());
      const double fraction = static_cast<double>(t.size()) / runs;
      const double median = t.empty() ? NAN : t[t.size() / 2];
      table[a].emplace_back(fraction, median);
      csv << rows.filters[e] << ',' << rows.angles[a] << ',' << runs << ',' << fraction << ','
          << median << '\n';
    }
  }
  out << "Convergence from a wrong initial attitude (" << runs << " runs x " << duration
      << " s of trot per angle; converged: roll/pitch < 2 deg and body velocity < 0.1 m/s from t_c "
         "on)\n\n";
  std::vector<std::vector<std::string>> cells = {{"angle"}, {"[deg]"}};
  for (const std::string& name : rows.filters) {
    cells[0].push_back(name);
    cells[1].push_back("converged, median t_c");
  }
  for (std::size_t a = 0; a < rows.angles.size(); ++a) {
    cells.push_back({formatFixed(rows.angles[a], 0)});
    for (const auto& [fraction, median] : table[a]) {
      cells.back().push_back(formatFixed(100.0 * fraction, 0) + " %, " +
                             (std::isnan(median) ? "-" : formatFixed(median, 2) + " s"));
    }
  }
  printTable(out, cells);
  writeAtomically(dir / "convergence.csv", [&](std::ostream& f) { f << csv.str(); });
}

}  // namespace legkit::tools
