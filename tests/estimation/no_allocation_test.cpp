// "No heap allocation per filter step", checked for every estimator of the kit across what
// changes the shape of a filter's problem: touchdowns and lift-offs of every gait (one, two and
// four feet down), feet given slots on a hexapod, and inputs the contract rejects (an IMU sample
// beyond range, a foot beyond range). This program counts every heap allocation it makes
// (tests/allocation_counter.hpp).
#include <catch2/catch.hpp>

#include <memory>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "estimation/estimators.hpp"
#include "estimation/invariant/invariant_ekf.hpp"
#include "estimation/log_frontend.hpp"
#include "hexapod_inputs.hpp"
#include "sim/simulator.hpp"

namespace legkit {
namespace {

// `duration` seconds of a simulated scenario as estimator inputs (built before counting starts).
test::Recording scenario(const std::string& name, double duration) {
  sim::SimOptions options;
  options.scenario = sim::scenarioByName(name);
  options.duration = duration;
  const io::Log log = sim::simulate(options).log;
  test::Recording r;
  r.steps = LogFrontend(log.layout, model::QuadrupedKinematics()).inputs(log);
  const io::LogRow& first = log.rows.front();
  r.x0 = {first.t, first.gt_q, first.gt_v, first.gt_p};
  return r;
}

// The number of stance-set changes (touchdowns plus lift-offs) in the inputs.
int contactChanges(const std::vector<StepInput>& steps) {
  int changes = 0;
  unsigned previous = 0;
  for (const StepInput& in : steps) {
    unsigned mask = 0;
    for (const ContactMeasurement& c : in.stance()) mask |= 1u << c.foot;
    changes += __builtin_popcount(mask ^ previous);
    previous = mask;
  }
  return changes;
}

// Heap allocations made by reset() and every step() of `steps`, on a filter built beforehand.
long allocationsOfRun(Estimator& e, const test::Recording& inputs) {
  const long before = test::allocationCount();
  e.reset(inputs.x0);
  for (const StepInput& in : inputs.steps) e.step(in);
  return test::allocationCount() - before;
}

}  // namespace

TEST_CASE("no allocation: every estimator, through the touchdowns and lift-offs of every gait",
          "[estimator]") {
  for (const char* gait : {"walk", "trot", "bound", "turn"}) {
    const test::Recording inputs = scenario(gait, 2.0);
    REQUIRE(contactChanges(inputs.steps) >= 8);  // the gait really steps in 2 s
    for (const std::string& name : estimatorNames()) {
      INFO(name << " on " << gait);
      const std::unique_ptr<Estimator> e = makeEstimator(name);
      CHECK(allocationsOfRun(*e, inputs) == 0);
      CHECK(e->estimate().t == inputs.steps.back().t);  // it did run
      CHECK(e->health().healthy());
    }
  }
}

TEST_CASE("no allocation: rejected samples and feet given slots", "[estimator]") {
  test::Recording inputs = scenario("trot", 1.0);
  const std::size_t n = inputs.steps.size();
  inputs.steps[n / 3].imu.w_m.x() = 100.0;  // beyond the gyro's range: not admitted
  StepInput& far = inputs.steps[n / 2];
  REQUIRE(far.num_contacts > 0);
  far.contacts[0].p_body.z() = -50.0;  // a foot beyond reach: dropped (a copy of the input)
  // Six feet on a hexapod, standing then on alternating tripods: the four-foot filters give the
  // stance feet slots (a second copy of the input whenever a foot is moved to another slot).
  const test::Recording hexapod = test::hexapodTripods(500, 2001);
  for (const std::string& name : estimatorNames()) {
    INFO(name);
    const std::unique_ptr<Estimator> e = makeEstimator(name);
    CHECK(allocationsOfRun(*e, inputs) == 0);
    CHECK(e->health()[Fault::kGyroRange] == 1);
    CHECK(e->health()[Fault::kContactRange] == 1);
    CHECK(allocationsOfRun(*e, hexapod) == 0);
    CHECK(e->estimate().t == hexapod.steps.back().t);
  }
}

TEST_CASE("no allocation: the InEKF's other discretisation and the reference's touchdown",
          "[estimator]") {
  const test::Recording inputs = scenario("trot", 1.0);
  invariant::InvariantEkfParams first_order;
  first_order.discretisation = invariant::inekf::Discretisation::kFirstOrder;
  invariant::InvariantEkfParams reference = first_order;
  reference.touchdown_attitude = invariant::inekf::TouchdownAttitude::kPredicted;
  for (const invariant::InvariantEkfParams& params : {first_order, reference}) {
    invariant::InvariantEkf filter(params);
    CHECK(allocationsOfRun(filter, inputs) == 0);
    CHECK(filter.numFeet() == inputs.steps.back().num_contacts);  // it did run
  }
}

}  // namespace legkit
