// Closed loop: the controller walks on an estimate instead of the truth (exercise 57.X). A source
// that reports the true state with its velocity off by b makes the robot's real speed off by
// about -b: the controller tracks the command with what it believes.
#include <catch2/catch.hpp>

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
