// eval::velocityBiasVariance on constructed velocity errors whose split is known.
#include <catch2/catch.hpp>
#include <cmath>

#include "eval/bias_variance.hpp"

using legkit::eval::Trajectory;
using legkit::eval::velocityBiasVariance;

namespace {

// 1000 rows of 1 ms at rest, and an estimate equal to it.
legkit::io::Log still() {
  legkit::io::Log log;
  log.layout.ground_truth = true;
  for (int k = 0; k < 1000; ++k) {
    legkit::io::LogRow r;
    r.t = 1e-3 * k;
    log.rows.push_back(r);
  }
  return log;
}

Trajectory copyOf(const legkit::io::Log& log) {
  Trajectory est;
  for (const auto& r : log.rows) est.push_back({r.t, r.gt_q, r.gt_v, r.gt_p});
  return est;
}

}  // namespace

TEST_CASE("a constant velocity error is all bias", "[eval]") {
  const auto log = still();
  Trajectory est = copyOf(log);
  for (auto& e : est) e.v = Eigen::Vector3d(0.03, 0.0, -0.04);
  const auto bv = velocityBiasVariance(log, est, 0.1);
  CHECK(bv.bias == Approx(0.05));
  CHECK(bv.variance == Approx(0.0).margin(1e-20));
}

TEST_CASE("an error alternating every row is all variance", "[eval]") {
  const auto log = still();
  Trajectory est = copyOf(log);
  for (std::size_t k = 0; k < est.size(); ++k) est[k].v.x() = (k % 2 == 0 ? 0.2 : -0.2);
  // A 0.1 s window holds about 101 rows: the local mean is at most 0.2/51 (at the ends), and
  // it has the sign of e_k, so the fast part is 0.2 less that little.
  const auto bv = velocityBiasVariance(log, est, 0.1);
  CHECK(bv.bias < 0.2 / 50);
  CHECK(bv.variance < 0.04);
  CHECK(bv.variance > 0.04 * (1 - 2.0 / 51));
}

TEST_CASE("a slow ramp is bias, a fast one variance, depending on the window", "[eval]") {
  const auto log = still();
  Trajectory est = copyOf(log);
  for (std::size_t k = 0; k < est.size(); ++k)
    est[k].v.y() = 0.1 * std::sin(2 * M_PI * log.rows[k].t);
  const auto narrow = velocityBiasVariance(log, est, 0.01);  // 1 Hz is slow against 10 ms
  const auto wide = velocityBiasVariance(log, est, 1.0);     // and averages out over 1 s
  CHECK(narrow.bias > 0.9 * 0.1 / std::sqrt(2.0));
  CHECK(narrow.variance < 1e-5);
  CHECK(wide.bias < narrow.bias / 2);
  CHECK(wide.variance > 10 * narrow.variance);
}

TEST_CASE("velocityBiasVariance rejects what it cannot split", "[eval]") {
  auto log = still();
  Trajectory est = copyOf(log);
  CHECK_THROWS_WITH(velocityBiasVariance(log, est, 0.0), Catch::Contains("window"));
  est.pop_back();
  CHECK_THROWS_WITH(velocityBiasVariance(log, est, 0.1), Catch::Contains("999 estimates"));
  log.layout.ground_truth = false;
  CHECK_THROWS_WITH(velocityBiasVariance(log, copyOf(log), 0.1), Catch::Contains("ground truth"));
}
