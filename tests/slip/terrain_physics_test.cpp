// The terrain classifier (estimation/slip/terrain.hpp) on what `legkit study slip` feeds it: the
// invariant EKF on contacts from the recommended fallback chain, the pipeline's slip check against
// the filter's previous estimate, and the ground forces ESTIMATED from the joint torques
// (FootForceFromTorque with that estimate), never the simulator's true forces. Before it, the
// guards for estimated forces (estimatedForceParams) on hand-made streams.
// Figures (10 s, seeds 1-3; print them with `test_terrain_physics -s`): with the guards the dry
// trot has no onset that counts and reads normal from its lower bound (0.25-0.27; true mu 0.6),
// physics-ice-push reads ice (mu_hat 0.107-0.127 from 9-10 onsets, true 0.1), physics-ice (a mu 0.1
// patch under the FR foot's path only) normal (0.374). Without them, on a pipeline that checks a
// foot for slip from its touchdown on (no touchdown settling), the dry trot read ice: mu_hat 0.113
// from 41 onsets flagged 3 ms after touchdown; on that run's samples the guards leave no onset
// and a lower bound of 0.28, normal.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "estimation/contact/detectors.hpp"
#include "estimation/contact/foot_force.hpp"
#include "estimation/contact_pipeline.hpp"
#include "estimation/estimators.hpp"
#include "estimation/slip/terrain.hpp"
#include "eval/contact_training.hpp"
#include "eval/runner.hpp"
#include "model/quadruped.hpp"
#include "model/quadruped_inertia.hpp"
#include "sim/physics_simulator.hpp"

using namespace legkit;  // NOLINT(google-build-using-namespace)

namespace {

constexpr int kFeet = 4;

sim::PhysicsResult simulate(const std::string& scenario, double duration, unsigned seed) {
  sim::PhysicsOptions o = sim::PhysicsOptions::forScenario(scenario);
  o.duration = duration;
  for (const sim::Push& p : o.scenario.pushes)
    o.duration = std::max(o.duration, p.start + p.duration + 1.0);
  o.seed = seed;
  return sim::simulatePhysics(o);
}

// The terrain class at the end of the study's run of `scenario` (its inputs, see above).
slip::TerrainClassifier classify(const sim::PhysicsResult& run, const std::string& scenario,
                                 const slip::TerrainParams& params) {
  const io::Log& log = run.log;
  const sim::PhysicsOptions o = sim::PhysicsOptions::forScenario(scenario);
  contact::DetectorContext context;
  context.gait = eval::plannedGait(o.scenario);
  FrontendNoise noise;
  noise.encoder_angle_sigma = o.encoder_angle_sigma;  // the study's matched front end
  PipelineOptions options;
  options.contact = "fallback";
  ContactPipeline pipeline(log.layout, model::QuadrupedKinematics(), noise, options,
                           contact::makeDetector("fallback", context));
  const std::unique_ptr<Estimator> filter = makeEstimator("invariant-ekf");
  const contact::FootForceFromTorque forces(model::QuadrupedGeometry::go2(),
                                            model::QuadrupedInertia::go2());
  slip::TerrainClassifier terrain(params);
  EstimateSample x = eval::initialState(log);
  filter->reset(x);
  pipeline.reset();
  std::optional<BaseCovariance> P = filter->covariance();
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const io::LogRow& row = log.rows[k];
    const double dt = k == 0 ? 0.0 : row.t - log.rows[k - 1].t;
    filter->step(pipeline.step(row, dt, x, P));
    const contact::BaseFeedback base = contact::feedbackFrom(x);
    const auto f = forces.estimate(pipeline.frontend().signals(row, dt, base));
    terrain.update(pipeline.slipReport(), f.data(), kFeet, dt);
    x = filter->estimate();
    P = filter->covariance();
  }
  return terrain;
}

void print(const std::string& what, const slip::TerrainClassifier& t) {
  std::printf("%s: %s, mu_hat %.3f from %d onsets, lower bound %.3f, stance %.1f s\n", what.c_str(),
              slip::terrainClassName(t.terrain()), t.frictionEstimate(), t.onsets(),
              t.frictionLowerBound(), t.stanceTime());
}

// One foot in stance: slipping or not.
slip::SlipReport stance(bool slipping) {
  slip::SlipReport r;
  r.num_feet = 1;
  r.feet[0].foot = 0;
  r.feet[0].slipping = slipping;
  return r;
}

}  // namespace

TEST_CASE("terrain guards for estimated forces: loaded stance and a slip that holds",
          "[57.7][terrain]") {
  const slip::TerrainParams p = slip::estimatedForceParams();
  CHECK(p.min_loaded_time == Approx(0.03));
  CHECK(p.min_slip_time == Approx(0.005));
  const std::array<Eigen::Vector3d, 1> f = {Eigen::Vector3d(6.0, 8.0, 100.0)};  // ratio 0.1
  const std::array<Eigen::Vector3d, 1> light = {Eigen::Vector3d(1.0, 0.0, 10.0)};
  slip::TerrainClassifier c(p);
  // Touchdown: a slip 10 ms into the stance gives no sample, however long it holds; the held
  // ratio does not count before 30 ms either.
  for (int k = 0; k < 10; ++k) c.update(stance(false), f.data(), 1, 0.001);
  CHECK(c.frictionLowerBound() == 0.0);
  for (int k = 0; k < 10; ++k) c.update(stance(true), f.data(), 1, 0.001);
  CHECK(c.onsets() == 0);
  CHECK(c.slipRate() > 0.0);  // the onset still counts as a slip
  // 30 ms loaded: the held ratio is a lower bound.
  for (int k = 0; k < 20; ++k) c.update(stance(false), f.data(), 1, 0.001);
  CHECK(c.frictionLowerBound() == Approx(0.1));
  // A slip flagged for 4 samples (4 ms) gives nothing; for 5 it gives its onset's ratio.
  for (int k = 0; k < 4; ++k) c.update(stance(true), f.data(), 1, 0.001);
  c.update(stance(false), f.data(), 1, 0.001);
  CHECK(c.onsets() == 0);
  const std::array<Eigen::Vector3d, 1> later = {Eigen::Vector3d(30.0, 40.0, 100.0)};
  c.update(stance(true), f.data(), 1, 0.001);  // onset at 0.1
  for (int k = 0; k < 3; ++k) c.update(stance(true), later.data(), 1, 0.001);
  CHECK(c.onsets() == 0);
  c.update(stance(true), later.data(), 1, 0.001);
  CHECK(c.onsets() == 1);
  CHECK(c.frictionEstimate() == Approx(0.1));  // the ratio at the onset, not at confirmation
  // A light sample or a swing restarts the loaded time.
  c.update(stance(false), light.data(), 1, 0.001);
  c.update(stance(true), f.data(), 1, 0.001);
  for (int k = 0; k < 10; ++k) c.update(stance(true), f.data(), 1, 0.001);
  CHECK(c.onsets() == 1);
  for (int k = 0; k < 40; ++k) c.update(stance(false), f.data(), 1, 0.001);
  c.update(slip::SlipReport{}, f.data(), 1, 0.001);  // swing: the foot is not in the report
  for (int k = 0; k < 10; ++k) c.update(stance(true), f.data(), 1, 0.001);
  CHECK(c.onsets() == 1);
  // Without the guards (the defaults, for exact forces) the same touchdown slip counts at once.
  slip::TerrainClassifier raw;
  raw.update(stance(true), f.data(), 1, 0.001);
  CHECK(raw.onsets() == 1);
  slip::TerrainParams bad = p;
  bad.min_slip_time = -0.001;
  CHECK_THROWS_AS(slip::TerrainClassifier(bad), std::invalid_argument);
}

TEST_CASE("terrain on the study's inputs: the dry trot is normal, the pushed robot on ice is ice",
          "[57.7][terrain][physics][study]") {
  for (const unsigned seed : {1u, 2u, 3u}) {
    INFO("seed " << seed);
    const sim::PhysicsResult trot = simulate("physics-trot", 10.0, seed);
    REQUIRE_FALSE(trot.status.fell);
    // Without the guards (printed): on the pipeline without touchdown settling, the touchdown
    // onsets on estimated forces called dry ground ice (mu_hat 0.11).
    print("physics-trot seed " + std::to_string(seed) + " without guards",
          classify(trot, "physics-trot", {}));
    const slip::TerrainClassifier dry =
        classify(trot, "physics-trot", slip::estimatedForceParams());
    print("physics-trot seed " + std::to_string(seed), dry);
    CHECK(dry.terrain() == slip::TerrainClass::kNormal);  // true mu 0.6
    CHECK(dry.frictionLowerBound() <= 0.6);

    const sim::PhysicsResult push = simulate("physics-ice-push", 10.0, seed);
    REQUIRE_FALSE(push.status.fell);
    const slip::TerrainClassifier ice =
        classify(push, "physics-ice-push", slip::estimatedForceParams());
    print("physics-ice-push seed " + std::to_string(seed), ice);
    CHECK(ice.terrain() == slip::TerrainClass::kIce);  // true mu 0.1 everywhere
    CHECK(ice.frictionEstimate() == Approx(0.1).margin(0.05));
    CHECK(ice.onsets() >= 5);
  }
  // The ice patch under one foot's path: the other feet hold at mu 0.6 (as with the true forces,
  // tests/slip/slip_physics_test.cpp).
  const sim::PhysicsResult patch = simulate("physics-ice", 10.0, 1);
  const slip::TerrainClassifier mixed =
      classify(patch, "physics-ice", slip::estimatedForceParams());
  print("physics-ice seed 1", mixed);
  CHECK(mixed.terrain() == slip::TerrainClass::kNormal);
}
