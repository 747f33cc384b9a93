// The physics log is an ordinary log: it passes the strict reader's round trip, it is
// deterministic from its seed, its IMU rows mean what sim/simulator.hpp's mean (integrating a row
// from t_k gives the truth at t_k+1), its contact and force columns are the physics' own, a fall
// is reported with its time and reason, and bad options are refused by name.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "io/log_reader.hpp"
#include "io/log_writer.hpp"
#include "model/imu_model.hpp"
#include "sim/physics_simulator.hpp"

using namespace legkit;

namespace {

sim::PhysicsOptions shortRun(const std::string& name, double duration) {
  sim::PhysicsOptions o = sim::PhysicsOptions::forScenario(name);
  o.duration = duration;
  return o;
}

}  // namespace

TEST_CASE("A physics trot log reads back exactly through the strict reader",
          "[sim][physics][log]") {
  const sim::PhysicsResult run = sim::simulatePhysics(shortRun("physics-trot", 2.5));
  REQUIRE(run.log.rows.size() == 2500);
  CHECK(run.log.layout.joints);
  CHECK(run.log.layout.torque);
  CHECK(run.log.layout.force);
  CHECK(run.log.layout.contact);
  CHECK(run.log.layout.ground_truth);
  CHECK(run.log.layout.contact_truth);
  std::stringstream file;
  io::writeLog(file, run.log);
  io::ReadOptions strict;
  strict.max_gap = 1.5e-3;
  const io::Log back = io::readLog(file, "physics.csv", strict);
  CHECK(back.layout == run.log.layout);
  CHECK(back.comments == run.log.comments);
  REQUIRE(back.rows.size() == run.log.rows.size());
  for (std::size_t k = 0; k < back.rows.size(); ++k) {
    REQUIRE(io::exactlyEqual(back.rows[k], run.log.rows[k]));
  }
}

TEST_CASE("Without ground truth the log has neither truth group and still reads back",
          "[sim][physics][log]") {
  sim::PhysicsOptions o = shortRun("physics-stand", 0.5);
  o.ground_truth = false;
  const sim::PhysicsResult run = sim::simulatePhysics(o);
  CHECK_FALSE(run.log.layout.ground_truth);
  CHECK_FALSE(run.log.layout.contact_truth);
  std::stringstream file;
  io::writeLog(file, run.log);
  const std::size_t at = file.str().find("\nt,");  // the header, after the comments
  REQUIRE(at != std::string::npos);
  const std::string header = file.str().substr(at + 1);
  CHECK(header.substr(0, header.find('\n')).find("gt_") == std::string::npos);
  const io::Log back = io::readLog(file, "physics.csv");
  CHECK(back.layout == run.log.layout);
  REQUIRE(back.rows.size() == run.log.rows.size());
  CHECK(io::exactlyEqual(back.rows.back(), run.log.rows.back()));
  CHECK(back.rows.back().contact[0]);  // the contact flags stay (the true contacts)
}

TEST_CASE("Same options, identical log; another seed, other noise on the same motion",
          "[sim][physics]") {
  sim::PhysicsOptions o = shortRun("physics-trot", 1.5);
  const sim::PhysicsResult a = sim::simulatePhysics(o);
  const sim::PhysicsResult b = sim::simulatePhysics(o);
  REQUIRE(a.log.rows.size() == b.log.rows.size());
  for (std::size_t k = 0; k < a.log.rows.size(); ++k) {
    REQUIRE(io::exactlyEqual(a.log.rows[k], b.log.rows[k]));
  }
  o.seed = 2;
  const sim::PhysicsResult c = sim::simulatePhysics(o);
  CHECK_FALSE(io::exactlyEqual(a.log.rows[100], c.log.rows[100]));
  CHECK(a.log.rows[100].gt_p == c.log.rows[100].gt_p);  // the noise does not steer the robot
}

TEST_CASE("Noise-free rows: integrating row k's IMU from the truth at t_k gives the truth at t_k+1",
          "[sim][physics]") {
  sim::PhysicsOptions o = shortRun("physics-trot", 3.0);
  o.noiseless();
  const sim::PhysicsResult run = sim::simulatePhysics(o);
  const double dt = 1.0 / o.rate;
  double worst_v = 0.0, worst_R = 0.0;
  for (std::size_t k = 0; k + 1 < run.log.rows.size(); ++k) {
    const io::LogRow& r = run.log.rows[k];
    const io::LogRow& next = run.log.rows[k + 1];
    const Eigen::Matrix3d R = r.gt_q.toRotationMatrix();
    // v_{k+1} = v_k + (R_k a_m + g) dt: exact, a_m is the mean acceleration of the interval.
    const Eigen::Vector3d v = r.gt_v + (R * r.acc + model::gravity()) * dt;
    worst_v = std::max(worst_v, (v - next.gt_v).norm());
    // R_{k+1} = R_k Exp(w dt), w the mean body rate: to second order in the rate change.
    const Eigen::Matrix3d R1 =
        R * Eigen::AngleAxisd(r.gyro.norm() * dt, r.gyro.normalized()).toRotationMatrix();
    worst_R =
        std::max(worst_R, Eigen::AngleAxisd(R1.transpose() * next.gt_q.toRotationMatrix()).angle());
  }
  CHECK(worst_v < 1e-9);
  CHECK(worst_R < 1e-6);
}

TEST_CASE("Contact flags are the true contacts; a noise-free force sensor reads the true force",
          "[sim][physics]") {
  sim::PhysicsOptions o = shortRun("physics-trot", 2.5);
  o.noiseless();
  const sim::PhysicsResult run = sim::simulatePhysics(o);
  int changes = 0;
  for (std::size_t k = 0; k < run.log.rows.size(); ++k) {
    const io::LogRow& r = run.log.rows[k];
    for (int leg = 0; leg < 4; ++leg) {
      const io::FootTruth& f = r.gt_feet[leg];
      REQUIRE(r.contact[leg] == f.contact);
      REQUIRE(f.contact == (f.normal_force > sim::kContactThreshold));
      REQUIRE(r.force[leg] == std::min(f.normal_force, o.force_sensor.saturation));
      if (!f.contact) REQUIRE(f.slip_speed == 0.0);
      if (k > 0) changes += r.contact[leg] != run.log.rows[k - 1].contact[leg];
    }
  }
  CHECK(changes > 8);  // the trot lifts and plants feet
}

TEST_CASE("A fall ends the run: the log stops before it, the status says when and why",
          "[sim][physics]") {
  sim::PhysicsOptions o = shortRun("physics-stand", 4.0);
  o.scenario.pushes = {{1.0, 0.5, {0.0, 400.0, 0.0}}};  // far beyond what standing can take
  const sim::PhysicsResult run = sim::simulatePhysics(o);
  REQUIRE(run.status.fell);
  CHECK(run.status.time > 1.0);
  CHECK(run.status.time < 4.0);
  CHECK_FALSE(run.status.reason.empty());
  REQUIRE_FALSE(run.log.rows.empty());
  CHECK(run.log.rows.back().t < run.status.time);
  CHECK(run.log.rows.size() == run.bias.size());
}

TEST_CASE("Bad options are refused, naming the option and the value", "[sim][physics]") {
  const auto refused = [](const sim::PhysicsOptions& o, const std::string& what) {
    try {
      sim::simulatePhysics(o);
    } catch (const std::invalid_argument& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(what) != std::string::npos);
      return;
    }
    FAIL("no exception for " << what);
  };
  CHECK_THROWS_WITH(sim::physicsScenarioByName("physics-moonwalk"),
                    Catch::Contains("physics-moonwalk") && Catch::Contains("physics-trot"));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  sim::PhysicsOptions o = shortRun("physics-stand", 1.0);
  o.scenario.terrain.friction = 0.0;
  refused(o, "terrain.friction = 0");
  o.scenario.terrain.friction = 2.5;
  refused(o, "terrain.friction = 2.5");
  o = shortRun("physics-ice", 1.0);
  o.scenario.terrain.patches[0].friction = -0.1;
  refused(o, "patch friction = -0.1");
  o = shortRun("physics-slope", 1.0);
  o.scenario.terrain.slope_angle = 0.4;
  refused(o, "terrain.slope_angle = 0.4");
  o.scenario.terrain.slope_angle = nan;
  refused(o, "terrain.slope_angle = nan");
  o = shortRun("physics-slope", 1.0);
  o.scenario.terrain.slope_length = 0.0;
  refused(o, "terrain.slope_length = 0");
  o.scenario.terrain.slope_length = -1.0;
  refused(o, "terrain.slope_length = -1");
  o = shortRun("physics-slope", 1.0);
  o.scenario.terrain.slope_start = 99.5;
  refused(o, "terrain.slope_start = 99.5");
  o.scenario.terrain.slope_start = nan;
  refused(o, "terrain.slope_start = nan");
  o = shortRun("physics-push", 1.0);
  o.scenario.pushes[0].force.y() = nan;
  refused(o, "push force");
  o.scenario.pushes[0].force.y() = 600.0;
  refused(o, "push force = 600");
  o = shortRun("physics-stand", 0.0);
  refused(o, "duration = 0");
  o.duration = 4000.0;
  refused(o, "duration = 4000");
  o.duration = 1.0;
  o.rate = 700.0;
  refused(o, "physics_rate = 2000");
  o.rate = 1000.0;
  o.physics_rate = 500.0;
  refused(o, "physics_rate = 500");
}
