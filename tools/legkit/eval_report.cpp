#include "eval_report.hpp"

#include <cmath>
#include <map>

#include "output.hpp"
#include "shard.hpp"

namespace legkit::tools {
namespace {

// The metrics of a row in table order, with their headings.
constexpr const char* kMetricNames[] = {"pos RMSE [m]", "ATE se3 [m]", "RPE 1 m [%]",
                                        "RPE 1 m [deg]", "ANEES"};
constexpr int kDigits[] = {4, 4, 3, 3, 3};

std::vector<double> metrics(const EvalEstimatorRow& r) {
  return {r.position_rmse, r.ate_se3, r.rpe_percent, r.rpe_deg, r.anees};
}

// A metric as the CSV gives it: 10 significant digits, NaN as empty (not computed).
std::string csvCell(double value) {
  return std::isnan(value) ? std::string() : formatG(value, 10);
}

// A log's error on one line of a CSV: quoted, its quotes doubled.
std::string quoted(const std::string& text) {
  std::string q = "\"";
  for (const char c : text)
    q += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return q + "\"";
}

struct Overall {
  std::vector<double> sum = std::vector<double>(std::size(kMetricNames), 0.0);
  std::vector<int> count = std::vector<int>(std::size(kMetricNames), 0);
  int logs = 0;
  int unhealthy = 0;
};

}  // namespace

nlohmann::json toJson(const std::vector<EvalLogRow>& rows) {
  nlohmann::json out = nlohmann::json::array();
  for (const EvalLogRow& row : rows) {
    nlohmann::json estimators = nlohmann::json::array();
    for (const EvalEstimatorRow& r : row.estimators) {
      estimators.push_back({{"estimator", r.estimator},
                            {"healthy", r.healthy},
                            {"failure", r.failure},
                            {"position_rmse", exact(r.position_rmse)},
                            {"ate_se3", exact(r.ate_se3)},
                            {"rpe_percent", exact(r.rpe_percent)},
                            {"rpe_deg", exact(r.rpe_deg)},
                            {"anees", exact(r.anees)}});
    }
    out.push_back({{"log", row.log},
                   {"error", row.error},
                   {"samples", row.samples},
                   {"estimators", estimators}});
  }
  return out;
}

std::vector<EvalLogRow> evalRowsFromJson(const nlohmann::json& rows, const std::string& where) {
  std::vector<EvalLogRow> out;
  try {
    for (const nlohmann::json& row : rows) {
      EvalLogRow r{row.at("log").get<std::string>(),
                   row.at("error").get<std::string>(),
                   row.at("samples").get<int>(),
                   {}};
      for (const nlohmann::json& e : row.at("estimators")) {
        const auto number = [&](const char* key) {
          return parseExact(e.at(key).get<std::string>(), where + ": " + r.log + ": " + key);
        };
        r.estimators.push_back({e.at("estimator").get<std::string>(), e.at("healthy").get<bool>(),
                                e.at("failure").get<std::string>(), number("position_rmse"),
                                number("ate_se3"), number("rpe_percent"), number("rpe_deg"),
                                number("anees")});
      }
      out.push_back(std::move(r));
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where + ": its rows are not legkit eval's (" + e.what() + ")");
  }
  return out;
}

std::string evalHeading(const nlohmann::json& options) {
  return "legkit eval: " + std::to_string(options.at("logs").size()) + " logs in " +
         options.at("dir").get<std::string>() + ", settings " +
         options.at("config").get<std::string>();
}

int evalStatus(const std::vector<EvalLogRow>& rows) {
  bool unhealthy = false;
  for (const EvalLogRow& row : rows) {
    if (!row.error.empty()) return kExitInput;
    for (const EvalEstimatorRow& r : row.estimators) unhealthy = unhealthy || !r.healthy;
  }
  return unhealthy ? kExitUnhealthy : kExitOk;
}

int reportEval(std::ostream& out, std::ostream& err, const std::filesystem::path& dir,
               const std::string& heading, const std::vector<EvalLogRow>& rows) {
  std::vector<std::vector<std::string>> table = {{"log", "estimator"}};
  std::string csv = "log,estimator,samples,healthy";
  for (const char* name : kMetricNames) {
    table[0].push_back(name);
  }
  table[0].push_back("status");
  csv += ",position_rmse_m,ate_se3_m,rpe_1m_percent,rpe_1m_deg,anees,error\n";
  std::vector<std::string> order;  // estimators in order of appearance
  std::map<std::string, Overall> overall;
  for (const EvalLogRow& row : rows) {
    if (!row.error.empty()) {
      table.push_back({row.log, "-", "-", "-", "-", "-", "-", "FAILED (see below)"});
      csv += row.log + ",,,,,,,,," + quoted(row.error) + "\n";
      continue;
    }
    for (const EvalEstimatorRow& r : row.estimators) {
      if (!overall.count(r.estimator)) order.push_back(r.estimator);
      Overall& o = overall[r.estimator];
      ++o.logs;
      o.unhealthy += !r.healthy;
      std::vector<std::string> cells = {row.log, r.estimator};
      csv += row.log + "," + r.estimator + "," + std::to_string(row.samples) + "," +
             (r.healthy ? "1" : "0");
      const std::vector<double> m = metrics(r);
      for (std::size_t i = 0; i < m.size(); ++i) {
        cells.push_back(formatG(m[i], kDigits[i]));
        csv += "," + csvCell(m[i]);
        if (!std::isnan(m[i])) {
          o.sum[i] += m[i];
          ++o.count[i];
        }
      }
      cells.push_back(r.healthy ? "ok" : "UNHEALTHY");
      csv += "," + (r.failure.empty() ? std::string() : quoted(r.failure)) + "\n";
      table.push_back(std::move(cells));
    }
  }
  int bad = 0;
  for (const EvalLogRow& row : rows) bad += !row.error.empty();
  out << heading << "\n\n";
  printTable(out, table);
  out << "\nOverall (mean over the " << rows.size() - bad << " logs that ran"
      << (bad ? ", " + std::to_string(bad) + " failed" : std::string()) << "):\n\n";
  std::vector<std::vector<std::string>> summary = {{"estimator", "logs"}};
  for (const char* name : kMetricNames) summary[0].push_back(name);
  summary[0].push_back("unhealthy");
  for (const std::string& name : order) {
    const Overall& o = overall.at(name);
    std::vector<std::string> cells = {name, std::to_string(o.logs)};
    csv += "overall," + name + ",," + std::to_string(o.logs - o.unhealthy == o.logs ? 1 : 0);
    for (std::size_t i = 0; i < o.sum.size(); ++i) {
      const double mean = o.count[i] ? o.sum[i] / o.count[i] : std::nan("");
      cells.push_back(formatG(mean, kDigits[i]));
      csv += "," + csvCell(mean);
    }
    cells.push_back(std::to_string(o.unhealthy));
    csv += ",\n";
    summary.push_back(std::move(cells));
  }
  printTable(out, summary);
  for (const EvalLogRow& row : rows) {
    if (!row.error.empty()) err << "legkit eval: FAILED " << row.error << '\n';
    for (const EvalEstimatorRow& r : row.estimators) {
      if (!r.healthy)
        err << "legkit eval: " << row.log << ": " << r.estimator << ": " << r.failure << '\n';
    }
  }
  writeAtomically(dir / "eval.csv", [&](std::ostream& f) { f << csv; });
  return evalStatus(rows);
}

}  // namespace legkit::tools
