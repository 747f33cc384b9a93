// The settings of a recorded log's evaluation and contacts (issue 22 items 4 and 7):
// contact.gait, the planned gait of the gait-clock detector, and frontend.truth_velocity_window,
// the window that differentiates a pose-only truth. Both read back what settingsYaml() wrote,
// refuse bad values naming the line and the key, and reach eval::runWithSettings.
#include <catch2/catch.hpp>
#include <stdexcept>
#include <string>

#include "estimation/settings.hpp"
#include "eval/log_run.hpp"
#include "eval/metrics.hpp"
#include "io/yaml_reader.hpp"
#include "settings_error.hpp"
#include "sim/simulator.hpp"

using namespace legkit;
using Catch::Matchers::Contains;

namespace {

constexpr auto errorOf = test::settingsErrorOf;

io::Log trot() {
  sim::SimOptions options;
  options.scenario = sim::scenarioByName("trot");
  options.duration = 3.0;  // the trot starts from a stand
  return sim::simulate(options).log;
}

}  // namespace

TEST_CASE("settings: contact.gait and frontend.truth_velocity_window read back",
          "[settings][real-robot]") {
  const Settings defaults = defaultSettings();
  CHECK(defaults.truth_velocity_window == eval::kTruthVelocityWindow);
  CHECK(defaults.gait.period == 0.0);
  CHECK_FALSE(gaitSchedule(defaults, 4));

  Settings s = defaults;
  s.gait.period = 0.4;
  s.gait.duty = 0.55;
  s.gait.offsets = {0.0, 0.5, 0.25, 0.75};
  s.gait.start = 1.5;
  s.truth_velocity_window = 0.2;
  const std::string text = settingsYaml(s);
  CHECK_THAT(text, Contains("offsets: [0, 0.5, 0.25, 0.75]"));
  CHECK_THAT(text, Contains("truth_velocity_window: 0.2"));
  const Settings back = settingsFromYaml(text, "back.yaml");
  CHECK(settingsYaml(back) == text);
  CHECK(back.gait.offsets == s.gait.offsets);
  CHECK(back.truth_velocity_window == 0.2);

  const std::optional<contact::GaitSchedule> g = gaitSchedule(back, 4);
  REQUIRE(g);
  CHECK(g->period == 0.4);
  CHECK(g->duty == 0.55);
  CHECK(g->start == 1.5);
  CHECK(g->num_feet == 4);
  CHECK(g->offset[2] == 0.25);
  CHECK(g->offset[3] == 0.75);
  CHECK_THROWS_WITH(gaitSchedule(back, 2),
                    Contains("back.yaml: contact.gait.offsets: 4 offsets") && Contains("2 feet"));
}

TEST_CASE("settings: bad gait and window values name their line and key", "[settings]") {
  CHECK_THAT(errorOf("frontend:\n  truth_velocity_window: 0\n"),
             Contains("t.yaml:2") && Contains("truth_velocity_window"));
  CHECK_THAT(errorOf("frontend:\n  truth_velocity_window: 2\n"), Contains("truth_velocity_window"));
  CHECK_THAT(errorOf("contact:\n  gait:\n    period: 0.5\n"),
             Contains("t.yaml:3") && Contains("needs its offsets"));
  CHECK_THAT(errorOf("contact:\n  gait:\n    period: 0.5\n    offsets: [0, 1]\n"),
             Contains("t.yaml:4") && Contains("offsets"));
  CHECK_THAT(errorOf("contact:\n  gait:\n    duty: 0\n"), Contains("t.yaml:3") && Contains("duty"));
  CHECK_THAT(errorOf("contact:\n  gait:\n    period: 0.5\n    offsets: [0, 0, 0, 0, 0, 0, 0]\n"),
             Contains("offsets") && Contains("at most 6 feet"));
  CHECK_THAT(errorOf("contact:\n  gait:\n    phase: 1\n"), Contains("phase"));
  CHECK(errorOf("contact:\n  gait:\n    period: 0.5\n    offsets: [0, 0.5, 0.5, 0]\n").empty());
}

TEST_CASE("runWithSettings: gait-clock runs on the settings' gait, and says which key is missing",
          "[settings][real-robot]") {
  const io::Log log = trot();
  Settings s = defaultSettings();
  s.pipeline.contact = "gait-clock";
  CHECK_THROWS_WITH(eval::runWithSettings(log, s, "eskf", {}),
                    Contains("needs a gait schedule") && Contains("contact.gait"));
  s.gait.period = 0.5;
  s.gait.offsets = {0.0, 0.5, 0.5, 0.0};
  const eval::RunResult run = eval::runWithSettings(log, s, "eskf", {});
  CHECK(run.contact_source == "gait-clock");
  REQUIRE(run.trajectory.size() == log.rows.size());
  REQUIRE(run.given_contact.size() == log.rows.size());

  // The truth window reaches the NEES of a pose-only truth.
  io::Log pose = log;
  pose.layout.gt_velocity = false;
  Settings truth = defaultSettings();
  truth.pipeline.contact = "truth";
  const eval::RunResult narrow = eval::runWithSettings(pose, truth, "eskf", {});
  truth.truth_velocity_window = 0.3;
  const eval::RunResult wide = eval::runWithSettings(pose, truth, "eskf", {});
  REQUIRE(narrow.nees.size() == wide.nees.size());
  CHECK(narrow.nees != wide.nees);
}
