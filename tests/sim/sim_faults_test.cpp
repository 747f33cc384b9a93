// Injected faults do what they say: a slipping foot moves at the chosen speed, contact flags are
// shifted by the offset, dropouts remove samples (and the loader's gap check sees it).
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>

#include "io/log_error.hpp"
#include "io/log_reader.hpp"
#include "io/log_writer.hpp"
#include "sim_test_support.hpp"

using namespace legkit;
using sim::test::footInWorld;

TEST_CASE("A slipping stance foot moves at the chosen speed and direction", "[57.3][sim]") {
  const model::QuadrupedKinematics kin;
  sim::SimOptions options = sim::test::noiselessRun("trot", 5.0);
  sim::SlipFault& slip = options.faults.slip;
  slip.leg = model::FR;
  slip.start = 3.0;
  slip.duration = 0.6;
  slip.speed = 0.3;
  slip.direction = Eigen::Vector3d(1.0, 1.0, 0.0);
  const Eigen::Vector3d direction = Eigen::Vector3d(1.0, 1.0, 0.0).normalized();
  const sim::SimResult run = sim::simulate(options);
  const auto& rows = run.log.rows;

  int sliding = 0;
  for (std::size_t k = 0; k + 1 < rows.size(); ++k) {
    for (int leg = 0; leg < model::kNumLegs; ++leg) {
      if (!rows[k].contact[leg] || !rows[k + 1].contact[leg]) continue;
      const Eigen::Vector3d v =
          (footInWorld(kin, rows[k + 1], leg) - footInWorld(kin, rows[k], leg)) /
          (rows[k + 1].t - rows[k].t);
      const bool in_window = rows[k].t >= slip.start && rows[k + 1].t <= slip.start + slip.duration;
      if (leg == slip.leg && in_window) {
        ++sliding;
        CHECK((v - slip.speed * direction).norm() < 1e-6);
      } else if (rows[k + 1].t <= slip.start || rows[k].t >= slip.start + slip.duration ||
                 leg != slip.leg) {
        CHECK(v.norm() < 1e-6);
      }
    }
  }
  // FR is in stance 60 % of the time: about 360 of the 600 samples of the window.
  CHECK(sliding == Approx(360).margin(15));
  CHECK(rows[3500].contact[model::FR] == sim::simulate(sim::test::noiselessRun("trot", 5.0))
                                             .log.rows[3500]
                                             .contact[model::FR]);  // the flags do not tell
}

TEST_CASE("A contact-timing offset shifts the logged flags", "[57.3][sim]") {
  sim::SimOptions options = sim::test::noiselessRun("trot", 3.0);
  const sim::SimResult truth = sim::simulate(options);
  options.faults.contact_offset = 0.02;  // flags 20 ms late
  const sim::SimResult late = sim::simulate(options);
  const auto& rows = truth.log.rows;
  int changed = 0;
  for (std::size_t k = 21; k + 1 < rows.size(); ++k) {
    // 20 samples late (the flag time t - 0.02 may round to either side of a contact change).
    const bool at_change = rows[k - 21].contact != rows[k - 19].contact;
    if (!at_change) CHECK(late.log.rows[k].contact == rows[k - 20].contact);
    CHECK(late.log.rows[k].force == rows[k].force);  // forces keep the true timing
    changed += late.log.rows[k].contact != rows[k].contact ? 1 : 0;
  }
  CHECK(changed > 100);
}

TEST_CASE("Dropouts remove samples and the loader's gap check reports them", "[57.3][sim]") {
  sim::SimOptions options;
  options.duration = 3.0;
  options.faults.dropouts = {{2.0, 0.05}};
  const sim::SimResult run = sim::simulate(options);
  CHECK(run.log.rows.size() == 3000 - 50);
  for (const io::LogRow& row : run.log.rows) CHECK_FALSE((row.t >= 2.0 && row.t < 2.05));

  std::stringstream file;
  io::writeLog(file, run.log);
  io::ReadOptions strict;
  strict.max_gap = 1.5 / options.rate;
  try {
    io::readLog(file, "dropout.csv", strict);
    FAIL("the gap was not reported");
  } catch (const io::LogError& e) {
    CHECK(e.column() == "t");
    CHECK(e.line() == 2 + 1 + 2000);  // comment, header, then the row after the 2000 kept ones
    CHECK(std::string(e.what()).find("gap of 0.05") != std::string::npos);
  }
  file.clear();
  file.seekg(0);
  CHECK(io::readLog(file, "dropout.csv").rows.size() == run.log.rows.size());

  options.faults.dropouts.clear();
  options.faults.dropout_probability = 0.02;
  const std::size_t kept = sim::simulate(options).log.rows.size();
  CHECK(kept == Approx(0.98 * 3000).margin(4 * std::sqrt(0.02 * 0.98 * 3000)));
}

TEST_CASE("Bad fault options are refused with a reason", "[57.3][sim]") {
  sim::SimOptions options;
  options.duration = 1.0;
  options.faults.slip.leg = 4;
  CHECK_THROWS_WITH(sim::simulate(options), Catch::Matchers::Contains("leg 4 is out of range"));
  options.faults.slip.leg = -1;
  options.faults.dropout_probability = 1.0;
  CHECK_THROWS_WITH(sim::simulate(options), Catch::Matchers::Contains("dropout probability"));
  CHECK_THROWS_WITH(sim::scenarioByName("gallop"), Catch::Matchers::Contains("unknown scenario"));
}
