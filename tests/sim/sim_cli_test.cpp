// `legkit sim --scenario trot --out log.csv` writes a log that the loader reads back exactly:
// the same rows, bit for bit, as the library's simulate() with the same options.
#include <unistd.h>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "io/log_reader.hpp"
#include "sim/simulator.hpp"
#include "spawn.hpp"

using namespace legkit;

TEST_CASE("legkit sim writes a log that reads back exactly", "[57.3][sim][log]") {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("legkit_sim_cli_" + std::to_string(getpid()) + ".csv"))
                               .string();
  REQUIRE(legkit::test::spawnAndWait({LEGKIT_EXE, "sim", "--scenario", "trot", "--duration", "2",
                                      "--seed", "3", "--dropout", "1.5:0.01", "--out", path},
                                     ".", "/dev/null") == 0);
  const io::Log log = io::readLog(path);
  std::remove(path.c_str());

  sim::SimOptions options;
  options.duration = 2.0;
  options.seed = 3;
  options.faults.dropouts = {{1.5, 0.01}};
  const sim::SimResult expected = sim::simulate(options);
  CHECK(log.layout == expected.log.layout);
  REQUIRE(log.rows.size() == expected.log.rows.size());
  CHECK(log.rows.size() == 2000 - 10);
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    REQUIRE(io::exactlyEqual(log.rows[k], expected.log.rows[k]));
  }
}
