// The logistic contact probability (estimation/contact/logistic_contact.hpp) and its training
// (logistic_training.hpp), without a simulator: hand values of the features and of p_c, the
// detector's problems and hysteresis, no allocation per update; the training recovers the weights
// that generated a synthetic labelled set, is deterministic, drops a constant or switched-off
// feature, and refuses degenerate input with std::invalid_argument.
#include <rapidcheck.h>
#include <rapidcheck/catch.h>
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "allocation_counter.hpp"
#include "estimation/contact/logistic_contact.hpp"
#include "estimation/contact/logistic_training.hpp"

using namespace legkit::contact;
namespace test = legkit::test;

namespace {

// Raw-unit generating model: p = sigma(b + a_F F + a_v |v| + a_phi phi).
struct RawWeights {
  double b, a_F, a_v, a_phi;
};

double sigma(double z) {
  return 1.0 / (1.0 + std::exp(-z));
}

// The learned model's weights in raw units (undoing the scaling).
RawWeights rawWeights(const LogisticModel& m) {
  RawWeights r{m.w[0], m.w[1] / m.scale[0], m.w[2] / m.scale[1], m.w[3] / m.scale[2]};
  r.b -= r.a_F * m.mean[0] + r.a_v * m.mean[1] + r.a_phi * m.mean[2];
  return r;
}

// n samples: force uniform in [0, 150] N, foot speed in [0, 1.5] m/s, phase in [0, 1), labels
// drawn from the generating model (fixed seed).
void synthetic(const RawWeights& g, int n, std::vector<ContactFeatures>& x, std::vector<bool>& y) {
  std::mt19937 gen(20261123);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < n; ++k) {
    ContactFeatures f;
    f.force = 150.0 * u(gen);
    f.foot_speed = 1.5 * u(gen);
    f.phase = u(gen);
    x.push_back(f);
    y.push_back(u(gen) < sigma(g.b + g.a_F * f.force + g.a_v * f.foot_speed + g.a_phi * f.phase));
  }
}

ContactSignals oneFoot(double force, double speed_x) {
  ContactSignals s;
  s.num_feet = 1;
  s.dt = 0.001;
  s.feet[0].force = force;
  s.feet[0].has_kinematics = true;
  s.base.valid = true;
  s.base.v = Eigen::Vector3d(speed_x, 0.0, 0.0);
  return s;
}

}  // namespace

TEST_CASE("logistic contact: features and probability by hand", "[contact][logistic]") {
  ContactSignals s = oneFoot(42.0, 1.0);
  s.gyro = Eigen::Vector3d(0.0, 0.0, 1.0);
  s.feet[0].p_body = Eigen::Vector3d(0.2, 0.0, -0.3);
  s.feet[0].v_body = Eigen::Vector3d(0.0, 0.1, 0.0);
  // v + R (omega x p + v_body) = (1, 0, 0) + (0, 0.2, 0) + (0, 0.1, 0)
  ContactFeatures x = contactFeatures(s, 0, nullptr);
  CHECK(x.force == 42.0);
  CHECK(x.foot_speed == Approx(std::sqrt(1.09)));
  CHECK(x.phase == 0.0);
  GaitSchedule g;  // 0.5 s, foot 0 offset 0: at t = 0.6 the phase is 0.2
  s.t = 0.6;
  CHECK(contactFeatures(s, 0, &g).phase == Approx(0.2));

  LogisticModel m;
  m.w = Eigen::Vector4d(-1.0, 2.0, -3.0, 0.0);
  m.mean = Eigen::Vector3d(40.0, 0.5, 0.0);
  m.scale = Eigen::Vector3d(10.0, 0.25, 1.0);
  x.foot_speed = 0.25;
  // z = -1 + 2 (42 - 40) / 10 - 3 (0.25 - 0.5) / 0.25 = -1 + 0.4 + 3 = 2.4
  CHECK(contactProbability(m, x) == Approx(sigma(2.4)));
  x.phase = std::nan("");  // unused by the model: no effect
  CHECK(contactProbability(m, x) == Approx(sigma(2.4)));
  x.force = std::nan("");
  CHECK(std::isnan(contactProbability(m, x)));
}

TEST_CASE("logistic contact detector: p_c, hysteresis, problems, no allocation",
          "[contact][logistic]") {
  LogisticModel m;
  m.w = Eigen::Vector4d(0.0, 1.0, -1.0, 0.0);  // z = F / 10 - |v| / 0.1
  m.scale = Eigen::Vector3d(10.0, 0.1, 1.0);
  LogisticContactDetector d(m);  // hysteresis 0.4: on above 0.9, off below 0.1
  CHECK(d.name() == "probabilistic");
  const auto p = [&](double f, double v) { return d.update(oneFoot(f, v)).feet[0]; };
  FootContact c = p(20.0, 0.1);  // z = 2 - 1 = 1: p = 0.73, not enough to touch down
  REQUIRE(c.usable());
  CHECK(c.probability == Approx(sigma(1.0)));
  CHECK_FALSE(c.contact);
  CHECK(c.force == 20.0);
  CHECK(p(30.0, 0.0).contact);  // z = 3: p = 0.95
  c = p(0.0, 0.1);              // p = sigma(-1) = 0.27: inside the band, stays in contact
  CHECK(c.probability == Approx(sigma(-1.0)));
  CHECK(c.contact);
  CHECK_FALSE(p(0.0, 0.3).contact);  // p = sigma(-3) = 0.05
  CHECK_FALSE(p(0.0, 0.0).contact);  // 0.5: stays out
  LogisticContactDetector plain(m, std::nullopt, LogisticParams{0.0});
  CHECK(plain.update(oneFoot(20.0, 0.1)).feet[0].contact);  // p_c > 0.5
  CHECK_FALSE(plain.update(oneFoot(0.0, 0.1)).feet[0].contact);
  CHECK_THROWS_AS(LogisticContactDetector(m, std::nullopt, LogisticParams{0.5}),
                  std::invalid_argument);
  d.reset();

  CHECK(std::string(p(std::nan(""), 0.0).problem) == "force is NaN");
  ContactSignals s = oneFoot(30.0, 0.0);
  s.feet[0].has_kinematics = false;
  CHECK(std::string(d.update(s).feet[0].problem) == "no leg kinematics");
  s = oneFoot(30.0, 0.0);
  s.base.valid = false;
  CHECK(std::string(d.update(s).feet[0].problem) == "no base estimate");
  s = oneFoot(30.0, std::nan(""));
  CHECK(std::string(d.update(s).feet[0].problem) == "foot speed not finite");
  s.num_feet = 0;
  CHECK_THROWS_AS(d.update(s), std::invalid_argument);

  // A model that does not use the force runs without a force sensor.
  LogisticModel no_force = m;
  no_force.w[1] = 0.0;
  LogisticContactDetector d2(no_force);
  s = oneFoot(std::nan(""), 0.0);
  CHECK(d2.update(s).feet[0].usable());
  CHECK(std::isnan(d2.update(s).feet[0].force));

  // A model that uses the phase needs a schedule.
  LogisticModel with_phase = m;
  with_phase.w[3] = -1.0;
  CHECK_THROWS_AS(LogisticContactDetector(with_phase), std::invalid_argument);
  CHECK_NOTHROW(LogisticContactDetector(with_phase, GaitSchedule{}));
  LogisticModel bad = m;
  bad.scale[0] = 0.0;
  CHECK_THROWS_AS(LogisticContactDetector(bad), std::invalid_argument);

  s = oneFoot(30.0, 0.0);
  s.num_feet = 4;
  for (int i = 1; i < 4; ++i) s.feet[i] = s.feet[0];
  d.update(s);
  const long before = test::allocationCount();
  for (int k = 0; k < 100; ++k) d.update(s);
  CHECK(test::allocationCount() == before);
}

TEST_CASE("logistic contact detector: its p_c is contactProbability's, in [0, 1], rising with F",
          "[contact][logistic]") {
  rc::prop("random models and readings", [] {
    const auto real = [](int lo, int hi) {  // a double in [lo, hi] on a grid of 0.001
      return *rc::gen::inRange(1000 * lo, 1000 * hi + 1) / 1000.0;
    };
    LogisticModel m;
    m.w = Eigen::Vector4d(real(-5, 5), real(0, 5), real(-5, 5), 0.0);
    m.mean = Eigen::Vector3d(real(0, 100), real(0, 1), 0.0);
    m.scale = Eigen::Vector3d(real(1, 50), real(1, 2), 1.0);
    const double force = real(0, 150), speed = real(0, 2);
    LogisticContactDetector d(m);
    const FootContact c = d.update(oneFoot(force, speed)).feet[0];
    RC_ASSERT(c.usable());
    const double p = contactProbability(m, contactFeatures(oneFoot(force, speed), 0, nullptr));
    RC_ASSERT(std::abs(c.probability - p) < 1e-12);
    RC_ASSERT(c.probability >= 0.0);
    RC_ASSERT(c.probability <= 1.0);
    const double p_more = d.update(oneFoot(force + 10.0, speed)).feet[0].probability;
    RC_ASSERT(p_more >= c.probability);
  });
}

TEST_CASE("trainLogistic recovers the generating weights of a synthetic set",
          "[contact][logistic]") {
  const RawWeights truth{-2.0, 0.08, -4.0, -1.5};
  std::vector<ContactFeatures> x;
  std::vector<bool> y;
  synthetic(truth, 40000, x, y);
  const LogisticModel m = trainLogistic(x, y);
  const RawWeights r = rawWeights(m);
  INFO("b " << r.b << " a_F " << r.a_F << " a_v " << r.a_v << " a_phi " << r.a_phi);
  // The maximum-likelihood estimate's standard errors at 40000 samples are a few percent (measured:
  // within 2 %).
  CHECK(r.b == Approx(truth.b).epsilon(0.1));
  CHECK(r.a_F == Approx(truth.a_F).epsilon(0.05));
  CHECK(r.a_v == Approx(truth.a_v).epsilon(0.05));
  CHECK(r.a_phi == Approx(truth.a_phi).epsilon(0.1));
  // And the probability it gives agrees with the generating one everywhere on the grid.
  double worst = 0.0;
  for (double f = 0.0; f <= 150.0; f += 15.0)
    for (double v = 0.0; v <= 1.5; v += 0.15)
      for (double phi = 0.0; phi < 1.0; phi += 0.1) {
        ContactFeatures q;
        q.force = f;
        q.foot_speed = v;
        q.phase = phi;
        const double p_true = sigma(truth.b + truth.a_F * f + truth.a_v * v + truth.a_phi * phi);
        worst = std::max(worst, std::abs(contactProbability(m, q) - p_true));
      }
  CHECK(worst < 0.03);

  // Deterministic: the same set gives the same weights, bit for bit.
  const LogisticModel again = trainLogistic(x, y);
  CHECK(again.w == m.w);
  CHECK(again.mean == m.mean);
  CHECK(again.scale == m.scale);
}

TEST_CASE("trainLogistic: switched-off and constant features get weight 0", "[contact][logistic]") {
  std::vector<ContactFeatures> x;
  std::vector<bool> y;
  synthetic({-2.0, 0.08, -4.0, 0.0}, 5000, x, y);
  TrainingOptions o;
  o.use_force = false;
  const LogisticModel no_force = trainLogistic(x, y, o);
  CHECK_FALSE(no_force.usesForce());
  CHECK(no_force.usesFootSpeed());
  for (ContactFeatures& f : x) f.phase = 0.0;  // no gait schedule: phase always 0
  const LogisticModel m = trainLogistic(x, y);
  CHECK_FALSE(m.usesPhase());
  CHECK(m.usesForce());
  CHECK_NOTHROW(LogisticContactDetector(m));  // so it needs no schedule
}

TEST_CASE("trainLogistic refuses degenerate input", "[contact][logistic]") {
  std::vector<ContactFeatures> x;
  std::vector<bool> y;
  synthetic({-2.0, 0.08, -4.0, -1.5}, 1000, x, y);
  CHECK_THROWS_AS(trainLogistic({}, {}), std::invalid_argument);
  CHECK_THROWS_AS(trainLogistic(x, std::vector<bool>(10, true)), std::invalid_argument);
  CHECK_THROWS_WITH(trainLogistic(x, std::vector<bool>(x.size(), true)),
                    Catch::Contains("every label is 'contact'"));
  CHECK_THROWS_WITH(trainLogistic(x, std::vector<bool>(x.size(), false)),
                    Catch::Contains("every label is 'no contact'"));
  std::vector<ContactFeatures> nan_x = x;
  nan_x[17].foot_speed = std::nan("");
  CHECK_THROWS_WITH(trainLogistic(nan_x, y), Catch::Contains("foot_speed of sample 17"));
  TrainingOptions o;
  o.use_foot_speed = false;
  CHECK_NOTHROW(trainLogistic(nan_x, y, o));  // the NaN feature is not used
  o.use_force = o.use_phase = false;
  CHECK_THROWS_AS(trainLogistic(x, y, o), std::invalid_argument);
  TrainingOptions bad;
  bad.l2 = -1.0;
  CHECK_THROWS_AS(trainLogistic(x, y, bad), std::invalid_argument);
}
