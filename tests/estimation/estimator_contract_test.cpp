// The Estimator contract (estimation/estimator.hpp), checked for every estimator of the kit on the
// same inputs: first sample, dt = 0, gaps, out-of-range IMU and contacts, invalid input, and the
// recovery of a state that is no longer physical. Plus the health guard's checks on their own.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "estimation/estimators.hpp"
#include "estimation/foot_slots.hpp"
#include "estimation/health_guard.hpp"
#include "estimation/log_frontend.hpp"
#include "hexapod_inputs.hpp"
#include "sim/simulator.hpp"

namespace legkit {
namespace {

// 3 s of the default trot (touchdowns and lift-offs), as estimator inputs, and its initial state.
struct Trot {
  std::vector<StepInput> inputs;
  EstimateSample x0;
};

const Trot& trot() {
  static const Trot t = [] {
    sim::SimOptions options;
    options.duration = 3.0;
    const io::Log log = sim::simulate(options).log;
    Trot r;
    r.inputs = LogFrontend(log.layout, model::QuadrupedKinematics()).inputs(log);
    const io::LogRow& first = log.rows.front();
    r.x0 = {first.t, first.gt_q, first.gt_v, first.gt_p};
    return r;
  }();
  return t;
}

bool finite(const EstimateSample& x) {
  return std::isfinite(x.t) && x.q.coeffs().allFinite() && x.v.allFinite() && x.p.allFinite();
}

bool same(const EstimateSample& a, const EstimateSample& b) {
  return a.q.coeffs() == b.q.coeffs() && a.v == b.v && a.p == b.p;
}

// Equal up to the rounding of a restart (the attitude goes through one more conversion).
bool close(const EstimateSample& a, const EstimateSample& b) {
  return a.q.angularDistance(b.q) < 1e-12 && (a.v - b.v).norm() < 1e-12 &&
         (a.p - b.p).norm() < 1e-12;
}

// Runs inputs[0..n) through e after a reset, checking after each step that the estimate is
// finite and, for a filter, that the covariance is finite with a positive diagonal.
void run(Estimator& e, const std::vector<StepInput>& inputs, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k) {
    e.step(inputs[k]);
    const EstimateSample x = e.estimate();
    INFO("step " << k);
    REQUIRE(finite(x));
    if (const auto cov = e.covariance()) {
      REQUIRE(cov->P.allFinite());
      REQUIRE(cov->P.diagonal().minCoeff() >= 0.0);
    }
  }
}

std::unique_ptr<Estimator> fresh(const std::string& name) {
  std::unique_ptr<Estimator> e = makeEstimator(name);
  e->reset(trot().x0);
  return e;
}

}  // namespace

TEST_CASE("contract: the first sample is never integrated, whatever its dt", "[estimator]") {
  for (const std::string& name : estimatorNames()) {
    INFO(name);
    const std::unique_ptr<Estimator> e = fresh(name);
    StepInput in;  // a free-fall reading (a_m = 0), 50 ms after x0, no contact
    in.t = trot().x0.t + 0.05;
    in.dt = 0.05;
    e->step(in);
    const EstimateSample x = e->estimate();
    CHECK(x.t == in.t);
    CHECK(x.v == trot().x0.v);
    CHECK(x.p == trot().x0.p);
    CHECK(e->health().total() == 0);
  }
}

TEST_CASE("contract: a sample at dt = 0 integrates nothing", "[estimator]") {
  const std::vector<StepInput>& inputs = trot().inputs;
  for (const std::string& name : estimatorNames()) {
    INFO(name);
    const std::unique_ptr<Estimator> e = fresh(name);
    run(*e, inputs, 1000);
    const EstimateSample before = e->estimate();
    StepInput again = inputs[999];  // the same instant again, without contacts
    again.dt = 0.0;
    again.num_contacts = 0;
    e->step(again);
    CHECK(same(e->estimate(), before));
  }
}

TEST_CASE("contract: a gap beyond max_dt is not integrated and is counted", "[estimator]") {
  const std::vector<StepInput>& inputs = trot().inputs;
  for (const std::string& name : estimatorNames()) {
    INFO(name);
    const std::unique_ptr<Estimator> e = fresh(name);
    run(*e, inputs, 1000);
    const EstimateSample before = e->estimate();
    std::vector<StepInput> after(inputs.begin() + 1000, inputs.end());
    for (StepInput& in : after) in.t += 10.0;  // 10 s of samples lost
    after.front().dt += 10.0;
    StepInput first = after.front();
    first.num_contacts = 0;
    e->step(first);
    CHECK(e->health()[Fault::kTimeGap] == 1);
    CHECK(close(e->estimate(), before));
    after.erase(after.begin());
    run(*e, after, after.size());  // and it carries on
    CHECK(e->health()[Fault::kTimeGap] == 1);
    CHECK(e->health().healthy());
  }
}

TEST_CASE("contract: an IMU sample beyond the sensor's range is not used", "[estimator]") {
  const std::vector<StepInput>& inputs = trot().inputs;
  struct Spike {
    const char* what;
    Eigen::Vector3d w_m, a_m;
    Fault fault;
  };
  const Spike spikes[] = {
      {"gyro 1e100", Eigen::Vector3d(1e100, 0, 0), Eigen::Vector3d::Zero(), Fault::kGyroRange},
      {"gyro 1e30", Eigen::Vector3d(0, 1e30, 0), Eigen::Vector3d::Zero(), Fault::kGyroRange},
      {"accelerometer 1e10", Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1e10),
       Fault::kAccelRange}};
  for (const std::string& name : estimatorNames()) {
    const std::unique_ptr<Estimator> clean = fresh(name);
    run(*clean, inputs, inputs.size());
    for (const Spike& s : spikes) {
      INFO(name << ", " << s.what);
      for (const std::size_t at : {std::size_t{0}, std::size_t{1500}}) {
        INFO("at sample " << at);
        std::vector<StepInput> faulty = inputs;
        faulty[at].imu.w_m += s.w_m;
        faulty[at].imu.a_m += s.a_m;
        const std::unique_ptr<Estimator> e = fresh(name);
        run(*e, faulty, faulty.size());
        CHECK(e->health()[s.fault] == 1);
        CHECK(e->health().healthy());
        // Holding the neighbouring sample for 1 ms barely moves the estimate.
        CHECK((e->estimate().p - clean->estimate().p).norm() < 0.01);
        CHECK((e->estimate().v - clean->estimate().v).norm() < 0.01);
      }
    }
  }
}

TEST_CASE("contract: a stance foot beyond range is dropped from its sample", "[estimator]") {
  const std::vector<StepInput>& inputs = trot().inputs;
  for (const std::string& name : estimatorNames()) {
    const std::unique_ptr<Estimator> clean = fresh(name);
    run(*clean, inputs, inputs.size());
    for (const char* what : {"variance 1e30", "position 1 km", "velocity 1e6"}) {
      INFO(name << ", " << what);
      std::vector<StepInput> faulty = inputs;
      StepInput& in = faulty[1500];
      REQUIRE(in.num_contacts > 0);
      ContactMeasurement& c = in.contacts[0];
      if (what[0] == 'v' && what[2] == 'r') c.cov *= 1e30;
      if (what[0] == 'p') c.p_body = Eigen::Vector3d(1000, 0, 0);
      if (what[0] == 'v' && what[2] == 'l') c.v_body = Eigen::Vector3d(1e6, 0, 0);
      const std::unique_ptr<Estimator> e = fresh(name);
      run(*e, faulty, faulty.size());
      CHECK(e->health()[Fault::kContactRange] == 1);
      CHECK(e->health().healthy());
      CHECK((e->estimate().p - clean->estimate().p).norm() < 0.02);
    }
  }
}

TEST_CASE("contract: a large but admitted variance is survived", "[estimator]") {
  std::vector<StepInput> inputs = trot().inputs;
  for (StepInput& in : inputs) {
    for (int k = 0; k < in.num_contacts; ++k) in.contacts[k].cov *= 1e10;  // ~ (1 m)^2..(3 m)^2
  }
  for (const std::string& name : estimatorNames()) {
    INFO(name);
    const std::unique_ptr<Estimator> e = fresh(name);
    run(*e, inputs, inputs.size());
    CHECK(e->health()[Fault::kContactRange] == 0);
  }
}

TEST_CASE("contract: a step of 1e-12 s and a variance of 1e-30 m^2 are survived", "[estimator]") {
  const std::vector<StepInput>& inputs = trot().inputs;
  std::vector<StepInput> tiny = inputs;  // sample 1500 again, 1e-12 s later
  StepInput again = tiny[1500];
  again.t += 1e-12;
  again.dt = 1e-12;
  tiny.insert(tiny.begin() + 1501, again);
  tiny[1502].dt -= 1e-12;
  std::vector<StepInput> exact = inputs;  // one foot measured with a variance of 1e-30 m^2
  exact[1500].contacts[0].cov = 1e-30 * Eigen::Matrix3d::Identity();
  for (const std::string& name : estimatorNames()) {
    const std::unique_ptr<Estimator> clean = fresh(name);
    run(*clean, inputs, inputs.size());
    for (const auto* variant : {&tiny, &exact}) {
      INFO(name << (variant == &tiny ? ", dt 1e-12" : ", variance 1e-30"));
      const std::unique_ptr<Estimator> e = fresh(name);
      run(*e, *variant, variant->size());
      CHECK(e->health().total() == 0);
      CHECK((e->estimate().p - clean->estimate().p).norm() < 0.01);
    }
  }
}

TEST_CASE("contract: input no caller can mean throws and changes nothing", "[estimator]") {
  const std::vector<StepInput>& inputs = trot().inputs;
  const double nan = std::nan("");
  for (const std::string& name : estimatorNames()) {
    const std::unique_ptr<Estimator> e = fresh(name);
    run(*e, inputs, 1500);
    const EstimateSample before = e->estimate();
    std::vector<StepInput> bad(7, inputs[1500]);
    bad[0].imu.w_m.x() = nan;
    bad[1].imu.a_m.z() = std::numeric_limits<double>::infinity();
    bad[2].dt = -1e-3;
    bad[3].t = nan;
    bad[4].contacts[0].foot = leg_odometry::kMaxContacts;  // beyond every estimator's feet
    bad[5].contacts[0].cov(0, 1) = 1.0;                    // not symmetric
    bad[6].contacts[0].p_body.y() = nan;
    for (std::size_t k = 0; k < bad.size(); ++k) {
      INFO(name << ", case " << k);
      CHECK_THROWS_AS(e->step(bad[k]), std::invalid_argument);
      CHECK(same(e->estimate(), before));
    }
    CHECK(e->health().total() == 0);
  }
}

TEST_CASE("contract: a state that is no longer physical is recovered, never NaN", "[estimator]") {
  // 1 s at 15 g along x without a foot down: every estimator integrates a speed far beyond
  // InputLimits::speed_max and must fall back to its last good state.
  const InputLimits limits;
  for (const std::string& name : estimatorNames()) {
    INFO(name);
    const std::unique_ptr<Estimator> e = fresh(name);
    StepInput in;
    in.imu.a_m = Eigen::Vector3d(15 * 9.81, 0, 9.81);
    in.t = trot().x0.t;
    for (int k = 0; k < 1000; ++k) {
      e->step(in);
      const EstimateSample x = e->estimate();
      REQUIRE(finite(x));
      REQUIRE(x.v.norm() <= limits.speed_max);
      in.t += 1e-3;
      in.dt = 1e-3;
    }
    CHECK_FALSE(e->health().healthy());
    CHECK(e->health()[Fault::kStateUnhealthy] >= 1);
  }
}

TEST_CASE("contract: a hexapod standing, then walking on tripods, runs on every estimator",
          "[estimator]") {
  // Exact readings of a body at rest 0.3 m above six feet: every estimator must stay at the
  // truth. Filters with four foot states give the stance feet slots (estimation/foot_slots.hpp):
  // with six feet down two wait, and at each tripod switch the new feet take the slots that
  // freed one sample later.
  const test::Recording hexapod = test::hexapodTripods(1000, 3001);
  const EstimateSample& x0 = hexapod.x0;
  for (const std::string& name : estimatorNames()) {
    INFO(name);
    const std::unique_ptr<Estimator> e = makeEstimator(name);
    e->reset(x0);
    for (const StepInput& in : hexapod.steps) {
      REQUIRE_NOTHROW(e->step(in));
      REQUIRE(finite(e->estimate()));
    }
    // The linear KF re-learns a landing foot through its swing noise instead of re-placing it,
    // and moves by 0.14 mm; the others stay exact to rounding.
    const double tolerance = name == "linear-kf" ? 1e-3 : 1e-9;
    CHECK((e->estimate().p - x0.p).norm() < tolerance);
    CHECK(e->estimate().v.norm() < tolerance);
    CHECK(e->health().healthy());
  }
}

TEST_CASE("foot slots: ids beyond the filter's feet get free slots, never a reused one",
          "[estimator]") {
  FootSlots<4> slots;
  Health health;
  std::optional<StepInput> storage;
  StepInput in;
  const auto down = [&](std::initializer_list<int> ids) {
    in.num_contacts = 0;
    for (const int id : ids) {
      in.contacts[in.num_contacts].foot = id;
      in.contacts[in.num_contacts++].cov = Eigen::Matrix3d::Identity();
    }
    const StepInput& mapped = slots.map(in, storage, health);
    std::vector<int> out;
    for (const ContactMeasurement& c : mapped.stance()) out.push_back(c.foot);
    return out;
  };
  CHECK(down({0, 1, 2, 3}) == std::vector<int>{0, 1, 2, 3});  // a quadruped: identity
  CHECK(down({0, 2, 4}) == std::vector<int>{0, 2});  // 4: slots 1 and 3 were held a sample ago
  CHECK(health[Fault::kNoFootSlot] == 1);
  CHECK(down({0, 2, 4}) == std::vector<int>{0, 2, 1});  // now slot 1 is free
  // A tripod switch: slots 0..2 were held a sample ago, so only slot 3 is free: foot 1 takes it
  // (its own slot 1 was foot 4's), feet 3 and 5 wait one sample.
  CHECK(down({1, 3, 5}) == std::vector<int>{3});
  CHECK(health[Fault::kNoFootSlot] == 3);
  CHECK(down({1, 3, 5}) == std::vector<int>{3, 0, 1});
}

TEST_CASE("health guard: the cheap and the full checks", "[estimator]") {
  Eigen::Matrix3d P = Eigen::Matrix3d::Identity();
  CHECK(looksPositiveDefinite(P));
  CHECK(isPositiveDefinite(P));
  Eigen::Matrix3d bad = P;
  bad(0, 1) = 1e-3;  // asymmetric: found by the full check
  CHECK_FALSE(isPositiveDefinite(bad));
  bad = P;
  bad(0, 2) = std::numeric_limits<double>::infinity();
  CHECK_FALSE(looksPositiveDefinite(bad));
  bad = P;
  bad(2, 2) = std::nan("");
  CHECK_FALSE(looksPositiveDefinite(bad));
  bad = P;
  bad(1, 1) = -1.0;
  CHECK_FALSE(looksPositiveDefinite(bad));
  bad = P;
  bad(0, 1) = bad(1, 0) = 2.0;  // symmetric, positive diagonal, indefinite
  CHECK(looksPositiveDefinite(bad));
  CHECK_FALSE(isPositiveDefinite(bad));

  // The last good state is the last one that passed the full check.
  HealthGuard guard;
  const InputLimits limits;
  EstimateSample x;
  guard.reset(x);
  for (int k = 1; k <= HealthGuard::kFullCheckInterval; ++k) {
    x.p.x() = k;
    REQUIRE(guard.check(x, P, limits));
  }
  CHECK(guard.lastGood().p.x() == HealthGuard::kFullCheckInterval);
  x.p.x() = -1.0;
  for (int k = 1; k < HealthGuard::kFullCheckInterval; ++k) REQUIRE(guard.check(x, bad, limits));
  CHECK_FALSE(guard.check(x, bad, limits));  // the full check finds it
  CHECK(guard.lastGood().p.x() == HealthGuard::kFullCheckInterval);
  x.v = Eigen::Vector3d(limits.speed_max * 2, 0, 0);
  CHECK_FALSE(guard.check(x, P, limits));
}

}  // namespace legkit
