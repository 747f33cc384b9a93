// Section 57.10: the overlapping Allan deviation against published reference values, the noise
// parameters recovered from simulated IMU data, and the recording reader's errors.
#include "estimation/imu/allan.hpp"

#include <rapidcheck/catch.h>
#include <catch2/catch.hpp>
#include <cstdint>
#include <fstream>
#include <random>

#include "io/log_error.hpp"
#include "io/log_writer.hpp"
#include "model/imu_model.hpp"
#include "scratch_folder.hpp"

using legkit::imu::AllanPoint;

namespace {

// Rate samples as an Eigen vector.
Eigen::VectorXd vec(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

// A resting IMU with the given noise, sampled every dt for the given number of samples, through
// the kit's own sensor model (model/imu_model.hpp): white noise plus a random-walk bias.
legkit::imu::ImuRecording simulatedImu(const legkit::model::ImuNoise& noise, double dt,
                                       std::size_t samples, unsigned seed) {
  std::mt19937_64 gen(seed);
  legkit::model::ImuBias bias;
  legkit::imu::ImuRecording rec;
  rec.tau0 = dt;
  rec.source = "simulated";
  rec.values.reserve(samples * 6);
  for (std::size_t k = 0; k < samples; ++k) {
    const legkit::model::ImuReading r = legkit::model::synthesiseReading(
        noise, dt, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
        bias, gen);
    rec.values.insert(rec.values.end(), r.w_m.data(), r.w_m.data() + 3);
    rec.values.insert(rec.values.end(), r.a_m.data(), r.a_m.data() + 3);
  }
  return rec;
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// The message of the LogError readImuRecording throws on path ("" if it throws none).
std::string readError(const std::filesystem::path& path) {
  try {
    legkit::imu::readImuRecording(path.string());
  } catch (const legkit::io::LogError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// W. J. Riley, Handbook of Frequency Stability Analysis, NIST SP 1065 (2008), p. 107: the
// "NBS14" 9-point frequency data set and its overlapping Allan deviations, 91.22945 at tau = 1
// and 85.95287 at tau = 2 (computed with Stable32); the same data and values are in the test
// suite of the allantools Python package (tests/nbs14/test_nbs14_10point.py).
TEST_CASE("overlapping Allan deviation of the NBS14 9-point data set", "[allan]") {
  const Eigen::VectorXd y = vec({892.0, 809.0, 823.0, 798.0, 671.0, 644.0, 883.0, 903.0, 677.0});
  const std::vector<AllanPoint> curve = legkit::imu::allanDeviation(y, 1.0, {1, 2});
  REQUIRE(curve.size() == 2);
  CHECK(curve[0].adev == Approx(91.22945).epsilon(1e-6));
  CHECK(curve[1].adev == Approx(85.95287).epsilon(1e-6));
  CHECK(curve[1].tau == 2.0);
}

// NIST SP 1065, pp. 107-108: the 1000-point data set made by the minimal
// standard generator n_{i+1} = 16807 n_i mod (2^31 - 1), n_0 = 1234567890, y_i = n_i / (2^31 - 1);
// overlapping Allan deviation 2.922319e-1, 9.159953e-2, 3.241343e-2 at tau = 1, 10, 100 (also in
// allantools' tests/nbs14/test_nbs14_1000point.py).
TEST_CASE("overlapping Allan deviation of the NBS14 1000-point data set", "[allan]") {
  std::vector<double> y(1000);
  std::uint64_t n = 1234567890;
  for (double& v : y) {
    v = static_cast<double>(n) / 2147483647.0;
    n = (16807 * n) % 2147483647;
  }
  const std::vector<AllanPoint> curve = legkit::imu::allanDeviation(vec(y), 1.0, {1, 10, 100});
  CHECK(curve[0].adev == Approx(2.922319e-1).epsilon(1e-6));
  CHECK(curve[1].adev == Approx(9.159953e-2).epsilon(1e-6));
  CHECK(curve[2].adev == Approx(3.241343e-2).epsilon(1e-6));
  // The simple 1-sigma interval: adev (1 -+ 1/sqrt(N/m)), here N/m = 10 at tau = 100.
  CHECK(curve[2].lo == Approx(3.241343e-2 * (1.0 - 1.0 / std::sqrt(10.0))).epsilon(1e-6));
  CHECK(curve[2].hi == Approx(3.241343e-2 * (1.0 + 1.0 / std::sqrt(10.0))).epsilon(1e-6));
}

TEST_CASE("averaging factors are log-spaced up to a quarter of the record", "[allan]") {
  const std::vector<int> m = legkit::imu::allanFactors(100000, std::pow(10.0, 0.1));
  REQUIRE(m.front() == 1);
  CHECK(m.back() <= 25000);
  CHECK(m.back() > 25000 / 2);
  for (std::size_t i = 1; i < m.size(); ++i) CHECK(m[i] > m[i - 1]);
  // Ten per decade once the integers stop crowding: 10..25000 spans 3.4 decades.
  const auto from10 = std::count_if(m.begin(), m.end(), [](int f) { return f >= 10; });
  CHECK(from10 == 34);
  const std::vector<int> octaves = legkit::imu::allanFactors(100000);
  CHECK(octaves ==
        std::vector<int>{1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384});
  CHECK_THROWS_AS(legkit::imu::allanFactors(100, 1.0), std::invalid_argument);
  CHECK_THROWS_AS(legkit::imu::allanDeviation(Eigen::VectorXd::Ones(100), 1.0, {26}),
                  std::invalid_argument);
}

TEST_CASE("the Allan deviation ignores an offset and scales with the signal", "[allan]") {
  rc::prop("adev(a y + c) = |a| adev(y)", [] {
    const auto seed = *rc::gen::arbitrary<unsigned>();
    const double a = *rc::gen::element(-3.0, -0.5, 0.25, 2.0);
    const double c = *rc::gen::element(-100.0, 0.0, 9.81);
    std::mt19937 gen(seed);
    std::normal_distribution<double> unit;
    Eigen::VectorXd y(64);
    for (Eigen::Index i = 0; i < y.size(); ++i) y(i) = unit(gen);
    const Eigen::VectorXd z = (a * y).array() + c;
    const auto p = legkit::imu::allanDeviation(y, 0.01, {1, 3, 16});
    const auto q = legkit::imu::allanDeviation(z, 0.01, {1, 3, 16});
    for (std::size_t i = 0; i < p.size(); ++i)
      RC_ASSERT(std::abs(q[i].adev - std::abs(a) * p[i].adev) <= 1e-9 * std::abs(a) * p[i].adev);
  });
}

// Known densities through the kit's sensor model, 2000 s at 100 Hz (the random walk is made as
// strong as the white noise per root second, so that its +1/2 line starts at a few seconds and the
// record holds both lines). Each recovered density must lie within three of its line's own
// relative standard errors (from the points' confidence bounds) of the truth, and those errors
// must be small enough for the check to mean something.
TEST_CASE("noise densities and random walks recovered from a simulated IMU", "[allan]") {
  legkit::model::ImuNoise truth;
  truth.gyro_noise_density = 0.004;     // rad/s/sqrt(Hz), the Go2's
  truth.accel_noise_density = 0.04;     // m/s^2/sqrt(Hz), the Go2's
  truth.gyro_bias_random_walk = 0.004;  // rad/s^2/sqrt(Hz)
  truth.accel_bias_random_walk = 0.04;  // m/s^3/sqrt(Hz)
  const auto seed = GENERATE(1u, 2u);
  const legkit::imu::AllanAnalysis analysis =
      legkit::imu::analyseImu(simulatedImu(truth, 0.01, 200000, seed));
  const double white[2] = {truth.gyro_noise_density, truth.accel_noise_density};
  const double walk[2] = {truth.gyro_bias_random_walk, truth.accel_bias_random_walk};
  for (int a = 0; a < 6; ++a) {
    INFO("seed " << seed << ", axis " << legkit::imu::ImuRecording::kAxisNames[a]);
    const legkit::imu::AxisNoise& axis = analysis.axes[a];
    REQUIRE(axis.white.found());
    REQUIRE(axis.random_walk.found());
    CHECK(axis.white.relative_error < 0.02);
    CHECK(axis.random_walk.relative_error < 0.2);
    CHECK(axis.white.level == Approx(white[a / 3]).epsilon(3.0 * axis.white.relative_error));
    CHECK(axis.random_walk.level ==
          Approx(walk[a / 3]).epsilon(3.0 * axis.random_walk.relative_error));
    // The -1/2 line stops before the +1/2 one starts.
    CHECK(axis.white.tau_last < axis.random_walk.tau_first);
    // No flicker in the model: the minimum lies near the crossing of the two lines,
    // tau = sqrt(3) N / K = 1.7 s, where sigma = sqrt(2 N K / sqrt(3)).
    CHECK(axis.tau_min > 0.5);
    CHECK(axis.tau_min < 6.0);
  }
  const legkit::model::ImuNoise noise = analysis.noise();
  CHECK(noise.gyro_noise_density >= analysis.axes[0].white.level);
  CHECK(noise.gyro_noise_density ==
        std::max({analysis.axes[0].white.level, analysis.axes[1].white.level,
                  analysis.axes[2].white.level}));
  CHECK(noise.accel_bias_random_walk ==
        std::max({analysis.axes[3].random_walk.level, analysis.axes[4].random_walk.level,
                  analysis.axes[5].random_walk.level}));
}

TEST_CASE("white noise alone has no +1/2 line and no minimum", "[allan]") {
  legkit::model::ImuNoise noise;
  noise.gyro_bias_random_walk = 0.0;
  noise.accel_bias_random_walk = 0.0;
  const legkit::imu::AllanAnalysis analysis =
      legkit::imu::analyseImu(simulatedImu(noise, 0.01, 50000, 3));
  for (const legkit::imu::AxisNoise& axis : analysis.axes) {
    CHECK(axis.white.found());
    CHECK_FALSE(axis.random_walk.found());
  }
  const legkit::model::ImuNoise out = analysis.noise();
  CHECK(std::isnan(out.gyro_bias_random_walk));
  CHECK(std::isnan(out.accel_bias_random_walk));
  CHECK(out.gyro_noise_density == Approx(0.004).epsilon(0.05));
}

TEST_CASE("recordings are read in both formats, with their sample period", "[allan]") {
  legkit::test::ScratchFolder dir("allan_read");
  SECTION("plain t,gx,gy,gz,ax,ay,az with comments before the header") {
    std::string text = "# a raw recording\nt,gx,gy,gz,ax,ay,az\r\n";
    for (int k = 0; k < 20; ++k)
      text += std::to_string(5.0 + 0.01 * k + (k % 2 ? 0.002 : 0.0)) + ", " + std::to_string(k) +
              ",2,3,4,5,9.81\r\n";
    writeText(dir.path / "plain.csv", text);
    const auto rec = legkit::imu::readImuRecording((dir.path / "plain.csv").string());
    REQUIRE(rec.samples() == 20);
    CHECK(rec.tau0 == Approx((0.19 + 0.002) / 19));  // (t_last - t_first) / (N - 1)
    CHECK(rec.axis(0)(7) == 7.0);
    CHECK(rec.axis(5)(19) == 9.81);
  }
  SECTION("the kit's log") {
    legkit::io::Log log;
    for (int k = 0; k < 12; ++k) {
      legkit::io::LogRow row;
      row.t = 0.002 * k;
      row.gyro = Eigen::Vector3d(0.1, 0.2, k);
      row.acc = Eigen::Vector3d(0.0, 0.0, 9.8);
      log.rows.push_back(row);
    }
    legkit::io::writeLog((dir.path / "kit.csv").string(), log);
    const auto rec = legkit::imu::readImuRecording((dir.path / "kit.csv").string());
    REQUIRE(rec.samples() == 12);
    CHECK(rec.tau0 == Approx(0.002));
    CHECK(rec.axis(2)(11) == 11.0);
    CHECK(rec.axis(5)(0) == 9.8);
  }
}

TEST_CASE("bad recordings name the file, line and column", "[allan]") {
  legkit::test::ScratchFolder dir("allan_bad");
  const std::string header = "t,gx,gy,gz,ax,ay,az\n";
  const auto file = [&](const std::string& name, const std::string& text) {
    writeText(dir.path / name, text);
    return dir.path / name;
  };
  const auto rows = [](int n, double dt) {
    std::string s;
    for (int k = 0; k < n; ++k) s += std::to_string(dt * k) + ",0,0,0,0,0,0\n";
    return s;
  };
  const std::string gap = readError(file("gap.csv", header + rows(5, 0.01) + "0.07,0,0,0,0,0,0\n"));
  CHECK_THAT(gap, Catch::Contains("gap.csv:7: column 't': a gap"));
  const std::string back =
      readError(file("back.csv", header + rows(3, 0.01) + "0.01,0,0,0,0,0,0\n"));
  CHECK_THAT(back, Catch::Contains("back.csv:5: column 't': time does not increase"));
  const std::string word =
      readError(file("word.csv", header + rows(3, 0.01) + "0.03,0,0,x,0,0,0\n"));
  CHECK_THAT(word, Catch::Contains("word.csv:5: column 'gz': expected a finite number, found 'x'"));
  const std::string nan = readError(file("nan.csv", header + "0,0,0,0,0,nan,0\n"));
  CHECK_THAT(nan, Catch::Contains("nan.csv:2: column 'ay'"));
  const std::string few = readError(file("few.csv", header + "0,0,0,0,0,0\n"));
  CHECK_THAT(few, Catch::Contains("few.csv:2: expected 7 fields"));
  const std::string many = readError(file("many.csv", header + "0,0,0,0,0,0,0,0\n"));
  CHECK_THAT(many, Catch::Contains("many.csv:2: more than 7 fields"));
  const std::string one = readError(file("one.csv", header + "0,0,0,0,0,0,0\n"));
  CHECK_THAT(one, Catch::Contains("fewer than two samples"));
  // Anything but the plain header goes to the kit's log reader, which names what it misses.
  const std::string other = readError(file("other.csv", "time,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,0\n"));
  CHECK_THAT(other, Catch::Contains("other.csv:1"));
  CHECK_THAT(readError(dir.path / "missing.csv"), Catch::Contains("cannot open"));
  // Too short for a curve: an exception, not a crash.
  const auto rec =
      legkit::imu::readImuRecording(file("short.csv", header + rows(5, 0.01)).string());
  CHECK_THROWS_AS(legkit::imu::analyseImu(rec), std::invalid_argument);
}
