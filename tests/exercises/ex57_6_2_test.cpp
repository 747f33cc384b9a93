// Exercise 57.6.2: the Newton step by hand and at the kit's optimum, the whole fit against the
// kit's trainer (estimation/contact/logistic_training.hpp) on physics features, and the trained
// model run by the kit's LogisticContactDetector on another physics run, scored against the truth.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "estimation/contact/logistic_training.hpp"
#include "estimation/log_frontend.hpp"
#include "eval/contact_scores.hpp"
#include "eval/contact_training.hpp"
#include "ex57_6_2.hpp"
#include "exercises/exercise_check.hpp"
#include "sim/physics_simulator.hpp"

using legkit::contact::ContactFeatures;
using legkit::contact::LogisticModel;

namespace {

// 8 s of the physics 2 Hz trot (1 s standing, then 0.5 m/s) from a seed.
legkit::io::Log physicsTrot(unsigned seed) {
  legkit::sim::PhysicsOptions options = legkit::sim::PhysicsOptions::forScenario("physics-trot");
  options.duration = 8.0;
  options.seed = seed;
  return legkit::sim::simulatePhysics(options).log;
}

legkit::contact::GaitSchedule trotSchedule() {
  return legkit::eval::plannedGait(legkit::sim::physicsScenarioByName("physics-trot"));
}

// The training set: every foot and row of one run, features as the kit's detector computes them
// (eval::appendTrainingSamples: base velocity and attitude from the truth), label = true contact.
struct TrainingSet {
  std::vector<ContactFeatures> samples;
  std::vector<bool> labels;
};
const TrainingSet& trainingSet() {
  static const TrainingSet set = [] {
    TrainingSet s;
    const legkit::contact::GaitSchedule gait = trotSchedule();
    legkit::eval::appendTrainingSamples(physicsTrot(5762), &gait,
                                        legkit::model::QuadrupedKinematics{}, s.samples, s.labels);
    return s;
  }();
  return set;
}

}  // namespace

TEST_CASE("57.6.2 one Newton step by hand", "[ex57.6.2][hint 1]") {
  // Two samples on the first feature, x = (1, +-1, 0, 0), labels 1 and 0, from w = 0: p = 1/2,
  // W = 1/4, g = (0, -1, 0, 0), H = diag(1/2 + 0, 1/2 + l2, l2, l2); with l2 = 1/2 the step is
  // w+ = (0, 1, 0, 0).
  const std::vector<Eigen::Vector4d> x = {Eigen::Vector4d(1.0, 1.0, 0.0, 0.0),
                                          Eigen::Vector4d(1.0, -1.0, 0.0, 0.0)};
  const std::vector<bool> y = {true, false};
  const Eigen::Vector4d w1 = ex57_6_2::newtonStep(Eigen::Vector4d::Zero(), x, y, 0.5);
  REQUIRE_NEAR(w1, Eigen::Vector4d(0.0, 1.0, 0.0, 0.0), 1e-12);
  // The bias is not penalised: four samples x = (1, 0, 0, 0), three positive, from w = 0:
  // sum (p - y) = 2 - 3 = -1 and sum W = 1, so w_0 moves by +1 whatever l2 (the log-odds log 3 is
  // where the steps converge).
  const std::vector<Eigen::Vector4d> ones(4, Eigen::Vector4d(1.0, 0.0, 0.0, 0.0));
  const std::vector<bool> three = {true, true, true, false};
  const Eigen::Vector4d b1 = ex57_6_2::newtonStep(Eigen::Vector4d::Zero(), ones, three, 10.0);
  REQUIRE_NEAR(b1, Eigen::Vector4d(1.0, 0.0, 0.0, 0.0), 1e-12);
}

TEST_CASE("57.6.2 the kit's optimum is a fixed point of your step", "[ex57.6.2][hint 1]") {
  // Synthetic samples: force ~ 60 N in contact, ~ 3 N in swing, with overlap; speed and phase
  // likewise. The kit's trainer fits them; at its weights your step must not move.
  std::mt19937 gen(5762);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<ContactFeatures> samples;
  std::vector<bool> labels;
  for (int k = 0; k < 400; ++k) {
    const bool c = k % 3 != 0;
    ContactFeatures f;
    f.force = (c ? 40.0 : 10.0) + 15.0 * n(gen);
    f.foot_speed = (c ? 0.05 : 0.6) + 0.3 * std::abs(n(gen));
    f.phase = (c ? 0.3 : 0.8) + 0.2 * n(gen);
    samples.push_back(f);
    labels.push_back(c);
  }
  legkit::contact::TrainingOptions options;
  options.l2 = 0.1;
  const LogisticModel kit = legkit::contact::trainLogistic(samples, labels, options);
  std::vector<Eigen::Vector4d> x;
  for (const ContactFeatures& f : samples) {
    const Eigen::Vector3d raw(f.force, f.foot_speed, f.phase);
    Eigen::Vector4d xn;
    xn << 1.0, (raw - kit.mean).cwiseQuotient(kit.scale);
    x.push_back(xn);
  }
  const Eigen::Vector4d w = ex57_6_2::newtonStep(kit.w, x, labels, 0.1);
  REQUIRE_NEAR(w, kit.w, 1e-8);
}

TEST_CASE("57.6.2 your fit is the kit's on physics features", "[ex57.6.2][hint 2]") {
  const TrainingSet& set = trainingSet();
  const LogisticModel mine = ex57_6_2::trainContactProbability(set.samples, set.labels, 1e-3);
  legkit::contact::TrainingOptions options;
  options.l2 = 1e-3;
  const LogisticModel kit = legkit::contact::trainLogistic(set.samples, set.labels, options);
  INFO(set.samples.size() << " samples; the kit's w = (" << kit.w.transpose() << ")");
  const Eigen::Vector3d mean = mine.mean, scale = mine.scale;
  REQUIRE_NEAR(mean, kit.mean, 1e-9 * kit.mean.norm());
  REQUIRE_NEAR(scale, kit.scale, 1e-9 * kit.scale.norm());
  const Eigen::Vector4d w = mine.w;
  REQUIRE_NEAR(w, kit.w, 1e-6 * (1.0 + kit.w.norm()));
}

TEST_CASE("57.6.2 your model detects contact on another physics run", "[ex57.6.2][hint 3]") {
  const TrainingSet& set = trainingSet();
  const LogisticModel model = ex57_6_2::trainContactProbability(set.samples, set.labels, 1e-3);
  // Another run (seed 5763), through the kit's detector with the planned gait and a perfect base
  // estimate as feedback, scored from t = 0.5 s on.
  const legkit::io::Log log = physicsTrot(5763);
  const legkit::LogFrontend frontend(log.layout, legkit::model::QuadrupedKinematics{});
  legkit::contact::LogisticContactDetector detector(model, trotSchedule());
  std::vector<double> t;
  std::vector<legkit::eval::FootFlags> detected, truth;
  // Calibration: per bin of p_c (tenths), samples and how many are truly in contact.
  std::array<double, 10> in_bin{}, true_in_bin{};
  double brier = 0.0;
  int unusable = 0;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const legkit::io::LogRow& row = log.rows[k];
    const double dt = k == 0 ? 0.0 : row.t - log.rows[k - 1].t;
    const legkit::contact::ContactEstimate e =
        detector.update(frontend.signals(row, dt, legkit::eval::truthFeedback(row)));
    if (row.t < 0.5) continue;
    legkit::eval::FootFlags d_k{}, t_k{};
    for (int i = 0; i < 4; ++i) {
      unusable += e.feet[i].usable() ? 0 : 1;
      d_k[i] = e.feet[i].contact;
      t_k[i] = row.gt_feet[i].contact;
      const double p = e.feet[i].probability;
      const int bin = std::min(9, static_cast<int>(p * 10.0));
      in_bin[bin] += 1.0;
      true_in_bin[bin] += t_k[i] ? 1.0 : 0.0;
      brier += (p - (t_k[i] ? 1.0 : 0.0)) * (p - (t_k[i] ? 1.0 : 0.0));
    }
    t.push_back(row.t);
    detected.push_back(d_k);
    truth.push_back(t_k);
  }
  brier /= 4.0 * static_cast<double>(t.size());
  const legkit::eval::ContactScores s = legkit::eval::scoreContacts(t, detected, truth, 4);
  const double low = true_in_bin[0] / in_bin[0], high = true_in_bin[9] / in_bin[9];
  INFO("F1 " << s.f1 << " (precision " << s.precision << ", recall " << s.recall
             << "); touchdown delay " << s.touchdown_delay_mean << " ms, lift-off "
             << s.liftoff_delay_mean << " ms; chatter " << s.chatter_per_min
             << " /min; Brier score " << brier << "; truly in contact: " << low
             << " of the samples with p_c < 0.1 (" << in_bin[0] << "), " << high
             << " of those with p_c >= 0.9 (" << in_bin[9] << ")");
  REQUIRE(unusable == 0);
  REQUIRE_ABOVE(s.f1, 0.95);
  REQUIRE_BELOW(brier, 0.05);
  REQUIRE_BELOW(low, 0.05);
  REQUIRE_ABOVE(high, 0.95);
}
