// Real robots end to end (issue 22): the shipped iCub walking log through its settings file, and
// the physics-real scenario (a simulated robot with a real one's imperfections) with and without
// heading corrections from the feet.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scratch_folder.hpp"
#include "spawn.hpp"

namespace fs = std::filesystem;
using namespace legkit;

namespace {

struct Row {
  double position = 0.0, yaw = 0.0, anees = 0.0;  // [m], [deg], [-] (NaN: no covariance)
};

// `legkit run ARGS --no-plots --out out` in `dir`; its exit status, and the summary's rows.
int runLegkit(const fs::path& dir, std::vector<std::string> arguments,
              std::map<std::string, Row>& table, std::string& output) {
  arguments.insert(arguments.begin(), {LEGKIT_EXE, "run"});
  arguments.insert(arguments.end(), {"--no-plots", "--out", "out"});
  const fs::path file = dir / "cli-output.txt";
  const int status = test::spawnAndWait(arguments, dir.string(), file.string());
  output = test::slurp(file);
  std::ifstream in(dir / "out" / "summary.json");
  if (!in) return status;

  const nlohmann::json summary = nlohmann::json::parse(in);
  for (const auto& e : summary["estimators"]) {
    Row r;
    r.position = e["position_rmse_m"].get<double>();
    r.yaw = e["yaw_rmse_deg"].get<double>();
    r.anees = e["anees"].is_null() ? std::nan("") : e["anees"].get<double>();
    table[e["estimator"].get<std::string>()] = r;
  }
  return status;
}

}  // namespace

TEST_CASE(
    "The shipped iCub log: from its still start, the flat-foot filters within 1.2 cm and "
    "no yaw worse than the gyro's",
    "[cli][real-robot]") {
  const test::ScratchFolder dir("icub_cli");
  std::map<std::string, Row> t;
  std::string output;
  const int status = runLegkit(dir.path,
                               {"--log", LEGKIT_SOURCE_DIR "/data/icub-walking/walking.csv",
                                "--config", LEGKIT_SOURCE_DIR "/config/robots/icub.yaml"},
                               t, output);
  INFO(output);
  REQUIRE(status == 0);
  // icub.yaml starts the gyro bias from the log's first 2 s of standing: about -5.7e-3 rad/s
  // about the IMU's z. The gyro alone then loses 0.29 deg of yaw, from a zero bias 2.39.
  CHECK_THAT(output, Catch::Matchers::Contains("start: gyro bias [") &&
                         Catch::Matchers::Contains("still window ending at 2.01 s"));
  const double gyro_yaw = t.at("imu-dead-reckoning").yaw;
  CHECK(gyro_yaw < 0.5);
  // Flat feet, the soles under the heading rule: 0.008 m and 0.26-0.28 deg (57.11's table). With
  // the soles outside the rule the same start gave 0.012 m and 0.93 deg; from a zero bias
  // 0.015 m and 1.30 deg.
  for (const char* name : {"eskf", "invariant-ekf", "tsif"}) {
    INFO(name);
    CHECK(t.at(name).position < 0.012);
    CHECK(t.at(name).yaw <= gyro_yaw + 0.1);
    // Scored against the differentiated Vicon pose, the Vicon glitch masked: 0.46, the paper's
    // noise values too large while the robot stands (57.11).
    CHECK(t.at(name).anees > 0.4);
    CHECK(t.at(name).anees < 2.0);
  }
  // The front end smooths the jittery stamps and differentiates the angles (icub.yaml): leg
  // odometry 0.022 m from the still start; on the recorded joint velocities it was 0.062 m (from
  // a zero bias), on the differentiated ones from a zero bias 0.031 m.
  CHECK_THAT(output,
             Catch::Matchers::Contains("time stamps smoothed (jitter 25 % of the row interval") &&
                 Catch::Matchers::Contains("joint velocities differentiated from the angles"));
  CHECK(t.at("leg-odometry").position < 0.025);
  CHECK(t.at("linear-kf").position < 0.025);
  CHECK(t.at("linear-kf").yaw <= gyro_yaw + 0.1);
}

TEST_CASE(
    "The iCub with point feet from its still start: every filter within 1.2 cm, no yaw "
    "worse than the gyro's",
    "[cli][real-robot]") {
  // icub.yaml with point feet, its model given by an absolute path.
  const test::ScratchFolder dir("icub_point_feet");
  std::string yaml = test::slurp(LEGKIT_SOURCE_DIR "/config/robots/icub.yaml");
  const auto replace = [&](const std::string& from, const std::string& to) {
    const std::size_t at = yaml.find(from);
    REQUIRE(at != std::string::npos);
    yaml.replace(at, from.size(), to);
  };
  replace("../../data/", LEGKIT_SOURCE_DIR "/data/");
  replace("  flat: true", "  flat: false");
  std::ofstream(dir.path / "icub-point.yaml") << yaml;
  std::map<std::string, Row> t;
  std::string output;
  const int status = runLegkit(dir.path,
                               {"--log", LEGKIT_SOURCE_DIR "/data/icub-walking/walking.csv",
                                "--config", (dir.path / "icub-point.yaml").string()},
                               t, output);
  INFO(output);
  REQUIRE(status == 0);
  // 0.010 m and 0.20-0.24 deg against the gyro's 0.29 deg; from a zero bias 0.025-0.026 m.
  const double gyro_yaw = t.at("imu-dead-reckoning").yaw;
  for (const char* name : {"eskf", "invariant-ekf", "tsif"}) {
    INFO(name);
    CHECK(t.at(name).position < 0.012);
    CHECK(t.at(name).yaw <= gyro_yaw + 0.1);
  }
}

TEST_CASE("--dataset icub-walking is the shipped log with its settings, one command",
          "[cli][real-robot]") {
  const test::ScratchFolder dir("icub_dataset");
  std::string output;
  std::map<std::string, Row> t;
  REQUIRE(runLegkit(dir.path, {"--dataset", "icub-walking"}, t, output) == 0);
  CHECK_THAT(output, Catch::Matchers::Contains("data/icub-walking/walking.csv (1188 samples)") &&
                         Catch::Matchers::Contains("config/robots/icub.yaml"));
  CHECK(t.at("invariant-ekf").position < 0.03);
  // A log of its own as well is refused (the dataset is one); an unknown dataset is named.
  CHECK(runLegkit(dir.path, {"--dataset", "icub-walking", "--log", "x.csv"}, t, output) == 1);
  CHECK(runLegkit(dir.path, {"--dataset", "no-such-log"}, t, output) == 1);
  CHECK_THAT(output, Catch::Matchers::Contains("--dataset"));
}

TEST_CASE(
    "physics-real: heading corrections from over-confident stance feet lose yaw; the heading rule "
    "and a robot's stance density (the defaults) keep the gyro's",
    "[cli][real-robot][physics][study]") {
  const test::ScratchFolder dir("physics_real_cli");
  // The filters as they were: heading corrections, and stance feet pinned as exact legs' are.
  std::ofstream(dir.path / "plain.yaml") << "feet:\n  correct_yaw: true\n  stance_density: 0.001\n";
  std::string output;
  std::map<std::string, Row> plain, kit;
  REQUIRE(runLegkit(dir.path, {"--scenario", "physics-real", "--config", "plain.yaml"}, plain,
                    output) == 0);
  REQUIRE(runLegkit(dir.path, {"--scenario", "physics-real"}, kit, output) == 0);
  const double gyro_yaw = kit.at("imu-dead-reckoning").yaw;
  for (const char* name : {"eskf", "invariant-ekf"}) {
    INFO(name << ": yaw " << plain.at(name).yaw << " deg with heading corrections, "
              << kit.at(name).yaw << " without; the gyro alone " << gyro_yaw);
    CHECK(plain.at(name).yaw > 2.0 * gyro_yaw);  // the real robot's failure, reproduced
    CHECK(kit.at(name).yaw <= gyro_yaw + 0.5);
    CHECK(kit.at(name).position < plain.at(name).position);
  }
}
