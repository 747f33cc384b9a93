// Shared helpers of the lie/ tests: RapidCheck generators aimed at the numerically hard rotation
// angles (where closed forms cancel or a series switch sits), and central differences on a group.
#pragma once

#include <rapidcheck.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <vector>

#include <lie/lie.hpp>

namespace lietest {

constexpr double kPi = 3.141592653589793238462643383279502884;

// Uniform double in [lo, hi). RapidCheck scales integer ranges with its "size" parameter, which
// starts at 0; we fix the size so that the first cases are as spread out as the last ones.
inline rc::Gen<double> uniform(double lo, double hi) {
  constexpr std::int64_t kSteps = std::int64_t(1) << 53;
  return rc::gen::map(
      rc::gen::resize(rc::kNominalSize, rc::gen::inRange<std::int64_t>(0, kSteps)),
      [lo, hi](std::int64_t i) { return lo + (hi - lo) * (double(i) / double(kSteps)); });
}

// Log-uniform double in [lo, hi), 0 < lo < hi.
inline rc::Gen<double> logUniform(double lo, double hi) {
  return rc::gen::map(uniform(std::log10(lo), std::log10(hi)),
                      [](double e) { return std::pow(10.0, e); });
}

// Rotation angles where lie/ must be careful: exactly 0, ~1e-12, ~1e-8, the Taylor switch of
// AngleSeries (theta = 1e-5, theta^2 = 1e-10), ~1e-4, its second switch (theta = 2.5), moderate
// angles, and angles just below pi: pi - [minGapToPi, max(1e-4, 10 minGapToPi)].
inline rc::Gen<double> hardAngle(double minGapToPi = 1e-9) {
  using rc::gen::just;
  return rc::gen::weightedOneOf<double>({
      {1, just(0.0)},
      {1, logUniform(3e-13, 3e-12)},
      {1, logUniform(3e-9, 3e-8)},
      {1, logUniform(0.9e-5, 1.1e-5)},
      {1, logUniform(3e-5, 3e-4)},
      {1, uniform(2.49, 2.51)},
      {4, uniform(1e-3, 3.0)},
      {2, rc::gen::map(logUniform(minGapToPi, std::max(1e-4, 10 * minGapToPi)),
                       [](double gap) { return kPi - gap; })},
  });
}

// Unit vector: uniform on the sphere, or exactly along a coordinate axis (the branches of the
// quaternion extraction in Log are chosen by the diagonal, which axes make extreme).
inline rc::Gen<Eigen::Vector3d> unitVector() {
  const auto sphere = rc::gen::apply(
      [](double z, double azimuth) {
        const double r = std::sqrt(std::max(0.0, 1 - z * z));
        return Eigen::Vector3d(r * std::cos(azimuth), r * std::sin(azimuth), z);
      },
      uniform(-1, 1), uniform(0, 2 * kPi));
  const auto axis =
      rc::gen::map(rc::gen::resize(rc::kNominalSize, rc::gen::inRange(0, 6)), [](int i) {
        Eigen::Vector3d e = Eigen::Vector3d::Zero();
        e(i % 3) = i < 3 ? 1.0 : -1.0;
        return e;
      });
  return rc::gen::weightedOneOf<Eigen::Vector3d>({{4, sphere}, {1, axis}});
}

inline rc::Gen<Eigen::Vector3d> rotationVector(rc::Gen<double> angle = hardAngle()) {
  return rc::gen::apply(
      [](double theta, const Eigen::Vector3d& u) -> Eigen::Vector3d { return theta * u; }, angle,
      unitVector());
}

// Translation-like column of SE_K(3): zero, tiny, or of scale 1e-3 .. 10.
inline rc::Gen<Eigen::Vector3d> translation() {
  const auto scaled = [](rc::Gen<double> scale) {
    return rc::gen::apply(
        [](double s, const Eigen::Vector3d& u) -> Eigen::Vector3d { return s * u; }, scale,
        unitVector());
  };
  return rc::gen::weightedOneOf<Eigen::Vector3d>(
      {{1, rc::gen::just(Eigen::Vector3d::Zero().eval())},
       {1, scaled(logUniform(1e-9, 1e-6))},
       {6, scaled(logUniform(1e-3, 10.0))}});
}

inline rc::Gen<std::vector<Eigen::Vector3d>> rotationVectors(int n,
                                                             rc::Gen<double> angle = hardAngle()) {
  return rc::gen::container<std::vector<Eigen::Vector3d>>(n, rotationVector(angle));
}

// Number of columns: K for a fixed-K group, 0..MaxK for the run-time one.
template <typename Group>
rc::Gen<int> numCols() {
  if constexpr (Group::kDynamic) {
    return rc::gen::resize(rc::kNominalSize, rc::gen::inRange(0, Group::MaxK + 1));
  } else {
    return rc::gen::just(int(Group::K));
  }
}

template <typename Group>
rc::Gen<typename Group::Tangent> tangentWithCols(int k, rc::Gen<double> angle) {
  using Tangent = typename Group::Tangent;
  return rc::gen::apply(
      [k](const Eigen::Vector3d& phi, const std::vector<Eigen::Vector3d>& rho) {
        Tangent xi(3 + 3 * k);
        xi.template head<3>() = phi;
        for (int i = 0; i < k; ++i) xi.template segment<3>(3 + 3 * i) = rho[i];
        return xi;
      },
      rotationVector(angle), rc::gen::container<std::vector<Eigen::Vector3d>>(k, translation()));
}

// One tangent vector of SE_K(3) (for SEKd: with a random number of columns).
template <typename Group>
rc::Gen<typename Group::Tangent> tangent(rc::Gen<double> angle = hardAngle()) {
  return rc::gen::mapcat(numCols<Group>(),
                         [angle](int k) { return tangentWithCols<Group>(k, angle); });
}

// n tangent vectors of SE_K(3) that share one number of columns.
template <typename Group>
rc::Gen<std::vector<typename Group::Tangent>> tangents(int n, rc::Gen<double> angle = hardAngle()) {
  using Tangent = typename Group::Tangent;
  return rc::gen::mapcat(numCols<Group>(), [n, angle](int k) {
    return rc::gen::container<std::vector<Tangent>>(n, tangentWithCols<Group>(k, angle));
  });
}

// Central differences: column j is (f(h e_j) - f(-h e_j)) / 2h, f: R^n -> R^m.
template <typename F>
Eigen::MatrixXd centralDifference(F&& f, Eigen::Index n, double h = 1e-6) {
  Eigen::MatrixXd J;
  for (Eigen::Index j = 0; j < n; ++j) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
    e(j) = h;
    const Eigen::VectorXd plus = f(e);
    const Eigen::VectorXd minus = f(Eigen::VectorXd(-e));
    if (j == 0) J.resize(plus.size(), n);
    J.col(j) = (plus - minus) / (2 * h);
  }
  return J;
}

template <typename A, typename B>
double maxAbsDiff(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return (a - b).cwiseAbs().maxCoeff();
}

}  // namespace lietest
