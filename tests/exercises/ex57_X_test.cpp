// Exercise 57.X: the FR foot on the ice patch (physics-ice), the slip seen by the kit's contact
// pipeline, and the estimate with and without slip handling, recomputed here with the kit.
#include <catch2/catch.hpp>
#include <cmath>

#include "estimation/contact_pipeline.hpp"
#include "estimation/estimators.hpp"
#include "ex57_X.hpp"
#include "exercises/exercise_check.hpp"
#include "sim/physics_simulator.hpp"

using legkit::slip::SlipReaction;

namespace {

// 7 s of physics-ice (seed 5790): 2 Hz trot at 0.5 m/s, the FR foot's path on ice (mu 0.1) from
// x = 1 m, the naive controller (it believes mu 0.6).
const legkit::io::Log& iceLog() {
  static const legkit::io::Log log = [] {
    legkit::sim::PhysicsOptions options = legkit::sim::PhysicsOptions::forScenario("physics-ice");
    options.duration = 7.0;
    options.seed = 5790;
    return legkit::sim::simulatePhysics(options).log;
  }();
  return log;
}

// The kit's run, written out: the same pipeline and estimator, its velocity RMS error.
double kitVelocityRmse(const std::string& name, SlipReaction reaction) {
  const legkit::io::Log& log = iceLog();
  legkit::PipelineOptions options;
  options.slip = reaction;
  legkit::ContactPipeline pipeline(log.layout, legkit::model::QuadrupedKinematics{},
                                   legkit::FrontendNoise{}, options);
  const std::unique_ptr<legkit::Estimator> filter = legkit::makeEstimator(name);
  legkit::EstimateSample x0;
  x0.t = log.rows[0].t;
  x0.q = log.rows[0].gt_q;
  x0.v = log.rows[0].gt_v;
  x0.p = log.rows[0].gt_p;
  filter->reset(x0);
  double sum_sq = 0.0;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const double dt = k == 0 ? 0.0 : log.rows[k].t - log.rows[k - 1].t;
    filter->step(pipeline.step(log.rows[k], dt, filter->estimate(), filter->covariance()));
    sum_sq += (filter->estimate().v - log.rows[k].gt_v).squaredNorm();
  }
  return std::sqrt(sum_sq / static_cast<double>(log.rows.size()));
}

const legkit::sim::FrictionPatch& icePatch() {
  static const legkit::sim::FrictionPatch ice =
      legkit::sim::physicsScenarioByName("physics-ice").terrain.patches.at(0);
  return ice;
}

}  // namespace

TEST_CASE("57.X the slip on the ice is seen within 10 ms", "[ex57.X][hint 1]") {
  const ex57_X::IceRun run =
      ex57_X::runOnIce(iceLog(), icePatch(), "invariant-ekf", SlipReaction::kNone);
  // The first true slip on the ice, found here: FR in contact, on the patch, faster than 0.1 m/s.
  const legkit::model::QuadrupedKinematics kin;
  double first = -1.0;
  for (const legkit::io::LogRow& row : iceLog().rows) {
    const legkit::io::FootTruth& foot = row.gt_feet[1];
    const Eigen::Vector3d at = row.gt_p + row.gt_q * kin.footPosition(1, row.q.segment<3>(3));
    if (foot.contact && foot.slip_speed > 0.1 && at.x() >= icePatch().min.x() &&
        at.x() <= icePatch().max.x() && at.y() >= icePatch().min.y() &&
        at.y() <= icePatch().max.y()) {
      first = row.t;
      break;
    }
  }
  INFO("first true slip on the ice " << run.first_true_slip << " s, detected at "
                                     << run.first_detection << " s");
  REQUIRE(first > 0.0);
  REQUIRE_NEAR(run.first_true_slip, first, 1e-12);
  REQUIRE(run.first_detection >= run.first_true_slip);
  REQUIRE_BELOW(run.first_detection - run.first_true_slip, 0.010);
}

TEST_CASE("57.X slip handling: the estimate with and without", "[ex57.X][hint 2]") {
  const ex57_X::IceRun none =
      ex57_X::runOnIce(iceLog(), icePatch(), "invariant-ekf", SlipReaction::kNone);
  const ex57_X::IceRun drop =
      ex57_X::runOnIce(iceLog(), icePatch(), "invariant-ekf", SlipReaction::kDrop);
  const ex57_X::IceRun inflate =
      ex57_X::runOnIce(iceLog(), icePatch(), "invariant-ekf", SlipReaction::kInflate);
  INFO("invariant-ekf on 7 s of physics-ice: velocity RMS error "
       << none.velocity_rmse << " m/s without slip handling, " << inflate.velocity_rmse
       << " inflating R, " << drop.velocity_rmse << " dropping the foot; final position error "
       << none.position_error << ", " << inflate.position_error << ", " << drop.position_error
       << " m");
  REQUIRE_NEAR(none.velocity_rmse, kitVelocityRmse("invariant-ekf", SlipReaction::kNone), 1e-12);
  REQUIRE_NEAR(drop.velocity_rmse, kitVelocityRmse("invariant-ekf", SlipReaction::kDrop), 1e-12);
  REQUIRE_BELOW(drop.velocity_rmse, 0.8 * none.velocity_rmse);
  REQUIRE_BELOW(inflate.velocity_rmse, 0.8 * none.velocity_rmse);
}

TEST_CASE("57.X the naive controller on the estimate, with and without slip handling",
          "[ex57.X][hint 3]") {
  // 10 s of physics-ice, seed 5790: the controller on the truth, then on your PipelineEstimator
  // (invariant-ekf) in closed loop, without slip handling and dropping the sliding foot.
  legkit::io::LogLayout layout;  // what the physics simulator writes
  layout.joints = layout.torque = layout.force = layout.contact = true;
  layout.ground_truth = layout.contact_truth = true;
  ex57_X::PipelineEstimator none(layout, "invariant-ekf", SlipReaction::kNone);
  ex57_X::PipelineEstimator drop(layout, "invariant-ekf", SlipReaction::kDrop);
  const auto run = [](legkit::sim::BaseStateSource* source) {
    legkit::sim::PhysicsOptions options = legkit::sim::PhysicsOptions::forScenario("physics-ice");
    options.seed = 5790;
    options.closed_loop = source;
    return legkit::sim::simulatePhysics(options).status;
  };
  const legkit::sim::PhysicsStatus on_truth = run(nullptr);
  const legkit::sim::PhysicsStatus on_none = run(&none);
  const legkit::sim::PhysicsStatus on_drop = run(&drop);
  INFO("the naive controller on the ice falls at "
       << on_truth.time << " s on the truth (" << on_truth.reason << "), at " << on_none.time
       << " s on the invariant-ekf without slip handling (" << on_none.reason << "), at "
       << on_drop.time << " s with the sliding foot dropped (" << on_drop.reason << ")");
  REQUIRE(on_truth.fell);
  REQUIRE(on_none.fell);
  REQUIRE(on_drop.fell);
  // The estimate's error brings the fall a second or more forward, slip handling or not: the
  // estimator cannot make an infeasible force plan feasible.
  REQUIRE_BELOW(on_none.time, on_truth.time - 1.0);
  REQUIRE_BELOW(on_drop.time, on_truth.time - 1.0);
}
