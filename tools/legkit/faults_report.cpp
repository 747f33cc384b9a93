#include "faults_report.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "output.hpp"
#include "shard.hpp"

namespace legkit::tools {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// "alarm at t s, ..." for every alarm raised, "-" when none.
std::string alarms(const FaultRun& r) {
  std::string s;
  for (const auto& [name, at] : r.alarms) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(3) << at;
    s += (s.empty() ? "" : ", ") + name + " at " + os.str() + " s";
  }
  return s.empty() ? "-" : s;
}

// "position m / attitude deg / velocity m/s / position sigma m" maxima over the run, then the
// estimator's and the pipeline's faults when there were any.
std::string errors(const FaultRun& r) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(4) << r.position << " m / " << std::setprecision(2)
     << r.attitude * kRadToDeg << " deg / " << r.velocity << " m/s / " << std::setprecision(4)
     << r.position_sigma << " m";
  if (!r.finite) os << " (not finite)";
  if (!r.health.empty()) os << "; " << r.health;
  return os.str();
}

nlohmann::json runToJson(const FaultRun& r) {
  nlohmann::json alarms = nlohmann::json::array();
  for (const auto& [name, at] : r.alarms) alarms.push_back({name, exact(at)});
  return {{"alarms", alarms},
          {"maxima",
           {exact(r.position), exact(r.attitude), exact(r.velocity), exact(r.position_sigma)}},
          {"finite", r.finite},
          {"health", r.health}};
}

FaultRun runFromJson(const nlohmann::json& j, const std::string& where) {
  FaultRun r;
  for (const nlohmann::json& a : j.at("alarms")) {
    r.alarms.emplace_back(a.at(0).get<std::string>(),
                          parseExact(a.at(1).get<std::string>(), where + ": alarm time"));
  }
  const nlohmann::json& m = j.at("maxima");
  if (m.size() != 4)
    throw InputError(where + ": 'maxima' holds " + std::to_string(m.size()) +
                     " numbers, 4 expected");
  double* const maxima[4] = {&r.position, &r.attitude, &r.velocity, &r.position_sigma};
  for (int i = 0; i < 4; ++i)
    *maxima[i] = parseExact(m.at(i).get<std::string>(), where + ": maxima");
  r.finite = j.at("finite").get<bool>();
  r.health = j.at("health").get<std::string>();
  return r;
}

}  // namespace

nlohmann::json faultRowsToJson(const std::vector<FaultCaseResult>& rows) {
  nlohmann::json all = nlohmann::json::array();
  for (const FaultCaseResult& c : rows) {
    all.push_back({{"case", c.name},
                   {"answered", runToJson(c.answered)},
                   {"without", c.without ? runToJson(*c.without) : nlohmann::json()}});
  }
  return all;
}

std::vector<FaultCaseResult> faultRowsFromJson(const nlohmann::json& rows,
                                               const std::string& where) {
  if (!rows.is_array()) throw InputError(where + ": no \"rows\" list of fault cases");
  std::vector<FaultCaseResult> cases;
  try {
    for (const nlohmann::json& c : rows) {
      const std::string at = where + ": case " + std::to_string(cases.size() + 1);
      FaultCaseResult r{c.at("case").get<std::string>(), runFromJson(c.at("answered"), at), {}};
      if (!c.at("without").is_null()) r.without = runFromJson(c.at("without"), at);
      cases.push_back(std::move(r));
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where + ": not a faults shard's rows (" + e.what() + ")");
  }
  return cases;
}

void reportFaults(std::ostream& out, const FaultsHeading& heading,
                  const std::vector<FaultCaseResult>& rows) {
  out << "# " << heading.filter << " on a " << heading.duration << " s physics trot (seed "
      << heading.seed
      << "), contacts from the fallback chain; errors are maxima: position / attitude / "
         "velocity / position sigma, then the estimator's and the pipeline's faults\n\n"
      << "| fault | alarms (first raised) | error with the monitor's answers | without them |\n"
      << "|---|---|---|---|\n";
  for (const FaultCaseResult& c : rows) {
    out << "| " << c.name << " | " << alarms(c.answered) << " | " << errors(c.answered) << " | "
        << (c.without ? errors(*c.without) : "-") << " |\n";
  }
}

}  // namespace legkit::tools
