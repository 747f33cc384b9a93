// `legkit allan` end to end: a plain recording in, the settings keys, the files and the exit codes
// out (it runs the built program).
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "scratch_folder.hpp"
#include "spawn.hpp"

namespace {

// Runs legkit with args in dir; returns the exit status, the output in *text.
int runLegkit(const std::vector<std::string>& args, const std::filesystem::path& dir,
              std::string* text) {
  std::vector<std::string> argv = {LEGKIT_EXE};
  argv.insert(argv.end(), args.begin(), args.end());
  const std::string output = (dir / "output.txt").string();
  const int status = legkit::test::spawnAndWait(argv, dir.string(), output);
  *text = legkit::test::slurp(output);
  UNSCOPED_INFO("legkit said:\n" << *text);
  return status;
}

// 200 s at 100 Hz of white noise of density 0.01 per root hertz with a bias that random-walks by
// `walk` per root second on every axis, timestamps jittered by up to 0.2 of a step.
void writeRecording(const std::filesystem::path& file, double walk) {
  std::ofstream f(file);
  f << "# an IMU\nt,gx,gy,gz,ax,ay,az\n";
  std::mt19937_64 gen(7);
  std::normal_distribution<double> unit;
  std::uniform_real_distribution<double> jitter(-0.002, 0.002);
  double bias[6] = {};
  for (int k = 0; k < 20000; ++k) {
    f << 100.0 + 0.01 * k + jitter(gen);
    for (double& b : bias) {
      f << ',' << b + 0.1 * unit(gen);  // 0.01 / sqrt(0.01)
      b += walk * 0.1 * unit(gen);      // walk * sqrt(0.01)
    }
    f << '\n';
  }
}

}  // namespace

TEST_CASE("legkit allan reads a plain recording and prints the settings keys", "[allan][cli]") {
  legkit::test::ScratchFolder dir("allan_cli");
  writeRecording(dir.path / "imu.csv", 0.01);
  std::string text;
  REQUIRE(runLegkit({"allan", "imu.csv", "--no-plots", "--out", "out"}, dir.path, &text) == 0);
  CHECK_THAT(text, Catch::Contains("20000 samples, tau0 0.01 s"));
  // The densities within three of their +-1.1 % standard errors; a random walk either measured
  // or left out with its reason (200 s are short for the +1/2 line).
  for (const char* key : {"imu:\n  gyro_noise_density: ", "  accel_noise_density: "}) {
    const std::size_t at = text.find(key);
    REQUIRE(at != std::string::npos);
    CHECK(std::stod(text.substr(at + std::string(key).size())) == Approx(0.01).epsilon(0.033));
  }
  CHECK_THAT(text, Catch::Contains("gyro_bias_random_walk: "));
  CHECK_THAT(text, Catch::Contains("accel_bias_random_walk: "));
  const std::string yaml = legkit::test::slurp(dir.path / "out" / "imu-noise.yaml");
  CHECK(text.find(yaml) != std::string::npos);
  const std::string csv = legkit::test::slurp(dir.path / "out" / "allan.csv");
  CHECK(csv.rfind("axis,tau,m,adev,lo,hi\ngyro_x,0.01,1,", 0) == 0);
  CHECK(std::filesystem::exists(dir.path / "out" / "allan-lines.csv"));
  CHECK_FALSE(std::filesystem::exists(dir.path / "out" / "allan.png"));
}

TEST_CASE("legkit allan refuses a gap and a missing input", "[allan][cli]") {
  legkit::test::ScratchFolder dir("allan_cli_bad");
  std::ofstream(dir.path / "gap.csv") << "t,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,0\n0.01,0,0,0,0,0,0\n"
                                         "0.02,0,0,0,0,0,0\n0.05,0,0,0,0,0,0\n";
  std::string text;
  CHECK(runLegkit({"allan", "gap.csv", "--no-plots"}, dir.path, &text) == 2);
  CHECK_THAT(text, Catch::Contains("gap.csv:5: column 't': a gap"));
  CHECK_FALSE(std::filesystem::exists(dir.path / "legkit-out"));
  CHECK(runLegkit({"allan"}, dir.path, &text) == 1);
  CHECK_THAT(text, Catch::Contains("give a recording FILE or --simulate SECONDS"));
}

TEST_CASE("legkit allan refuses what is not a resting IMU and writes nothing", "[allan][cli]") {
  legkit::test::ScratchFolder dir("allan_cli_moving");
  std::string text;
  // A reading near 1e300 overflowed the Allan sums: "not found" and B = 0, exit 0.
  std::ofstream(dir.path / "huge.csv") << "t,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,9.8\n"
                                          "0.01,0,1e300,0,0,0,9.8\n0.02,0,0,0,0,0,9.8\n";
  CHECK(runLegkit({"allan", "huge.csv", "--no-plots"}, dir.path, &text) == 2);
  CHECK_THAT(text, Catch::Contains("huge.csv:3: column 'gy': a rate of"));
  CHECK_THAT(text, Catch::Contains("beyond an IMU's full scale"));
  // A rate that wanders by 1 rad/s per root second, as a moving robot's does: its bias random walk
  // is beyond any IMU at rest, so no imu-noise.yaml (nor anything else) is written.
  writeRecording(dir.path / "moving.csv", 1.0);
  CHECK(runLegkit({"allan", "moving.csv", "--no-plots", "--out", "out"}, dir.path, &text) == 2);
  CHECK_THAT(text, Catch::Contains("moving.csv: not a resting IMU's record: gyro_x reads a bias "
                                   "random walk of"));
  CHECK_THAT(text, Catch::Contains("where an IMU at rest shows at most 0.1; nothing written"));
  CHECK_FALSE(std::filesystem::exists(dir.path / "out"));
  // The kit's own log of a trotting robot: refused the same way (it wrote its densities before).
  REQUIRE(runLegkit({"sim", "--scenario", "trot", "--duration", "10", "--out", "trot.csv"},
                    dir.path, &text) == 0);
  CHECK(runLegkit({"allan", "trot.csv", "--no-plots", "--out", "out"}, dir.path, &text) == 2);
  CHECK_THAT(text, Catch::Contains("trot.csv: not a resting IMU's record"));
  CHECK_FALSE(std::filesystem::exists(dir.path / "out"));
}
