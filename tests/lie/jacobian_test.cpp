// Every Jacobian of lie/ (SO3 and SEK3 Jr, Jl, JrInv, JlInv, and the Gamma functions) against
// a long-double reference series, at the angles where closed forms cancel or switch:
//   Jl(xi) = sum_k ad(xi)^k / (k+1)!,   Jr(xi) = sum_k (-ad(xi))^k / (k+1)!,
// 60 terms in long double (|xi| <= pi-ish and the columns enter ad nilpotently, so no scaling
// and squaring is needed), inverses by a long-double LU inverse of the series. The tolerance,
// 1e-12 relative to the largest entry, catches any error of 1e-8 (DESIGN.md: manif's SE(3)
// Jacobian is off by 2e-8 near theta = 1e-4; Sophus's SE(3) left Jacobian by 2 near 1e-8).
// A forward-difference check is an independent, looser sanity check of the same matrices.
#include <catch2/catch.hpp>

#include <Eigen/LU>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <random>
#include <vector>

#include "lie_test_support.hpp"

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using LD = long double;
using MatLD = Eigen::Matrix<LD, Eigen::Dynamic, Eigen::Dynamic>;

using SEK3_3 = lie::SEK3<double, 3>;
using SEK3_6 = lie::SEK3<double, 6>;
using SEKd6 = lie::SEKd<double, 6>;

namespace {

constexpr double kRelTol = 1e-12;

// The angles of the hard regions: 0, 1e-12, 1e-8, both sides of the Taylor switch
// (theta = 1e-5), 1e-4, moderate, both sides of the series switch (2.5), and just below pi.
const std::vector<double>& specialAngles() {
  static const std::vector<double> angles = {0.0,
                                             1e-12,
                                             1e-8,
                                             1e-5 * (1 - 1e-6),
                                             1e-5 * (1 + 1e-6),
                                             1e-4,
                                             1e-2,
                                             0.5,
                                             1.0,
                                             2.5 * (1 - 1e-9),
                                             2.5 * (1 + 1e-9),
                                             3.0,
                                             lietest::kPi - 1e-4,
                                             lietest::kPi - 1e-6,
                                             lietest::kPi - 1e-9};
  return angles;
}

// ad(xi) of SE_k(3) (k = 0: SO(3)'s hat) in long double.
MatLD adLD(const VectorXd& xi) {
  const Eigen::Index n = xi.size(), k = (n - 3) / 3;
  const auto hatLD = [](const Vector3d& v) {
    MatLD m = MatLD::Zero(3, 3);
    m << 0, -LD(v(2)), LD(v(1)), LD(v(2)), 0, -LD(v(0)), -LD(v(1)), LD(v(0)), 0;
    return m;
  };
  MatLD A = MatLD::Zero(n, n);
  const MatLD P = hatLD(xi.head<3>());
  for (Eigen::Index i = 0; i <= k; ++i) A.block(3 * i, 3 * i, 3, 3) = P;
  for (Eigen::Index i = 0; i < k; ++i)
    A.block(3 + 3 * i, 0, 3, 3) = hatLD(xi.segment<3>(3 + 3 * i));
  return A;
}

// sum_{j=0}^{terms-1} M^j / (j + offset)!  (offset 1: a Jacobian; offset 2: Gamma_2), at most
// 60 terms.
MatLD powerSeries(const MatLD& M, int offset, int terms = 60) {
  MatLD power = MatLD::Identity(M.rows(), M.cols());
  LD factorial = 1;
  for (int i = 2; i <= offset; ++i) factorial *= i;
  MatLD sum = power / factorial;
  for (int j = 1; j < terms; ++j) {
    power = power * M;
    factorial *= (j + offset);
    const MatLD term = power / factorial;
    sum += term;
    // Past j > theta the terms fall factorially: stop once they are far below long double's
    // resolution (for theta = 0, ad^2 = 0 and this stops at once).
    if (term.cwiseAbs().maxCoeff() <= 1e-30L * sum.cwiseAbs().maxCoeff()) break;
  }
  return sum;
}

// Largest entry of |J - ref| relative to max(1, largest |ref| entry).
template <typename Derived>
double relError(const Eigen::MatrixBase<Derived>& J, const MatLD& ref) {
  const MatLD diff = J.template cast<LD>() - ref;
  return double(diff.cwiseAbs().maxCoeff() / std::max(LD(1), ref.cwiseAbs().maxCoeff()));
}

// Tangent vectors with the given angle, several axes (coordinate axes included) and column
// scales 0, 1e-3, 1, 10.
std::vector<VectorXd> testTangents(Eigen::Index k) {
  std::mt19937 gen(1234 + int(k));
  std::normal_distribution<double> n01;
  const auto randomUnit = [&] {
    Vector3d u(n01(gen), n01(gen), n01(gen));
    return Vector3d(u.normalized());
  };
  std::vector<Vector3d> axes = {Vector3d::UnitX(), -Vector3d::UnitZ(), randomUnit(), randomUnit()};
  std::vector<VectorXd> out;
  for (const double theta : specialAngles()) {
    for (const Vector3d& axis : axes) {
      for (const double scale : {0.0, 1e-3, 1.0, 10.0}) {
        VectorXd xi(3 + 3 * k);
        xi.head<3>() = theta * axis;
        for (Eigen::Index i = 0; i < k; ++i) xi.segment<3>(3 + 3 * i) = scale * randomUnit();
        out.push_back(xi);
      }
    }
  }
  return out;
}

void report(const char* what, double worst) {
  if (std::getenv("LEGKIT_JACOBIAN_REPORT"))
    std::cout << what << ": worst relative error " << worst << "\n";
}

}  // namespace

TEST_CASE("SO3 Jacobians and Gamma functions against long-double series", "[lie][jacobian]") {
  double worst = 0;
  for (const VectorXd& xi : testTangents(0)) {
    const Vector3d phi = xi;
    const MatLD ad = adLD(xi);
    const MatLD Jl = powerSeries(ad, 1), Jr = powerSeries(-ad, 1);
    const MatLD JlInv = Jl.inverse(), JrInv = Jr.inverse();
    const double errors[] = {relError(lie::SO3d::Jl(phi), Jl),
                             relError(lie::SO3d::Jr(phi), Jr),
                             relError(lie::SO3d::JlInv(phi), JlInv),
                             relError(lie::SO3d::JrInv(phi), JrInv),
                             relError(lie::Gamma<0>(phi), powerSeries(ad, 0)),
                             relError(lie::Gamma<1>(phi), Jl),
                             relError(lie::Gamma<2>(phi), powerSeries(ad, 2))};
    for (const double e : errors) {
      CAPTURE(phi.transpose(), phi.norm());
      CHECK(e <= kRelTol);
      worst = std::max(worst, e);
    }
  }
  report("SO3", worst);
}

TEMPLATE_TEST_CASE("SEK3 Jacobians against long-double series", "[lie][jacobian]", lie::SE3d,
                   lie::SE23d, SEK3_3, SEK3_6, SEKd6) {
  using G = TestType;
  double worst = 0;
  for (int k = G::kDynamic ? 0 : G::K; k <= G::MaxK; ++k) {
    for (const VectorXd& x : testTangents(k)) {
      const typename G::Tangent xi = x;
      const MatLD ad = adLD(x);
      const MatLD Jl = powerSeries(ad, 1), Jr = powerSeries(-ad, 1);
      const MatLD JlInv = Jl.inverse(), JrInv = Jr.inverse();
      const double errors[] = {relError(G::Jl(xi), Jl), relError(G::Jr(xi), Jr),
                               relError(G::JlInv(xi), JlInv), relError(G::JrInv(xi), JrInv)};
      for (int j = 0; j < 4; ++j) {
        CAPTURE(k, j, x.transpose(), x.head<3>().norm());
        CHECK(errors[j] <= kRelTol);
        worst = std::max(worst, errors[j]);
      }
    }
  }
  report("SEK3", worst);
}

// The tolerance really is tight enough to see an error of 1e-8 in any entry: the references'
// largest entries are at most ~1 + 10 pi, so kRelTol times that is still < 1e-10.
TEST_CASE("the Jacobian tolerance resolves 1e-8", "[lie][jacobian]") {
  for (const VectorXd& x : testTangents(2)) {
    const MatLD Jl = powerSeries(adLD(x), 1);
    MatLD wrong = Jl;
    wrong(4, 1) += 1e-8L;
    CHECK(relError(MatrixXd(Jl.cast<double>()), wrong) > kRelTol);
  }
}

// Independent sanity check: forward differences of the defining property
// Exp(xi + d) = Exp(xi) Exp(Jr d), step 1e-7, loose tolerance (truncation ~1e-7 |xi|^2).
TEMPLATE_TEST_CASE("SEK3 Jr by forward differences", "[lie][jacobian]", lie::SO3d, lie::SE3d,
                   lie::SE23d, SEK3_6, SEKd6) {
  using G = TestType;
  const double h = 1e-7;
  Eigen::Index k = 0;
  if constexpr (!std::is_same_v<G, lie::SO3d>) k = G::kDynamic ? 4 : G::K;
  for (const VectorXd& x : testTangents(k)) {
    const typename G::Tangent xi = x;
    const G X = G::Exp(xi);
    MatrixXd J(x.size(), x.size());
    for (Eigen::Index j = 0; j < x.size(); ++j) {
      typename G::Tangent xj = xi;
      xj(j) += h;
      J.col(j) = VectorXd((X.inverse() * G::Exp(xj)).Log()) / h;
    }
    CAPTURE(x.transpose());
    CHECK(lietest::maxAbsDiff(J, MatrixXd(G::Jr(xi))) <= 1e-5 * (1 + x.squaredNorm()));
  }
}
