// The settings file (estimation/settings.hpp): the defaults are the estimators' own, a file reads
// back what settingsYaml() wrote, every kind of bad value is refused naming its line and key, and
// a key reaches the filter it configures.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "estimation/estimators.hpp"
#include "estimation/log_frontend.hpp"
#include "estimation/settings.hpp"
#include "eval/runner.hpp"
#include "io/yaml_reader.hpp"
#include "settings_error.hpp"
#include "sim/simulator.hpp"

namespace legkit {
namespace {

using Catch::Matchers::Contains;

constexpr auto errorOf = test::settingsErrorOf;

// A short analytic trot, its inputs on the log's true flags and its initial state.
struct Trot {
  io::Log log;
  std::vector<StepInput> inputs;
  EstimateSample x0;
};

const Trot& trot() {
  static const Trot t = [] {
    sim::SimOptions options;
    options.duration = 1.0;
    Trot r;
    r.log = sim::simulate(options).log;
    r.inputs = LogFrontend(r.log.layout, model::QuadrupedKinematics()).inputs(r.log);
    r.x0 = eval::initialState(r.log);
    return r;
  }();
  return t;
}

// Runs `e` over the trot; its estimate and (for a filter) covariance at the end.
std::pair<EstimateSample, std::optional<BaseCovariance>> runTrot(Estimator& e) {
  e.reset(trot().x0);
  for (const StepInput& in : trot().inputs) e.step(in);
  return {e.estimate(), e.covariance()};
}

}  // namespace

TEST_CASE("settings: the defaults are every estimator's own but a robot's leg noise",
          "[settings]") {
  // The one difference: a robot's stance feet and leg velocities (kRobotStanceDensity,
  // kRobotFootVelocitySigma), not exact legs' (withExactLegs).
  CHECK(defaultSettings().feet.stance_density == kRobotStanceDensity);
  CHECK(defaultSettings().linear_kf.foot_velocity_sigma == kRobotFootVelocitySigma);
  const Settings exact_legs = withExactLegs(defaultSettings());
  for (const std::string& name : estimatorNames()) {
    CAPTURE(name);
    const auto plain = makeEstimator(name);
    const auto configured = makeEstimator(name, exact_legs);
    REQUIRE(configured->name() == name);
    const auto [x_plain, P_plain] = runTrot(*plain);
    const auto [x_conf, P_conf] = runTrot(*configured);
    CHECK(x_conf.p == x_plain.p);  // bit for bit: the defaults do not move `legkit run`
    CHECK(x_conf.v == x_plain.v);
    CHECK(x_conf.q.coeffs() == x_plain.q.coeffs());
    REQUIRE(P_conf.has_value() == P_plain.has_value());
    if (P_conf) CHECK(P_conf->P == P_plain->P);
  }
  CHECK_THROWS_WITH(makeEstimator("no-such", defaultSettings()), Contains("eskf"));
}

TEST_CASE("settings: a key reaches the filter it configures", "[settings]") {
  Settings loud = defaultSettings();
  loud.imu.gyro_noise_density = 1.0;  // 250 times the Go2's [rad/s/sqrt(Hz)]
  const auto quiet_P = *runTrot(*makeEstimator("eskf", defaultSettings())).second;
  const auto loud_P = *runTrot(*makeEstimator("eskf", loud)).second;
  // After 1 s the attitude variance has grown with the gyro noise.
  const double quiet = quiet_P.P.topLeftCorner<3, 3>().trace();
  const double loud_trace = loud_P.P.topLeftCorner<3, 3>().trace();
  INFO("ESKF attitude variance trace after 1 s: " << quiet << " (Go2 gyro), " << loud_trace
                                                  << " (1 rad/s/sqrt(Hz))");
  CHECK(loud_trace > 2.0 * quiet);

  // The priors reach every filter: a confident velocity prior is a smaller velocity variance at
  // reset.
  Settings confident = defaultSettings();
  confident.priors.sigma_velocity = 1e-4;
  for (const char* name : {"linear-kf", "eskf", "invariant-ekf", "tsif"}) {
    CAPTURE(name);
    const auto plain = makeEstimator(name, defaultSettings());
    const auto sure = makeEstimator(name, confident);
    plain->reset(trot().x0);
    sure->reset(trot().x0);
    CHECK(sure->covariance()->P(4, 4) < 0.5 * plain->covariance()->P(4, 4));
  }
}

TEST_CASE("settings: gating reaches every filter with feet", "[settings]") {
  // The trot with every stance foot measured 0.3 m too high for 20 ms: an outlier the gate stops.
  std::vector<StepInput> inputs = trot().inputs;
  for (std::size_t k = 500; k < 520; ++k) {
    for (int i = 0; i < inputs[k].num_contacts; ++i) inputs[k].contacts[i].p_body.z() += 0.3;
  }
  Settings gated_settings = defaultSettings();
  gated_settings.gating.enabled = true;
  for (const char* name : {"linear-kf", "eskf", "invariant-ekf", "tsif"}) {
    CAPTURE(name);
    const auto gatedCount = [&inputs](const std::unique_ptr<Estimator>& e) {
      e->reset(trot().x0);
      for (const StepInput& in : inputs) e->step(in);
      return e->health().count[static_cast<int>(Fault::kGated)];
    };
    CHECK(gatedCount(makeEstimator(name, defaultSettings())) == 0);
    CHECK(gatedCount(makeEstimator(name, gated_settings)) > 0);
  }
}

TEST_CASE("settings: settingsYaml reads back to the same settings", "[settings]") {
  const Settings defaults = defaultSettings();
  const std::string text = settingsYaml(defaults);
  CHECK(settingsYaml(settingsFromYaml(text, "defaults.yaml")) == text);
  CHECK_THAT(text, Contains("gyro_noise_density: 0.004"));
  CHECK_THAT(text, Contains("[rad/s/sqrt(Hz)]"));

  Settings s = defaults;  // a value off its default in every section
  s.imu.accel_bias_random_walk = 1.25e-3;
  s.imu_extrinsic.q_BI =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  s.imu_extrinsic.p_BI = {0.1, -0.02, 0.05};
  s.limits.max_dt = 0.05;
  s.priors.foot_init_sigma = 0.5;
  s.feet.swing_density = 3.0;
  s.linear_kf.use_leg_velocity = false;
  s.linear_kf.foot_velocity_sigma = 0.08;
  s.invariant_ekf.discretisation = invariant::inekf::Discretisation::kFirstOrder;
  s.tsif.iterations = 2;
  s.frontend.foot_point_sigma = 0.01;
  s.robot = {"robot.xml", "trunk", {"FL_foot", "FR \"foot\""}, {"j1", "j2"}};
  s.estimators = {"tsif", "eskf"};
  s.pipeline.contact = "schmitt";
  s.pipeline.slip = slip::SlipReaction::kDrop;
  s.pipeline.soft.min_probability = 0.2;
  s.schmitt.f_high = 40.0;
  s.schmitt.f_low = 15.0;
  s.robot.mass = 20.5;
  s.gating.enabled = true;
  s.initialisation.duration = 3.0;
  s.monitors.velocity_sigma_max = 2.0;
  const std::string changed = settingsYaml(s);
  const Settings back = settingsFromYaml(changed, "changed.yaml");
  CHECK(settingsYaml(back) == changed);
  CHECK(changed != text);
  CHECK(back.imu_extrinsic.q_BI.coeffs() == s.imu_extrinsic.q_BI.coeffs());
  CHECK(back.imu_extrinsic.p_BI == s.imu_extrinsic.p_BI);
  CHECK(back.robot.feet == s.robot.feet);
  CHECK(back.estimators == s.estimators);
  CHECK(back.invariant_ekf.discretisation == invariant::inekf::Discretisation::kFirstOrder);
  CHECK(back.pipeline.slip == slip::SlipReaction::kDrop);
  CHECK(back.linear_kf.use_leg_velocity == false);
  CHECK(back.tsif.iterations == 2);
  CHECK(back.schmitt.f_low == 15.0);
  CHECK_FALSE(back.schmitt.saturation.has_value());  // auto, written and read as auto
  CHECK(back.robot.mass == 20.5);
  CHECK(back.source == "changed.yaml");
}

TEST_CASE("settings: contact forces scale to the robot's weight unless given", "[settings]") {
  const Settings d = defaultSettings();
  const double m_go2 = model::QuadrupedInertia::go2().totalMass();
  CHECK(robotMass(d, nullptr) == m_go2);
  // The built-in Go2 keeps the kit's Go2 design exactly.
  const contact::DetectorContext go2 = detectorContext(d, m_go2, 4);
  const contact::SchmittParams design = contact::go2SchmittParams();
  CHECK(go2.schmitt.f_high == design.f_high);
  CHECK(go2.schmitt.f_low == design.f_low);
  CHECK(go2.schmitt.saturation == design.saturation);
  CHECK(go2.grf.threshold == contact::GrfThresholdParams{}.threshold);
  CHECK(go2.momentum.threshold == contact::MomentumObserverParams{}.threshold);
  // Twice the load a foot: twice the forces (twice the mass on four feet, or the mass on two).
  for (const auto& [mass, feet] : {std::pair{2 * m_go2, 4}, std::pair{m_go2, 2}}) {
    const contact::DetectorContext c = detectorContext(d, mass, feet);
    CHECK(c.schmitt.f_high == Approx(2 * design.f_high).epsilon(1e-14));
    CHECK(c.schmitt.f_low == Approx(2 * design.f_low).epsilon(1e-14));
    CHECK(c.schmitt.saturation == Approx(2 * design.saturation).epsilon(1e-14));
    CHECK(c.schmitt.negative_limit == Approx(2 * design.negative_limit).epsilon(1e-14));
    CHECK(c.schmitt_torque.f_high == Approx(2 * contact::SchmittParams{}.f_high).epsilon(1e-14));
    CHECK(c.grf.threshold == Approx(2 * contact::GrfThresholdParams{}.threshold).epsilon(1e-14));
    CHECK(c.momentum.release ==
          Approx(2 * contact::MomentumObserverParams{}.release).epsilon(1e-14));
    CHECK(c.schmitt.t_on == design.t_on);  // times do not scale
  }
  // What the file gives wins; robot.mass replaces the model's.
  const Settings s = settingsFromYaml(
      "robot:\n  mass: 60\ncontact:\n  schmitt:\n    f_high: 150\n    f_low: 120\n"
      "    saturation: auto\n    t_on: 0.01\n",
      "t.yaml");
  CHECK(robotMass(s, nullptr) == 60.0);
  const contact::DetectorContext c = detectorContext(s, robotMass(s, nullptr), 2);
  CHECK(c.schmitt.f_high == 150.0);
  CHECK(c.schmitt.f_low == 120.0);
  CHECK(c.schmitt.saturation == Approx(design.saturation * (60.0 / 2) / (m_go2 / 4)));
  CHECK(c.schmitt.t_on == 0.01);
  CHECK_THROWS_WITH(detectorContext(d, 0.0, 4), Contains("mass must be positive"));
  CHECK_THROWS_WITH(detectorContext(d, m_go2, 0), Contains("a robot of 0 feet"));
}

TEST_CASE("settings: config/legkit.yaml is what `legkit config --print` writes", "[settings]") {
  std::ifstream in(LEGKIT_SOURCE_DIR "/config/legkit.yaml");
  REQUIRE(in);
  std::ostringstream file;
  file << in.rdbuf();
  CHECK(file.str() == settingsYaml(defaultSettings()));
}

TEST_CASE("settings: keys left out keep their defaults; other spellings", "[settings]") {
  const Settings s = settingsFromYaml(
      "imu:\n  gyro_noise_density: 0.01\n  extrinsic:\n    rotation_rpy_deg: [0, 0, 90]\n"
      "contact:\n  schmitt:\n",
      "t.yaml");
  CHECK(s.imu.gyro_noise_density == 0.01);
  CHECK(s.imu.accel_noise_density == defaultSettings().imu.accel_noise_density);
  CHECK_FALSE(s.schmitt.f_high.has_value());  // auto: the robot's
  CHECK(s.pipeline.contact == "fallback");
  const Eigen::Vector3d x_base = s.imu_extrinsic.q_BI * Eigen::Vector3d::UnitX();
  CHECK(x_base.isApprox(Eigen::Vector3d::UnitY(), 1e-12));  // yaw 90 deg: IMU x is base y
  // A quaternion rounded to 4 digits is normalised.
  const Settings q =
      settingsFromYaml("imu:\n  extrinsic:\n    rotation: [0.7071, 0, 0, 0.7071]\n", "t.yaml");
  CHECK(q.imu_extrinsic.q_BI.norm() == Approx(1.0).epsilon(1e-15));
  CHECK(settingsFromYaml("", "empty.yaml").estimators.empty());
}

TEST_CASE("settings: every bad value names its file, line and key", "[settings]") {
  // Unknown keys, at any depth.
  CHECK_THAT(errorOf("imu:\n  gyro_density: 0.1\n"),
             Contains("t.yaml:2: imu.gyro_density: unknown key") && Contains("gyro_noise_density"));
  CHECK_THAT(errorOf("limits: {}\nimus:\n  x: 1\n"), Contains("t.yaml:2: imus: unknown key"));
  CHECK_THAT(errorOf("contact:\n  schmitt:\n    f_hi: 3\n"),
             Contains("t.yaml:3: contact.schmitt.f_hi: unknown key"));
  // Wrong types.
  CHECK_THAT(errorOf("imu:\n  gyro_noise_density: abc\n"),
             Contains("t.yaml:2: imu.gyro_noise_density: expected a number in [0, 1], got 'abc'"));
  CHECK_THAT(errorOf("imu:\n  gyro_noise_density: \"0.004\"\n"),
             Contains("t.yaml:2: imu.gyro_noise_density: expected a number"));
  CHECK_THAT(errorOf("imu:\n  gyro_noise_density: [1, 2]\n"),
             Contains("t.yaml:2: imu.gyro_noise_density: expected a number"));
  CHECK_THAT(errorOf("gating:\n  enabled: yes\n"),
             Contains("t.yaml:2: gating.enabled: expected true or false"));
  CHECK_THAT(errorOf("tsif:\n  iterations: 1.5\n"),
             Contains("t.yaml:2: tsif.iterations: expected an integer in [1, 2]"));
  CHECK_THAT(errorOf("imu: 3\n"), Contains("t.yaml:1: imu: expected a map"));
  CHECK_THAT(errorOf("- 1\n- 2\n"), Contains("t.yaml:1: expected a map of sections"));
  // Lists of the wrong length.
  CHECK_THAT(errorOf("imu:\n  extrinsic:\n    translation: [0, 1]\n"),
             Contains("t.yaml:3: imu.extrinsic.translation: expected a list of 3 values, got 2"));
  CHECK_THAT(errorOf("imu:\n  extrinsic:\n    rotation: [1, 0, 0]\n"),
             Contains("t.yaml:3: imu.extrinsic.rotation: expected a list of 4 values"));
  CHECK_THAT(errorOf("imu:\n  extrinsic:\n    translation: [0, x, 0]\n"),
             Contains("t.yaml:3: imu.extrinsic.translation[1]: expected a number"));
  // Out of range: negative, a probability outside [0, 1], NaN, inf, absurd but finite.
  CHECK_THAT(
      errorOf("feet:\n  stance_density: -0.001\n"),
      Contains("t.yaml:2: feet.stance_density: expected a number in") && Contains("got -0.001"));
  CHECK_THAT(errorOf("contact:\n  soft:\n    min_probability: 1.5\n"),
             Contains("t.yaml:3: contact.soft.min_probability: expected a number in [0, 1]"));
  CHECK_THAT(errorOf("imu:\n  accel_noise_density: .nan\n"),
             Contains("t.yaml:2: imu.accel_noise_density: expected a number"));
  CHECK_THAT(errorOf("imu:\n  accel_noise_density: nan\n"),
             Contains("t.yaml:2: imu.accel_noise_density: expected a finite number"));
  CHECK_THAT(errorOf("limits:\n  max_dt: .inf\n"), Contains("t.yaml:2: limits.max_dt: expected"));
  CHECK_THAT(errorOf("imu:\n  gyro_noise_density: 1e6\n"),
             Contains("t.yaml:2: imu.gyro_noise_density: expected a number in [0, 1], got 1e6"));
  CHECK_THAT(errorOf("imu:\n  extrinsic:\n    rotation: [1, 0, 0.5, 0]\n"),
             Contains("t.yaml:3: imu.extrinsic.rotation: expected a unit quaternion"));
  // Names: estimators, detectors, enums; repeated names and keys; keys that contradict.
  CHECK_THAT(errorOf("estimators: [eskf, kalman]\n"),
             Contains("t.yaml:1: estimators[1]: expected one of imu-dead-reckoning") &&
                 Contains("got 'kalman'"));
  CHECK_THAT(errorOf("estimators: [eskf, eskf]\n"),
             Contains("t.yaml:1: estimators[1]: 'eskf' is listed twice"));
  CHECK_THAT(errorOf("contact:\n  rolling_foot: true\n  detector: magic\n"),
             Contains("t.yaml:3: contact.detector: expected one of truth,") && Contains("schmitt"));
  CHECK_THAT(
      errorOf("invariant_ekf:\n  discretisation: euler\n"),
      Contains("t.yaml:2: invariant_ekf.discretisation: expected one of exact, first-order"));
  CHECK_THAT(errorOf("gating:\n  enabled: true\n  enabled: false\n"),
             Contains("t.yaml:3: gating.enabled: key given twice"));
  CHECK_THAT(errorOf("contact:\n  schmitt:\n    f_high: 10\n    f_low: 20\n"),
             Contains("t.yaml:3: contact.schmitt: f_low must not exceed f_high"));
  CHECK_THAT(errorOf("contact:\n  schmitt:\n    f_high: 40\n"),
             Contains("t.yaml:3: contact.schmitt: give f_high and f_low together"));
  CHECK_THAT(errorOf("contact:\n  schmitt:\n    f_high: 40\n    f_low: 10\n    saturation: 30\n"),
             Contains("contact.schmitt: saturation must be above f_high"));
  CHECK_THAT(errorOf("contact:\n  schmitt:\n    f_high: automatic\n    f_low: 1\n"),
             Contains("t.yaml:3: contact.schmitt.f_high: expected a number"));
  CHECK_THAT(errorOf("robot:\n  mass: -1\n"), Contains("t.yaml:2: robot.mass: expected a number"));
  CHECK_THAT(
      errorOf("imu:\n  extrinsic:\n    rotation: [1, 0, 0, 0]\n    rotation_rpy_deg: [0, 0, 0]\n"),
      Contains("t.yaml:3: imu.extrinsic: give rotation or rotation_rpy_deg, not both"));
  CHECK_THAT(errorOf("robot:\n  model: go2.xml\n"),
             Contains("t.yaml:2: robot: a robot model needs its base body and its feet"));
  // YAML syntax.
  CHECK_THAT(errorOf("imu:\n  gyro_noise_density: [1, 2\n"), Contains("t.yaml:3: YAML syntax"));
  CHECK_THAT(errorOf("imu:\n gyro: 1\n  x: 2\n"), Contains("t.yaml:3: YAML syntax"));
  // A file that is not there.
  CHECK_THROWS_WITH(loadSettings("/no/such/settings.yaml"),
                    Contains("/no/such/settings.yaml: cannot be read"));
}

}  // namespace legkit
