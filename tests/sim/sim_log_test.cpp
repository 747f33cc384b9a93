// A simulated log is an ordinary log: it passes the strict loader (with the gap check at 1.5
// sample periods) and a written log reads back exactly.
#include <unistd.h>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>

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
