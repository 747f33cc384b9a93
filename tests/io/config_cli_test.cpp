// `legkit config` and `legkit run --config` as a user meets them.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "legkit_cli.hpp"

namespace fs = std::filesystem;

namespace {

using Catch::Matchers::Contains;
using legkit::test::slurp;

using Result = legkit::test::ProgramResult;

using legkit::test::runLegkit;
using legkit::test::writeFile;

}  // namespace

TEST_CASE("legkit config: --print is config/legkit.yaml, --check names the line", "[cli]") {
  const legkit::test::ScratchFolder dir("config_cli");
  Result r = runLegkit(dir.path, {"config", "--print"});
  CHECK(r.status == 0);
  CHECK(r.output == slurp(LEGKIT_SOURCE_DIR "/config/legkit.yaml"));

  r = runLegkit(dir.path, {"config", "--check", LEGKIT_SOURCE_DIR "/config/legkit.yaml"});
  CHECK(r.status == 0);
  CHECK(r.output == "ok\n");

  writeFile(dir.path / "bad.yaml",
            "imu:\n  gyro_noise_density: 0.004\n  accel_noise_density: -1\n");
  r = runLegkit(dir.path, {"config", "--check", "bad.yaml"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("bad.yaml:3: imu.accel_noise_density: expected a number"));
  // The run refuses the same file before it simulates anything.
  r = runLegkit(dir.path, {"run", "--scenario", "trot", "--duration", "1", "--no-plots", "--config",
                           "bad.yaml"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("bad.yaml:3: imu.accel_noise_density"));
  CHECK_FALSE(fs::exists(dir.path / "legkit-out"));

  // A robot model for a log whose legs are the quadruped's joint columns: refused, naming the
  // key; a model that cannot be read is named as such first.
  writeFile(dir.path / "robot.yaml",
            "robot:\n  model: biped.xml\n  base: pelvis\n  feet: [l, r]\n");
  r = runLegkit(dir.path, {"run", "--scenario", "trot", "--duration", "1", "--no-plots", "--config",
                           "robot.yaml"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("robot.yaml: robot.model:") && Contains("biped.xml") &&
                           Contains("cannot open the file"));
  r = runLegkit(dir.path, {"run", "--scenario", "trot", "--duration", "1", "--no-plots", "--config",
                           LEGKIT_SOURCE_DIR "/config/robots/go2.yaml"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("go2.yaml: robot.model:") && Contains("no generic joint"));

  CHECK(runLegkit(dir.path, {"config"}).status == 1);  // --print or --check
}

TEST_CASE("legkit run --config: the file picks the estimators, the command line overrides",
          "[cli]") {
  const legkit::test::ScratchFolder dir("config_run");
  writeFile(dir.path / "two.yaml",
            "estimators: [invariant-ekf, linear-kf]\n"
            "contact:\n  detector: truth\n  slip_reaction: none\n  settle_time: 0\n");
  Result r = runLegkit(dir.path, {"run", "--scenario", "trot", "--duration", "2", "--no-plots",
                                  "--config", "two.yaml", "--slip", "drop", "--out", "out"});
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Contains("settings: two.yaml"));
  CHECK_THAT(r.output, Contains("slip handling: drop"));  // the command line wins
  const std::string summary = slurp(dir.path / "out" / "summary.json");
  CHECK_THAT(summary, Contains("\"config\": \"two.yaml\""));
  CHECK_THAT(summary, Contains("\"estimator\": \"invariant-ekf\""));
  CHECK_THAT(summary, Contains("\"estimator\": \"linear-kf\""));
  CHECK_FALSE(fs::exists(dir.path / "out" / "estimate_eskf.csv"));
  CHECK_FALSE(fs::exists(dir.path / "out" / "estimate_tsif.csv"));
  CHECK(fs::exists(dir.path / "out" / "estimate_linear-kf.csv"));
  // The invariant EKF comes first, as the file lists it.
  CHECK(summary.find("\"invariant-ekf\"") < summary.find("\"linear-kf\""));
}

TEST_CASE("legkit config --check loads the robot model; legkit robot shows it", "[cli][robot]") {
  const legkit::test::ScratchFolder dir("config_cli_robot");
  // A model that is not there, and a foot the model does not have: the check says so (exit 2), as
  // the run would, naming the settings file and the model.
  writeFile(dir.path / "missing.yaml",
            "robot:\n  model: nowhere.urdf\n  base: trunk\n  feet: [f]\n");
  Result r = runLegkit(dir.path, {"config", "--check", "missing.yaml"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("missing.yaml: robot.model: robot model '") &&
                           Contains("nowhere.urdf") && Contains("cannot open the file"));
  const std::string go1 = LEGKIT_SOURCE_DIR "/data/robots/unitree/go1.urdf";
  writeFile(dir.path / "nofoot.yaml",
            "robot:\n  model: " + go1 + "\n  base: trunk\n  feet: [FL_foot, toe]\n");
  r = runLegkit(dir.path, {"config", "--check", "nofoot.yaml"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("no site or body named 'toe' for a foot"));

  // The shipped Go1 (its URDF names meshes that are not shipped): joints in column order, the
  // mass of its <inertial> elements, feet at zero angles and at given ones.
  const std::string settings = LEGKIT_SOURCE_DIR "/config/robots/go1.yaml";
  r = runLegkit(dir.path, {"config", "--check", settings});
  CHECK(r.status == 0);
  CHECK(r.output == "ok\n");
  r = runLegkit(dir.path,
                {"robot", settings, "--angles", "0,0.8,-1.6,0,0.8,-1.6,0,0.8,-1.6,0,0.8,-1.6"});
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Contains("mass    13.101 kg") && Contains("joint0_q   FL_hip_joint") &&
                           Contains("joint11_q  RR_calf_joint"));
  // At zero angles the leg hangs straight: thigh + calf = 0.426 m below the hip; at thigh 0.8 and
  // calf -1.6 the foot is under the hip, 2 * 0.213 cos(0.8) = 0.2968 m below it.
  CHECK_THAT(r.output, Contains("foot0  FL_foot   0.1881   0.1268  -0.4260") &&
                           Contains("foot3  RR_foot  -0.1881  -0.1268  -0.2968"));
  r = runLegkit(dir.path, {"robot", settings, "--angles", "1,2"});
  CHECK(r.status == 1);
  CHECK_THAT(r.output, Contains("2 angles given") && Contains("has 12 joints"));

  // A log whose joints are not the robot's: the quadruped's own columns against the Go1's
  // generic joints.
  r = runLegkit(dir.path, {"sim", "--scenario", "trot", "--duration", "0.1", "--out", "trot.csv"});
  REQUIRE(r.status == 0);
  r = runLegkit(dir.path, {"robot", settings, "--log", "trot.csv"});
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("trot.csv: the log's joints are not the robot's") &&
                           Contains("has 12 joints (joint0_q .. joint11_q, robot.joints)"));
}
