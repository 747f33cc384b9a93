// Exercise 57.3.3: leg odometry over a simulated log (sim/ writes it, io/ reads it back), compared
// with the log's ground truth.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "ex57_3_3.hpp"
#include "exercises/exercise_check.hpp"
#include "io/log_writer.hpp"
#include "sim/simulator.hpp"

namespace {

legkit::io::Log simulatedLog(const std::string& scenario, double duration, bool noiseless) {
  legkit::sim::SimOptions options;
  options.scenario = legkit::sim::scenarioByName(scenario);
  options.duration = duration;
  options.seed = 5733;
  if (noiseless) options.noiseless();
  return legkit::sim::simulate(options).log;
}

}  // namespace

TEST_CASE("57.3.3 noiseless trot log: leg odometry equals the truth", "[ex57.3.3][hint 1]") {
  const legkit::model::QuadrupedKinematics kin;
  const std::string path =
      (std::filesystem::temp_directory_path() / "legkit_ex57_3_3_trot.csv").string();
  legkit::io::writeLog(path, simulatedLog("trot", 3.0, true));
  const ex57_3_3::Comparison c = ex57_3_3::compareLogFile(path, kin);
  std::filesystem::remove(path);
  INFO("rmse " << c.rmse << " m/s, max " << c.max_error << " m/s over " << c.rows_used << " rows");
  REQUIRE(c.rows_used == 3000);
  REQUIRE(c.rows_without_contact == 0);
  REQUIRE_BELOW(c.rmse, 1e-6);
  REQUIRE_BELOW(c.max_error, 1e-5);
}

TEST_CASE("57.3.3 noisy turning log: error at the gyro-noise level", "[ex57.3.3][hint 2]") {
  const legkit::model::QuadrupedKinematics kin;
  const ex57_3_3::Comparison c = ex57_3_3::compareWithTruth(simulatedLog("turn", 3.0, false), kin);
  INFO("rmse " << c.rmse << " m/s, max " << c.max_error << " m/s over " << c.rows_used << " rows");
  REQUIRE(c.rows_used == 3000);
  // Per 1 kHz sample the Go2 gyro's white noise is 0.004 rad/s/sqrt(Hz) * sqrt(1000 Hz) = 0.13
  // rad/s per axis; through w x r with |r| ~ 0.35 m that is a few cm/s, common to every foot (so
  // averaging feet does not remove it). Encoder-rate noise adds only mm/s.
  REQUIRE_ABOVE(c.rmse, 0.01);
  REQUIRE_BELOW(c.rmse, 0.1);
}

TEST_CASE("57.3.3 flight rows give no velocity and are counted", "[ex57.3.3][hint 3]") {
  const legkit::model::QuadrupedKinematics kin;
  const legkit::io::Log log = simulatedLog("bound", 3.0, true);
  int flight = 0;
  for (const legkit::io::LogRow& row : log.rows) {
    const bool any = row.contact[0] || row.contact[1] || row.contact[2] || row.contact[3];
    if (!any) {
      ++flight;
      REQUIRE_FALSE(ex57_3_3::rowVelocity(row, kin).has_value());
    }
  }
  REQUIRE(flight > 0);
  const ex57_3_3::Comparison c = ex57_3_3::compareWithTruth(log, kin);
  REQUIRE(c.rows_without_contact == flight);
  REQUIRE(c.rows_used + flight == static_cast<int>(log.rows.size()));
  REQUIRE_BELOW(c.rmse, 1e-6);
}

TEST_CASE("57.3.3 a log without ground truth is rejected", "[ex57.3.3][hint 4]") {
  const legkit::model::QuadrupedKinematics kin;
  legkit::io::Log log = simulatedLog("stand", 0.1, true);
  log.layout.ground_truth = false;
  REQUIRE_THROWS_AS(ex57_3_3::compareWithTruth(log, kin), std::invalid_argument);
}
