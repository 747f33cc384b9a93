// The odometry pose history (estimation/fusion/odom_history.hpp): interpolation, never
// extrapolation, the reasons it gives, the ring's wrap-around, no allocation per push.
#include <catch2/catch.hpp>
#include <cmath>

#include "allocation_counter.hpp"
#include "estimation/fusion/odom_history.hpp"

using legkit::fusion::Matrix6d;
using legkit::fusion::OdomHistory;
using legkit::fusion::OdomPose;
using Lookup = legkit::fusion::OdomHistory::Lookup;

namespace {

// A body turning at a constant rate about a fixed body axis while moving at constant velocity:
// R(t) = R0 Exp(w t), p(t) = p0 + v t. Slerp between two samples of it is exact.
const Eigen::Vector3d kW(0.3, -0.5, 1.2);
const Eigen::Vector3d kV(0.5, 0.1, -0.05);
const lie::SO3d kR0 = lie::SO3d::Exp(Eigen::Vector3d(0.2, 0.1, -2.0));

OdomPose truePose(double t) {
  OdomPose x;
  x.t = t;
  x.R_OB = kR0 * lie::SO3d::Exp(kW * t);
  x.p_OB = Eigen::Vector3d(1.0, 2.0, 0.3) + kV * t;
  x.cov = Matrix6d::Identity() * (1e-4 + 1e-3 * t);  // grows linearly: interpolation is exact
  return x;
}

}  // namespace

TEST_CASE("odom history: interpolates between samples, exact at samples", "[fusion][extero]") {
  OdomHistory h(512);
  for (int k = 0; k < 300; ++k) h.push(truePose(0.001 * k));
  CHECK(h.size() == 300);
  for (double t : {0.0, 0.0105, 0.1234567, 0.2, 0.2985, 0.299}) {
    const auto r = h.at(t);
    REQUIRE(r.status == Lookup::kOk);
    const OdomPose x = truePose(t);
    CHECK(r.pose.t == t);
    CHECK((r.pose.R_OB.matrix() - x.R_OB.matrix()).cwiseAbs().maxCoeff() < 1e-12);
    CHECK((r.pose.p_OB - x.p_OB).cwiseAbs().maxCoeff() < 1e-12);
    CHECK((r.pose.cov - x.cov).cwiseAbs().maxCoeff() < 1e-15);
  }
  // At a sample's own time: that sample, bitwise.
  const OdomPose s = truePose(0.001 * 42);
  const auto r = h.at(s.t);
  CHECK(r.pose.R_OB.matrix() == s.R_OB.matrix());
  CHECK(r.pose.p_OB == s.p_OB);
}

TEST_CASE("odom history: never extrapolates and says why", "[fusion][extero]") {
  OdomHistory h(8);
  CHECK(h.at(0.0).status == Lookup::kEmpty);
  for (int k = 0; k < 20; ++k) h.push(truePose(0.01 * k));
  // The ring keeps the newest 8: samples 12..19.
  CHECK(h.size() == 8);
  CHECK(h.oldestTime() == 0.01 * 12);
  CHECK(h.newestTime() == 0.01 * 19);
  CHECK(h.at(0.01 * 12).status == Lookup::kOk);
  CHECK(h.at(0.01 * 12 - 1e-9).status == Lookup::kTooOld);
  CHECK(h.at(0.01 * 19).status == Lookup::kOk);
  CHECK(h.at(0.01 * 19 + 1e-9).status == Lookup::kInFuture);
  CHECK(h.at(std::nan("")).status == Lookup::kNotFinite);
  CHECK(h.at(INFINITY).status == Lookup::kNotFinite);
  CHECK(std::string(legkit::fusion::toString(Lookup::kTooOld)) ==
        "older than the odometry history");
  const auto mid = h.at(0.155);
  REQUIRE(mid.status == Lookup::kOk);
  CHECK((mid.pose.p_OB - truePose(0.155).p_OB).norm() < 1e-12);

  // A sample not after the newest, or not finite, is refused and changes nothing.
  OdomPose late = truePose(0.01 * 19);
  CHECK_THROWS_WITH(h.push(late), Catch::Contains("is not after the newest sample"));
  late.t = 0.5;
  late.p_OB.x() = std::nan("");
  CHECK_THROWS_WITH(h.push(late), Catch::Contains("non-finite pose"));
  CHECK(h.size() == 8);
  CHECK(h.newestTime() == 0.01 * 19);
  CHECK_THROWS_AS(OdomHistory(1), std::invalid_argument);
  h.clear();
  CHECK(h.at(0.15).status == Lookup::kEmpty);
}

TEST_CASE("odom history: push and at allocate nothing", "[fusion][extero]") {
  OdomHistory h(100);
  std::vector<OdomPose> poses;
  for (int k = 0; k < 1000; ++k) poses.push_back(truePose(0.001 * k));
  const long before = legkit::test::allocationCount();
  double sum = 0.0;
  for (const auto& x : poses) {
    h.push(x);
    sum += h.at(x.t - 0.0505).pose.p_OB.x();
  }
  CHECK(legkit::test::allocationCount() == before);
  CHECK(std::isfinite(sum));
}
