// A simulated log is an ordinary log: it passes the strict loader (with the gap check at 1.5
// sample periods) and a written log reads back exactly.
#include <unistd.h>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "io/foot_measurement.hpp"
#include "io/log_reader.hpp"
#include "io/log_writer.hpp"
#include "sim/simulator.hpp"

using namespace legkit;

TEST_CASE("The default trot log reads back exactly and passes the loader", "[57.3][sim][log]") {
  sim::SimOptions options;  // the default: trot, Go2 sensors, every optional group
  options.duration = 3.0;
  const sim::SimResult run = sim::simulate(options);
  REQUIRE(run.log.rows.size() == 3000);

  const std::string path = (std::filesystem::temp_directory_path() /
                            ("legkit_sim_log_" + std::to_string(getpid()) + ".csv"))
                               .string();
  io::writeLog(path, run.log);
  io::ReadOptions strict;
  strict.max_gap = 1.5 / options.rate;
  const io::Log back = io::readLog(path, strict);
  std::remove(path.c_str());

  CHECK(back.layout == run.log.layout);
  CHECK(back.layout.joints);
  CHECK(back.layout.torque);
  CHECK(back.layout.force);
  CHECK(back.layout.contact);
  CHECK(back.layout.ground_truth);
  CHECK(back.comments == run.log.comments);
  REQUIRE(back.rows.size() == run.log.rows.size());
  for (std::size_t k = 0; k < back.rows.size(); ++k) {
    REQUIRE(io::exactlyEqual(back.rows[k], run.log.rows[k]));
  }
}

TEST_CASE("Every scenario's log passes the loader", "[57.3][sim][log]") {
  for (const std::string& name : sim::scenarioNames()) {
    INFO("scenario " << name);
    sim::SimOptions options;
    options.scenario = sim::scenarioByName(name);
    options.duration = 2.5;
    options.ground_truth = false;  // as a real robot would record it
    std::stringstream file;
    io::writeLog(file, sim::simulate(options).log);
    const io::Log log = io::readLog(file, name);
    CHECK(log.rows.size() == 2500);
    CHECK_FALSE(log.layout.ground_truth);
  }
}

TEST_CASE("The simulator can also write the robot-agnostic foot columns", "[57.3][sim][log]") {
  sim::SimOptions options;
  options.duration = 1.0;
  options.foot_columns = io::FootCovariance::kFull;
  const sim::SimResult run = sim::simulate(options);
  std::stringstream file;
  io::writeLog(file, run.log);
  const io::Log log = io::readLog(file, "feet");
  REQUIRE(log.layout.foot_columns == io::FootCovariance::kFull);
  REQUIRE_FALSE(log.layout.joints);  // one leg description per log
  REQUIRE(log.layout.num_feet == 4);
  // The same run with joint columns (same seed, same encoder noise) gives the angles.
  options.foot_columns = io::FootCovariance::kNone;
  const sim::SimResult with_joints = sim::simulate(options);
  const io::LogRow& joints = with_joints.log.rows[500];
  const model::QuadrupedKinematics kin;
  const io::LogRow& row = log.rows[500];
  for (int leg = 0; leg < model::kNumLegs; ++leg) {
    const ContactMeasurement m = io::footMeasurement(log.layout, row, leg);
    CHECK(m.foot == leg);
    CHECK(m.p_body == kin.footPosition(leg, joints.q.segment<3>(3 * leg)));
    CHECK(m.cov == m.cov.transpose());
    CHECK(m.cov.trace() > 3e-6);  // at least the 1 mm kinematic-model error per axis
  }
  CHECK_THROWS_WITH(io::footMeasurement(log.layout, row, 4),
                    Catch::Matchers::Contains("foot 4 is not in the log"));
}
