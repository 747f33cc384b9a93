// `legkit study faults`' table (57.9) from its per-case results, made by one function for the
// single-machine study and for `legkit merge` of its shards (shard.hpp), and the rows a shard
// keeps in its manifest ("rows", every number with every bit) and the merge reads.
//
// The items a shard takes are the fault cases: each is written into the same physics trot (every
// shard simulates it, seeded by --seed) and run with the monitor's answers and, when it has
// some, without them, whatever the other cases.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace legkit::tools {

// One monitored run of a fault case.
struct FaultRun {
  std::vector<std::pair<std::string, double>> alarms;  // each alarm raised: name, first time [s]
  // Maxima over the run: position [m], attitude [rad], velocity [m/s], position sigma [m].
  double position = 0.0, attitude = 0.0, velocity = 0.0, position_sigma = 0.0;
  bool finite = true;
  std::string health;  // eval::describe of the estimator's and the pipeline's health
};

struct FaultCaseResult {
  std::string name;
  FaultRun answered;                // with the monitor's answers
  std::optional<FaultRun> without;  // without them, when the monitor has an answer
};

struct FaultsHeading {
  std::string filter;
  double duration = 0.0;  // of the physics trot [s]
  unsigned seed = 7;
};

// The results as the manifest's "rows" (numbers as %.17g text), and back; InputError naming
// `where` when they are not what fault results are.
nlohmann::json faultRowsToJson(const std::vector<FaultCaseResult>& rows);
std::vector<FaultCaseResult> faultRowsFromJson(const nlohmann::json& rows,
                                               const std::string& where);

// The study's table (markdown) on `out`.
void reportFaults(std::ostream& out, const FaultsHeading& heading,
                  const std::vector<FaultCaseResult>& rows);

}  // namespace legkit::tools
