// Sharding (tools/legkit/shard.hpp): --shard i/N parsed strictly, the blocks of N shards tile the
// items exactly once, the numbers of the per-run rows read back bit for bit, and eval::reduceRuns
// (what `legkit merge` recomputes a study with) gives what eval::monteCarlo gives.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "estimation/estimators.hpp"
#include "eval/monte_carlo.hpp"
#include "output.hpp"
#include "shard.hpp"

using namespace legkit;
using namespace legkit::tools;

TEST_CASE("--shard i/N: 1 <= i <= N <= 10000, whole decimal numbers, nothing else", "[shard]") {
  CHECK(parseShard("1/1").text() == "1/1");
  CHECK(parseShard("3/8").index == 3);
  CHECK(parseShard("3/8").count == 8);
  CHECK(parseShard("10000/10000").whole() == false);
  for (const char* bad : {"", "/", "1", "1/", "/2", "0/2", "3/2", "-1/2", "1/-2", "1/0", "a/2",
                          "1/2/3", " 1/2", "1/2 ", "1.0/2", "1/10001", "+1/2", "1/2x"}) {
    INFO(bad);
    CHECK_THROWS_AS(parseShard(bad), std::invalid_argument);
  }
}

TEST_CASE("the N blocks tile the M items in order, each item once, none empty", "[shard]") {
  for (int total = 1; total <= 40; ++total) {
    for (int n = 1; n <= total; ++n) {
      int next = 0;
      for (int i = 1; i <= n; ++i) {
        const Block b = shardBlock({i, n}, total, "runs");
        CHECK(b.begin == next);
        CHECK(b.end > b.begin);
        next = b.end;
      }
      CHECK(next == total);
    }
  }
  CHECK_THROWS_AS(shardBlock({1, 5}, 4, "runs"), UsageError);
}

TEST_CASE("exact() numbers read back bit for bit", "[shard]") {
  for (const double x : {0.0, -0.0, 1.0 / 3.0, 0.1, 1e-300, 5e-324, 1.7976931348623157e308,
                         -2.5e-17, 123456789.123456789}) {
    const double y = parseExact(exact(x), "test");
    CHECK(std::memcmp(&x, &y, sizeof x) == 0);
  }
  CHECK(std::isnan(parseExact(exact(std::nan("")), "test")));
  CHECK_THROWS_AS(parseExact("1.5x", "test"), InputError);
  CHECK_THROWS_AS(parseExact("", "test"), InputError);
}

TEST_CASE("reduceRuns of monteCarlo's per-run results is monteCarlo's estimate", "[shard]") {
  eval::MonteCarloOptions options;
  options.runs = 3;
  options.sim.duration = 1.0;
  options.threads = 2;
  options.prior = eval::InitialPrior{};
  std::vector<eval::RunSummary> runs(options.runs);
  options.on_run = [&](int j, std::size_t, const io::Log&, const eval::RunResult& run) {
    runs[j].nees = run.nees;  // each run's slot written once
    runs[j].nees_dof = run.nees_dof;
    runs[j].us_per_step = run.us_per_step;
  };
  const auto result = eval::monteCarlo(options, {{"eskf", [] { return makeEstimator("eskf"); }}});
  for (int j = 0; j < options.runs; ++j) runs[j].metrics = result[0].runs[j];
  const eval::MonteCarloEstimate again = eval::reduceRuns("eskf", result[0].t, runs);
  CHECK(again.anees == result[0].anees);
  CHECK(again.mean_anees == result[0].mean_anees);
  CHECK(again.fraction_inside == result[0].fraction_inside);
  CHECK(again.bounds.lower == result[0].bounds.lower);
  runs[1].nees.pop_back();
  CHECK_THROWS_AS(eval::reduceRuns("eskf", result[0].t, runs), std::invalid_argument);
  CHECK_THROWS_AS(eval::reduceRuns("eskf", result[0].t, {}), std::invalid_argument);
}
