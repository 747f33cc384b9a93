// Closed loop: the controller walks on an estimate instead of the truth (exercise 57.X). A source
// that reports the true state with its velocity off by b makes the robot's real speed off by
// about -b: the controller tracks the command with what it believes.
#include <catch2/catch.hpp>
#include <limits>

#include "sim/physics_simulator.hpp"

using namespace legkit;

namespace {

// The truth from the row's ground-truth columns, velocity shifted by `bias`, after `delay` rows.
class BiasedTruth : public sim::BaseStateSource {
 public:
  BiasedTruth(const Eigen::Vector3d& bias, int delay) : bias_(bias), delay_(delay) {}
  bool update(const io::LogRow& row, sim::BaseEstimate& out) override {
    ++calls_;
    if (calls_ <= delay_) return false;
    out.R = row.gt_q.toRotationMatrix();
    out.p = row.gt_p;
    out.v = row.gt_v + bias_;
    return true;
  }
  int calls() const { return calls_; }

 private:
  Eigen::Vector3d bias_;
  int delay_;
  int calls_ = 0;
};

// The truth until t = 1 s, then a velocity that is not a number: the torques are NaN.
class BrokenSource : public sim::BaseStateSource {
 public:
  bool update(const io::LogRow& row, sim::BaseEstimate& out) override {
    out.R = row.gt_q.toRotationMatrix();
    out.p = row.gt_p;
    out.v = row.gt_v;
    if (row.t >= 1.0) out.v.x() = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
};

sim::PhysicsResult trot(sim::BaseStateSource* source) {
  sim::PhysicsOptions o = sim::PhysicsOptions::forScenario("physics-trot");
  o.duration = 5.0;
  o.closed_loop = source;
  return sim::simulatePhysics(o);
}

}  // namespace

TEST_CASE("Closed loop on the truth walks like the open loop", "[sim][physics]") {
  const sim::PhysicsResult open = trot(nullptr);
  BiasedTruth truth(Eigen::Vector3d::Zero(), 500);
  const sim::PhysicsResult closed = trot(&truth);
  CHECK(truth.calls() == static_cast<int>(closed.log.rows.size()));
  REQUIRE_FALSE(closed.status.fell);
  // Only the gyro and encoder noise (the sensors the closed loop uses) separate the two.
  CHECK(std::abs(closed.mean_velocity.x() - open.mean_velocity.x()) < 0.02);
  CHECK(io::exactlyEqual(closed.log.rows[400], open.log.rows[400]));  // before the first estimate
  CHECK_FALSE(io::exactlyEqual(closed.log.rows[1500], open.log.rows[1500]));
}

TEST_CASE("A velocity estimate 0.1 m/s too fast slows the robot by about 0.1 m/s",
          "[sim][physics]") {
  const sim::PhysicsResult open = trot(nullptr);
  BiasedTruth biased(Eigen::Vector3d(0.1, 0.0, 0.0), 0);
  const sim::PhysicsResult closed = trot(&biased);
  REQUIRE_FALSE(closed.status.fell);
  const double change = closed.mean_velocity.x() - open.mean_velocity.x();
  INFO("mean forward speed " << open.mean_velocity.x() << " -> " << closed.mean_velocity.x());
  CHECK(change == Approx(-0.1).margin(0.03));
}

TEST_CASE("MuJoCo's reset on bad numbers is a failed run, never a silent log", "[sim][physics]") {
  // MuJoCo 2.2.2 zeroes a NaN ctrl (and resets mjData on a bad qpos/qvel/qacc) with only a warning.
  BrokenSource broken;
  sim::PhysicsOptions o = sim::PhysicsOptions::forScenario("physics-trot");
  o.duration = 2.0;
  o.closed_loop = &broken;
  const sim::PhysicsResult r = sim::simulatePhysics(o);
  REQUIRE(r.status.fell);  // the failure path every caller already handles
  CHECK(r.status.diverged);
  CHECK_THAT(r.status.reason, Catch::Contains("MuJoCo reset the simulation: bad ctrl at t = 1.0"));
  CHECK(r.status.time == Approx(1.0).margin(2e-3));
  REQUIRE_FALSE(r.log.rows.empty());
  CHECK(r.log.rows.back().t < r.status.time);
  CHECK(r.log.rows.back().gt_feet[0].normal_force > 0.0);  // not a reset state
}
