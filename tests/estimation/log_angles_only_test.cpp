// A recorded log with joint angles and no joint velocity columns (issue 22 item 4): the reader
// takes it (layout.joint_velocity false), the writer writes it back, and the front end
// differentiates the angles unless the settings insist on logged velocities.
#include <catch2/catch.hpp>

#include <sstream>
#include <stdexcept>

#include "estimation/log_conditioning.hpp"
#include "estimation/settings.hpp"
#include "io/log_columns.hpp"
#include "io/log_error.hpp"
#include "io/log_reader.hpp"
#include "io/log_writer.hpp"
#include "sim/simulator.hpp"

using namespace legkit;

namespace {

io::Log simulatedTrot() {
  sim::SimOptions options;
  options.scenario = sim::scenarioByName("trot");
  options.duration = 0.5;
  return sim::simulate(options).log;
}

// The log written without its velocity columns and read back.
io::Log withoutVelocities(io::Log log) {
  log.layout.joint_velocity = false;
  std::ostringstream out;
  io::writeLog(out, log);
  std::istringstream in(out.str());
  return io::readLog(in, "angles.csv");
}

// The same rows as generic joints joint<k>_q (no joint<k>_dq).
io::Log genericWithoutVelocities(io::Log log) {
  log.layout.joints = false;
  log.layout.torque = false;
  log.layout.num_joints = io::kNumJoints;
  for (io::LogRow& row : log.rows) {
    row.joint_q.head<io::kNumJoints>() = row.q;
    row.q.setZero();
    row.dq.setZero();
    row.tau.setZero();
  }
  return withoutVelocities(log);
}

std::string header(const io::LogLayout& layout) {
  std::string out;
  for (const io::Column& c : io::columnsOf(layout)) out += (out.empty() ? "" : ",") + c.name;
  return out;
}

}  // namespace

TEST_CASE("a log with joint angles and no velocity columns reads and writes back", "[57.11][log]") {
  const io::Log full = simulatedTrot();
  const io::Log angles = withoutVelocities(full);
  CHECK(angles.layout.joints);
  CHECK_FALSE(angles.layout.joint_velocity);
  CHECK(header(angles.layout).find("dq_") == std::string::npos);
  REQUIRE(angles.rows.size() == full.rows.size());
  for (std::size_t k = 0; k < full.rows.size(); ++k) {
    REQUIRE(angles.rows[k].q == full.rows[k].q);
    REQUIRE(angles.rows[k].dq.isZero());
  }
  io::Log again = withoutVelocities(angles);
  CHECK(again.layout == angles.layout);

  const io::Log generic = genericWithoutVelocities(full);
  CHECK(generic.layout.num_joints == io::kNumJoints);
  CHECK_FALSE(generic.layout.joint_velocity);
  CHECK(header(generic.layout).find("_dq") == std::string::npos);

  // A log with velocity columns says so.
  std::ostringstream out;
  io::writeLog(out, full);
  std::istringstream in(out.str());
  CHECK(io::readLog(in, "full.csv").layout.joint_velocity);
}

TEST_CASE("velocity columns are all or none", "[57.11][log]") {
  io::LogLayout layout;
  layout.joints = true;
  std::string text = header(layout);
  text.erase(text.find(",dq_RR_2"), 8);  // one velocity column short
  std::istringstream in(text + "\n");
  CHECK_THROWS_WITH(io::readLog(in, "short.csv"),
                    Catch::Matchers::Contains("dq_RR_2") && Catch::Matchers::Contains("or none"));
  io::LogLayout feet;
  feet.joints = false;
  feet.foot_columns = io::FootCovariance::kDiagonal;
  feet.joint_velocity = false;
  CHECK_THROWS_AS(io::columnsOf(feet), std::invalid_argument);
}

TEST_CASE("the front end differentiates a log's angles when it has no velocities",
          "[57.11][frontend]") {
  const io::Log full = simulatedTrot();
  for (const io::Log& recorded : {withoutVelocities(full), genericWithoutVelocities(full)}) {
    io::Log log = recorded;
    const ConditioningReport report = condition(log, defaultSettings().conditioning);
    CHECK(report.velocities_absent);
    CHECK(report.velocities_from_angles);
    CHECK_THAT(report.describe(),
               Catch::Matchers::Contains(
                   "joint velocities differentiated from the angles (the log has none)"));
    const bool generic = log.layout.num_joints > 0;
    for (std::size_t k = 1; k < log.rows.size(); ++k) {
      const io::LogRow& a = log.rows[k - 1];
      const io::LogRow& b = log.rows[k];
      const double dt = b.t - a.t;
      if (generic) {
        REQUIRE((b.joint_dq - (b.joint_q - a.joint_q) / dt).isZero(1e-9));
      } else {
        REQUIRE((b.dq - (b.q - a.q) / dt).isZero(1e-9));
      }
    }

    io::Log angles = recorded;
    LogConditioning what;
    what.joint_velocities = JointVelocitySource::kAngles;
    CHECK(condition(angles, what).velocities_from_angles);

    io::Log logged = recorded;
    what.joint_velocities = JointVelocitySource::kLogged;
    CHECK_THROWS_WITH(condition(logged, what),
                      Catch::Matchers::Contains("frontend.joint_velocities") &&
                          Catch::Matchers::Contains("no joint velocity columns"));
  }
  // A log with its velocities keeps them under auto.
  io::Log log = full;
  const ConditioningReport report = condition(log, defaultSettings().conditioning);
  CHECK_FALSE(report.velocities_absent);
  CHECK_FALSE(report.velocities_from_angles);
  CHECK_THAT(report.describe(), !Catch::Matchers::Contains("the log has none"));
}

TEST_CASE("frontend.joint_velocities reads auto, logged and angles", "[57.11][settings]") {
  CHECK(settingsFromYaml("frontend:\n  joint_velocities: \"auto\"\n", "t.yaml")
            .conditioning.joint_velocities == JointVelocitySource::kAuto);
  CHECK(settingsFromYaml("frontend:\n  joint_velocities: \"logged\"\n", "t.yaml")
            .conditioning.joint_velocities == JointVelocitySource::kLogged);
  const Settings s = settingsFromYaml("frontend:\n  joint_velocities: \"angles\"\n", "t.yaml");
  CHECK(settingsFromYaml(settingsYaml(s), "again.yaml").conditioning.joint_velocities ==
        JointVelocitySource::kAngles);
}
