// DelayedFilter (section 57.8): poses arriving 80 ms late, applied at their stamps and the inputs
// re-run, give the filter that applied them on time; bad poses are rejected, counted, and change
// nothing; step() and updatePose() allocate nothing. For the InvariantEkf and the Eskf, on 2 s of
// the simulated trot (1 kHz, feet touching down and lifting off throughout).
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "allocation_counter.hpp"
#include "estimation/fusion/delayed_filter.hpp"
#include "estimation/invariant/eskf.hpp"
#include "estimation/invariant/invariant_ekf.hpp"
#include "estimation/trot_log.hpp"

namespace legkit {
namespace {

using fusion::DelayedFilter;
using fusion::Matrix6d;
using fusion::PoseMeasurement;
using fusion::PoseRejection;

constexpr double kLatency = 0.08;  // [s] the latency

struct Run {
  EstimateSample x0;
  std::vector<StepInput> steps;
  std::vector<PoseMeasurement> poses;  // 10 Hz, stamped on samples, noisy truth
};

Matrix6d poseCovariance() {
  Eigen::Matrix<double, 6, 1> sigma;
  sigma << 0.01, 0.01, 0.02, 0.03, 0.03, 0.05;  // [rad], [m]
  Matrix6d cov = sigma.array().square().matrix().asDiagonal();
  cov(3, 4) = cov(4, 3) = 0.3 * 0.03 * 0.03;  // some correlation
  return cov;
}

// 2 s of the trot with a pose of the truth every 0.1 s (from 0.2 s), perturbed by its noise.
const Run& trotRun() {
  static const Run run = [] {
    const io::Log log = test::trotLog(2.0, 7, false);
    Run r;
    r.steps = test::inputsOf(log);
    const io::LogRow& first = log.rows.front();
    r.x0 = {first.t, first.gt_q, first.gt_v, first.gt_p};
    std::mt19937 rng(11);
    std::normal_distribution<double> n;
    const Matrix6d L = poseCovariance().llt().matrixL();
    for (std::size_t k = 200; k + 80 < log.rows.size(); k += 100) {  // all arrive in the run
      const io::LogRow& row = log.rows[k];
      Eigen::Matrix<double, 6, 1> u;
      for (int i = 0; i < 6; ++i) u(i) = n(rng);
      const Eigen::Matrix<double, 6, 1> e = L * u;
      PoseMeasurement z;
      z.t = row.t;
      z.t_arrival = row.t + kLatency;
      z.R_MB = lie::SO3d::Exp(e.head<3>()) * lie::SO3d::fromQuaternion(row.gt_q);
      z.p_MB = row.gt_p + e.tail<3>();
      z.cov = poseCovariance();
      r.poses.push_back(z);
    }
    return r;
  }();
  return run;
}

// Largest difference between two filters' states and covariances.
template <class Filter>
double difference(const Filter& a, const Filter& b) {
  const EstimateSample x = a.estimate(), y = b.estimate();
  double d = (x.p - y.p).cwiseAbs().maxCoeff();
  d = std::max(d, (x.v - y.v).cwiseAbs().maxCoeff());
  d = std::max(d, (x.q.coeffs() - y.q.coeffs()).cwiseAbs().maxCoeff());
  if (a.P().rows() != b.P().rows()) return INFINITY;
  return std::max(d, (a.P() - b.P()).cwiseAbs().maxCoeff());
}

template <class Filter>
bool identical(const Filter& a, const Filter& b) {
  const EstimateSample x = a.estimate(), y = b.estimate();
  return x.t == y.t && x.p == y.p && x.v == y.v && x.q.coeffs() == y.q.coeffs() &&
         a.P().rows() == b.P().rows() && a.P() == b.P() && a.health().count == b.health().count;
}

// On time (each pose right after the sample at its stamp) against delayed (each pose after the
// sample at its arrival, through DelayedFilter): the largest difference after every arrival.
template <class Filter>
double delayedAgainstOnTime(const Filter& prototype) {
  const Run& run = trotRun();
  Filter on_time = prototype;
  on_time.reset(run.x0);
  DelayedFilter<Filter> delayed(prototype);
  delayed.reset(run.x0);
  std::size_t next_on_time = 0, next_arrival = 0;
  double worst = 0.0;
  int arrivals = 0;
  for (const StepInput& in : run.steps) {
    on_time.step(in);
    if (next_on_time < run.poses.size() && run.poses[next_on_time].t == in.t) {
      CHECK(on_time.updatePose(run.poses[next_on_time]) == fusion::PoseUpdate::kUsed);
      ++next_on_time;
    }
    delayed.step(in);
    if (next_arrival < run.poses.size() && run.poses[next_arrival].t_arrival <= in.t + 1e-12) {
      const auto result = delayed.updatePose(run.poses[next_arrival++]);
      CHECK(result.used);
      CHECK(delayed.stats().last_replayed == 80);  // 80 ms of 1 kHz samples re-run
      worst = std::max(worst, difference(delayed.filter(), on_time));
      ++arrivals;
    }
  }
  CHECK(arrivals == static_cast<int>(run.poses.size()));
  CHECK(delayed.stats().used == run.poses.size());
  CHECK(delayed.stats().rejections() == 0);
  worst = std::max(worst, difference(delayed.filter(), on_time));
  // The poses mattered: without them the filter ends elsewhere.
  Filter alone = prototype;
  alone.reset(run.x0);
  for (const StepInput& in : run.steps) alone.step(in);
  CHECK(difference(alone, on_time) > 1e-4);
  return worst;
}

// Every rejection reason once on `a`, a copy `b` seeing none; then both go on identically.
template <class Filter>
void checkRejections(Filter prototype) {
  const Run& run = trotRun();
  DelayedFilter<Filter> a(prototype, 300);  // 0.3 s of history
  a.reset(run.x0);
  for (std::size_t k = 0; k < 1000; ++k) a.step(run.steps[k]);  // t = 0 .. 0.999 s
  REQUIRE(a.size() == 300);
  REQUIRE(a.newestTime() == run.steps[999].t);
  REQUIRE(a.oldestTime() == run.steps[700].t);
  // A pose at 0.9 s used first (the out-of-order reference), then everything else rejected.
  PoseMeasurement good = run.poses[7];
  REQUIRE(good.t == run.steps[900].t);
  REQUIRE(a.updatePose(good).used);
  DelayedFilter<Filter> b = a;

  const auto rejected = [&](PoseMeasurement z, PoseRejection why) {
    const auto result = a.updatePose(z);
    CHECK_FALSE(result.used);
    CHECK(result.reason == why);
    CHECK(identical(a.filter(), b.filter()));
  };
  PoseMeasurement z = good;
  z.valid = false;
  rejected(z, PoseRejection::kNotValid);
  z = good;
  z.p_MB.z() = NAN;
  rejected(z, PoseRejection::kNotFinite);
  z = good;
  z.cov(5, 5) = -1e-4;
  rejected(z, PoseRejection::kNotPositiveDefinite);
  z = good;
  z.t = run.steps[650].t;  // older than the 0.3 s held
  rejected(z, PoseRejection::kTooOld);
  z = good;
  z.t = run.steps[999].t + 0.0005;  // after the newest sample
  rejected(z, PoseRejection::kFuture);
  z = run.poses[6];  // 0.8 s: in the history but older than the pose used at 0.9 s
  rejected(z, PoseRejection::kOutOfOrder);
  for (PoseRejection r :
       {PoseRejection::kNotValid, PoseRejection::kNotFinite, PoseRejection::kNotPositiveDefinite,
        PoseRejection::kTooOld, PoseRejection::kFuture, PoseRejection::kOutOfOrder}) {
    INFO(fusion::poseRejectionName(r));
    CHECK(a.stats()[r] == 1);
  }
  CHECK(a.stats().rejections() == 6);
  CHECK(a.stats().used == 1);

  // Both go on: more samples, a later pose; every snapshot of the history is unchanged, so the
  // two agree bitwise.
  for (std::size_t k = 1000; k < 1100; ++k) {
    a.step(run.steps[k]);
    b.step(run.steps[k]);
  }
  REQUIRE(run.poses[8].t == run.steps[1000].t);
  CHECK(a.updatePose(run.poses[8]).used);
  CHECK(b.updatePose(run.poses[8]).used);
  CHECK(identical(a.filter(), b.filter()));
}

}  // namespace

TEST_CASE("delayed poses (80 ms) equal the same poses applied on time: InvariantEkf", "[fusion]") {
  const double worst = delayedAgainstOnTime(invariant::InvariantEkf());
  INFO("largest difference " << worst);
  CHECK(worst <= 1e-9);
}

TEST_CASE("delayed poses (80 ms) equal the same poses applied on time: Eskf", "[fusion]") {
  const double worst = delayedAgainstOnTime(invariant::Eskf());
  INFO("largest difference " << worst);
  CHECK(worst <= 1e-9);
}

TEST_CASE("delayed poses: each rejection counted, a rejected pose changes nothing", "[fusion]") {
  SECTION("InvariantEkf") {
    checkRejections(invariant::InvariantEkf());
  }
  SECTION("Eskf") {
    checkRejections(invariant::Eskf());
  }
}

TEST_CASE("delayed poses: the filter's gate rejects a pose 2 m off, counted, nothing changes",
          "[fusion]") {
  const Run& run = trotRun();
  invariant::InvariantEkfParams params;
  params.gating.enabled = true;
  DelayedFilter<invariant::InvariantEkf> a{invariant::InvariantEkf(params)};
  a.reset(run.x0);
  for (std::size_t k = 0; k < 400; ++k) a.step(run.steps[k]);
  const DelayedFilter<invariant::InvariantEkf> b = a;
  PoseMeasurement z = run.poses[1];  // 0.3 s
  z.p_MB.x() += 2.0;
  const auto result = a.updatePose(z);
  CHECK(result.reason == PoseRejection::kGated);
  CHECK(a.stats()[PoseRejection::kGated] == 1);
  CHECK(identical(a.filter(), b.filter()));
  CHECK(a.updatePose(run.poses[1]).used);  // the pose itself passes
}

TEST_CASE("delayed poses: a bad step is refused before anything changes; capacity >= 1",
          "[fusion]") {
  const Run& run = trotRun();
  DelayedFilter<invariant::Eskf> f{invariant::Eskf()};
  f.reset(run.x0);
  for (std::size_t k = 0; k < 10; ++k) f.step(run.steps[k]);
  StepInput back = run.steps[5];  // earlier than the newest sample
  CHECK_THROWS_WITH(f.step(back), Catch::Contains("DelayedFilter::step at t = 0.005") &&
                                      Catch::Contains("earlier than the previous sample"));
  StepInput nan = run.steps[10];
  nan.imu.a_m.x() = NAN;
  CHECK_THROWS_AS(f.step(nan), std::invalid_argument);
  CHECK(f.size() == 10);
  CHECK(f.newestTime() == run.steps[9].t);
  CHECK_THROWS_WITH(DelayedFilter<invariant::Eskf>(invariant::Eskf(), 0),
                    Catch::Contains("capacity must be at least 1"));
}

TEST_CASE("delayed poses: step() and updatePose() allocate nothing", "[fusion]") {
  const Run& run = trotRun();
  DelayedFilter<invariant::InvariantEkf> inekf{invariant::InvariantEkf()};
  DelayedFilter<invariant::Eskf> eskf{invariant::Eskf()};
  inekf.reset(run.x0);
  eskf.reset(run.x0);
  std::size_t next = 0;
  const long before = test::allocationCount();
  for (const StepInput& in : run.steps) {
    inekf.step(in);
    eskf.step(in);
    if (next < run.poses.size() && run.poses[next].t_arrival <= in.t + 1e-12) {
      inekf.updatePose(run.poses[next]);
      eskf.updatePose(run.poses[next++]);
    }
  }
  CHECK(test::allocationCount() - before == 0);
  CHECK(inekf.stats().used == run.poses.size());  // it did run
  CHECK(eskf.stats().used == run.poses.size());
}

}  // namespace legkit
