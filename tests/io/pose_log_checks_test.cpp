// Issue 23 item 11, the pose file (estimation/fusion/pose_log.hpp): a covariance whose Cholesky
// factor overflows to inf or NaN is refused by the reader and the writer (Eigen reports success
// for it), and the attitude round trip holds to the bound the header states
// (kPoseLogAttitudeRoundTrip), measured here over many attitudes.
#include <catch2/catch.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "estimation/fusion/pose_log.hpp"
#include "io/log_error.hpp"

namespace {

using Catch::Matchers::Contains;
using legkit::fusion::Matrix6d;
using legkit::fusion::PoseMeasurement;

std::string header() {
  std::string h;
  for (const auto& c : legkit::fusion::poseLogColumns()) h += (h.empty() ? "" : ",") + c;
  return h + "\n";
}

// One row: identity attitude, the covariance's upper triangle given by `cov`.
std::string row(double t, const Matrix6d& cov) {
  std::ostringstream out;
  out.precision(17);
  out << t << ',' << t + 0.01 << ",1,2,3,1,0,0,0";
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) out << ',' << cov(i, j);
  }
  out << ",1\n";
  return out.str();
}

std::string errorOf(const std::string& text) {
  std::istringstream in(text);
  try {
    legkit::fusion::readPoseLog(in, "p.csv");
  } catch (const legkit::io::LogError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("pose file: a covariance whose Cholesky factor overflows is refused",
          "[fusion][extero][issue23]") {
  // c00 = 1e-300, c02 = 1e200: the factor's L20 = 1e200 / 1e-150 overflows to inf and L22 is
  // sqrt(1 - inf) = NaN, which Eigen's LLT does not see (NaN <= 0 is false): "Success". The
  // matrix is indefinite (c00 c22 - c02^2 < 0).
  Matrix6d cov = Matrix6d::Identity();
  cov(0, 0) = 1e-300;
  cov(0, 2) = cov(2, 0) = 1e200;
  const std::string text = header() + row(0.0, Matrix6d::Identity()) + row(0.1, cov);
  const std::string error = errorOf(text);
  CHECK_THAT(error, Contains("p.csv:3"));
  CHECK_THAT(error, Contains("c00"));
  CHECK_THAT(error, Contains("positive definite"));

  PoseMeasurement z;
  z.cov = cov;
  std::ostringstream out;
  CHECK_THROWS_WITH(legkit::fusion::writePoseLog(out, {z}), Contains("positive definite"));
  // A large but finite factor is still a covariance.
  Matrix6d big = Matrix6d::Identity() * 1e300;
  CHECK(errorOf(header() + row(0.0, big)).empty());
}

TEST_CASE("pose file: the attitude round trip holds to the bound the header states",
          "[fusion][extero][issue23]") {
  std::mt19937 rng(23);
  std::normal_distribution<double> normal;
  std::vector<PoseMeasurement> poses;
  for (int k = 0; k < 30000; ++k) {
    PoseMeasurement z;
    z.t = k;
    z.t_arrival = k;
    Eigen::Vector3d w(normal(rng), normal(rng), normal(rng));
    if (k % 3 == 1) w *= 1e-6;
    if (k % 3 == 2) w = w.normalized() * (3.14159265358979 - 1e-4 * std::abs(normal(rng)));
    z.R_MB = lie::SO3d::Exp(w);
    poses.push_back(z);
  }
  const auto trip = [](const std::vector<PoseMeasurement>& p) {
    std::stringstream file;
    legkit::fusion::writePoseLog(file, p);
    return legkit::fusion::readPoseLog(file, "trip.csv");
  };
  const auto worst = [](const std::vector<PoseMeasurement>& a,
                        const std::vector<PoseMeasurement>& b) {
    double w = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k) {
      w = std::max(w, (a[k].R_MB.matrix() - b[k].R_MB.matrix()).cwiseAbs().maxCoeff());
    }
    return w;
  };
  const auto once = trip(poses);
  const auto twice = trip(once);
  const double first = worst(once, poses);
  const double next = worst(twice, once);
  INFO("worst entry error: first round trip " << first << ", next " << next);
  CHECK(first <= legkit::fusion::kPoseLogAttitudeRoundTrip);
  CHECK(next <= legkit::fusion::kPoseLogAttitudeRoundTrip);
  // The former promise, 1e-15, does not hold: the bound is not stated tighter than it is.
  CHECK(first > 1e-15);
}
