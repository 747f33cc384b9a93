// The runner checks every estimate: an estimator that throws, or hands back NaN, or a covariance
// NEES cannot use, fails alone, with the row, its time and "file:line"; the runner never throws.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "estimation/imu/dead_reckoning_estimator.hpp"
#include "estimation/leg_odometry/leg_odometry_estimator.hpp"
#include "eval/log_run.hpp"
#include "eval/monte_carlo.hpp"
#include "eval/runner.hpp"
#include "io/log_reader.hpp"
#include "io/log_writer.hpp"

using namespace legkit;

namespace {

enum class Planted { kNone, kThrow, kNan, kIndefinite };

// Stands still, and at row `at` does what `fault` says.
class Faulty final : public Estimator {
 public:
  Faulty(Planted fault, std::size_t at) : fault_(fault), at_(at) {}
  std::string name() const override { return "faulty"; }
  void reset(const EstimateSample& x0) override {
    x_ = x0;
    k_ = 0;
  }
  void step(const StepInput& in) override {
    x_.t = in.t;
    if (k_++ != at_) return;
    if (fault_ == Planted::kThrow) throw std::runtime_error("planted failure");
    if (fault_ == Planted::kNan) x_.p.x() = std::nan("");
  }
  EstimateSample estimate() const override { return x_; }
  std::optional<BaseCovariance> covariance() const override {
    BaseCovariance c;
    if (fault_ == Planted::kIndefinite && k_ > at_) c.P(4, 4) = -1.0;
    return c;
  }

 private:
  Planted fault_;
  std::size_t at_;
  std::size_t k_ = 0;
  EstimateSample x_;
};

// A 20-row log with ground truth, read back through the reader so that it knows its source.
io::Log smallLog() {
  io::Log log;
  log.layout.ground_truth = true;
  log.comments = {"one comment"};
  for (int k = 0; k < 20; ++k) {
    io::LogRow row;
    row.t = 1e-3 * k;
    row.acc.z() = 9.81;
    log.rows.push_back(row);
  }
  std::stringstream file;
  io::writeLog(file, log);
  return io::readLog(file, "small.csv");
}

}  // namespace

TEST_CASE("runner: a healthy run has no failure", "[eval]") {
  const io::Log log = smallLog();
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics());
  Faulty e(Planted::kNone, 0);
  const eval::RunResult r = eval::runOnLog(e, log, frontend, eval::initialState(log));
  CHECK_FALSE(r.failed());
  CHECK(r.ok());
  CHECK(r.trajectory.size() == 20);
  CHECK(r.nees.size() == 20);
}

TEST_CASE("runner: a failing estimator is stopped and located, never thrown through", "[eval]") {
  const io::Log log = smallLog();
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics());
  struct Case {
    Planted fault;
    const char* what;
  };
  for (const Case& c : {Case{Planted::kThrow, "planted failure"}, Case{Planted::kNan, "non-finite"},
                        Case{Planted::kIndefinite, "negative variance"}}) {
    INFO(c.what);
    Faulty e(c.fault, 7);
    eval::RunResult r;
    REQUIRE_NOTHROW(r = eval::runOnLog(e, log, frontend, eval::initialState(log)));
    REQUIRE(r.failed());
    CHECK_FALSE(r.ok());
    CHECK(r.failure->row == 7);
    CHECK(r.failure->t == 0.007);
    // One comment line, the header, then rows 0..: row 7 is on line 10.
    CHECK(r.failure->where == "small.csv:10");
    CHECK_THAT(r.failure->what, Catch::Matchers::Contains(c.what));
    CHECK(r.trajectory.size() == 7);
    CHECK_THAT(eval::describe(*r.failure), Catch::Matchers::StartsWith("small.csv:10, t = 0.007"));
  }
}

TEST_CASE("runner: health counts are described in words", "[eval]") {
  Health h;
  CHECK(eval::describe(h).empty());
  h.record(legkit::Fault::kGyroRange, 1.0);
  h.record(legkit::Fault::kGyroRange, 2.0);
  h.record(legkit::Fault::kStateUnhealthy, 3.0);
  CHECK(eval::describe(h) == "2 gyro out of range, 1 state unhealthy (recovered)");
}

TEST_CASE("monte carlo: a run whose estimator fails stops the study with its name and row",
          "[eval]") {
  eval::MonteCarloOptions options;
  options.runs = 2;
  options.threads = 1;
  options.sim.duration = 0.2;
  const std::vector<eval::NamedEstimator> estimators = {
      {"faulty", [] { return std::make_unique<Faulty>(Planted::kThrow, 5); }}};
  try {
    eval::monteCarlo(options, estimators);
    FAIL("monteCarlo did not throw");
  } catch (const eval::RunFailedError& e) {
    CHECK_THAT(e.what(), Catch::Matchers::Contains("faulty failed in run 0 (seed 1)"));
    CHECK_THAT(e.what(), Catch::Matchers::Contains("(row 5): threw: planted failure"));
  }
}

namespace {

// Says every foot is down, and throws at sample `at` (as a detector does for a negative dt).
class Stubborn final : public contact::ContactDetector {
 public:
  explicit Stubborn(std::size_t at) : at_(at) {}
  std::string name() const override { return "stubborn"; }
  void reset() override { k_ = 0; }
  contact::ContactEstimate update(const contact::ContactSignals& s) override {
    if (k_++ == at_) throw std::invalid_argument("stubborn: planted at t = " + std::to_string(s.t));
    contact::ContactEstimate e;
    e.t = s.t;
    e.num_feet = s.num_feet;
    for (int foot = 0; foot < s.num_feet; ++foot) e.feet[foot] = {true, 1.0};
    return e;
  }

 private:
  std::size_t at_;
  std::size_t k_ = 0;
};

}  // namespace

TEST_CASE("runner: on a contact pipeline, the same failure rules; flags and slip per row",
          "[eval]") {
  const io::Log log = smallLog();  // joints at zero, no contact columns
  PipelineOptions options;
  options.contact = "stubborn";
  ContactPipeline pipeline(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, options,
                           std::make_unique<Stubborn>(100));
  Faulty healthy(Planted::kNone, 0);
  eval::RunResult r = eval::runOnLog(healthy, log, pipeline, eval::initialState(log));
  CHECK(r.ok());
  CHECK(r.contact_source == "stubborn");
  CHECK(r.slip_reaction == "none");
  REQUIRE(r.detected_contact.size() == 20);
  REQUIRE(r.slip.size() == 20);
  CHECK(r.detected_contact[3][0]);
  CHECK(r.detected_contact[3][3]);
  CHECK_FALSE(r.detected_contact[3][4]);  // beyond the log's four feet
  // The estimator's failure, as on the front end.
  Faulty failing(Planted::kThrow, 7);
  r = eval::runOnLog(failing, log, pipeline, eval::initialState(log));
  REQUIRE(r.failed());
  CHECK(r.failure->row == 7);
  CHECK(r.trajectory.size() == 7);
  CHECK(r.detected_contact.size() == 7);
  // The pipeline's (its detector's) failure is the run's, located the same way.
  ContactPipeline throwing(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, options,
                           std::make_unique<Stubborn>(4));
  REQUIRE_NOTHROW(r = eval::runOnLog(healthy, log, throwing, eval::initialState(log)));
  REQUIRE(r.failed());
  CHECK(r.failure->row == 4);
  CHECK(r.failure->where == "small.csv:7");
  CHECK_THAT(r.failure->what, Catch::Matchers::Contains("threw: stubborn: planted"));
  CHECK(r.trajectory.size() == 4);
}

TEST_CASE("runner: a log without truth whose first accelerometer reading is zero starts level",
          "[eval]") {
  io::Log log;
  log.layout.joints = true;
  log.rows.resize(2);
  log.rows[1].t = 0.001;
  log.rows[1].acc = Eigen::Vector3d(0.0, 0.0, 9.81);
  const EstimateSample x0 = eval::initialState(log);  // row 0 reads a = 0: free fall, no tilt
  CHECK(x0.q.coeffs().allFinite());
  CHECK(x0.q.angularDistance(Eigen::Quaterniond::Identity()) == 0.0);
  log.rows[0].acc = Eigen::Vector3d(0.0, 9.81, 0.0);  // lying on its side: rolled 90 deg
  CHECK(eval::initialState(log).q.angularDistance(
            Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()))) < 1e-12);
}

namespace {

// `seconds` of a robot standing level at 1 kHz whose gyro reads the constant bias b plus a
// +-1e-3 rad/s square wave (noise with a zero mean over every even number of rows), with truth.
io::Log standingLog(double seconds, const Eigen::Vector3d& b) {
  io::Log log;
  log.layout.ground_truth = true;
  for (int k = 0; k <= static_cast<int>(seconds * 1000.0); ++k) {
    io::LogRow row;
    row.t = 1e-3 * k;
    row.gyro = b + Eigen::Vector3d::Constant(k % 2 == 0 ? 1e-3 : -1e-3);
    row.acc.z() = 9.81;
    log.rows.push_back(row);
  }
  return log;
}

}  // namespace

TEST_CASE("runner: the still start gives the window's mean rate; a log that moves has none",
          "[eval]") {
  const Eigen::Vector3d b(0.002, -0.003, -0.0057);  // the iCub's turn-on bias is of this size
  engineering::StationaryInitParams params;         // a 2 s window
  const std::optional<eval::StillStart> still = eval::stillStart(standingLog(4.0, b), params);
  REQUIRE(still);
  CHECK((still->b_g - b).norm() < 1e-6);
  CHECK(still->t_end == Approx(params.duration).margin(0.01));
  CHECK_THAT(eval::describeStart(still),
             Catch::Matchers::StartsWith("gyro bias [0.00200, -0.00300, -0.00570] rad/s"));
  CHECK_THAT(eval::describeStart(std::nullopt), Catch::Matchers::Contains("starts at zero"));
  // runStart: what the settings ask for. Zero (the default) reads no window and says nothing.
  Settings settings;
  const eval::RunStart zero = eval::runStart(standingLog(4.0, b), settings);
  CHECK_FALSE(zero.still);
  CHECK_FALSE(zero.gyroBias());
  CHECK(zero.note.empty());
  settings.gyro_bias_start = GyroBiasStart::kStillWindow;
  const eval::RunStart window = eval::runStart(standingLog(4.0, b), settings);
  REQUIRE(window.gyroBias());
  CHECK(*window.gyroBias() == still->b_g);
  CHECK(window.note == eval::describeStart(still));

  io::Log turning = standingLog(4.0, b);  // turns back and forth at 1 rad/s, 1 Hz, from row 0
  for (io::LogRow& row : turning.rows) row.gyro.z() += std::sin(2.0 * M_PI * row.t);
  params.max_wait = 3.0;
  CHECK_FALSE(eval::stillStart(turning, params));
  // runStart asked for the window on that log: none, zero bias, and a line that says so.
  settings.initialisation.max_wait = 3.0;
  const eval::RunStart none = eval::runStart(turning, settings);
  CHECK_FALSE(none.still);
  CHECK_FALSE(none.gyroBias());
  CHECK(none.note == eval::describeStart(std::nullopt));
}

TEST_CASE("runner: a run given the still start's gyro bias integrates the rate less it", "[eval]") {
  const Eigen::Vector3d b(0.0, 0.0, -0.0057);
  const io::Log log = standingLog(4.0, b);
  const LogFrontend frontend(log.layout, model::QuadrupedKinematics());
  const std::optional<eval::StillStart> still = eval::stillStart(log, {});
  REQUIRE(still);
  const auto yawAtEnd = [&](const std::optional<Eigen::Vector3d>& b_g) {
    imu::DeadReckoningEstimator e;
    const eval::RunResult r = eval::runOnLog(e, log, frontend, eval::initialState(log), 0.05, b_g);
    REQUIRE(r.ok());
    return r.trajectory.back().q.angularDistance(Eigen::Quaterniond::Identity());
  };
  CHECK(yawAtEnd(std::nullopt) == Approx(0.0057 * 4.0).epsilon(0.01));  // the bias integrated
  CHECK(yawAtEnd(still->b_g) < 1e-5);                                   // the bias removed
  leg_odometry::LegOdometryEstimator lo;
  const eval::RunResult r =
      eval::runOnLog(lo, log, frontend, eval::initialState(log), 0.05, still->b_g);
  REQUIRE(r.ok());
  CHECK(r.trajectory.back().q.angularDistance(Eigen::Quaterniond::Identity()) < 1e-5);
}
