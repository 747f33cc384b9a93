// Properties of lie::SEK3 for K = 1 (SE(3)), 2 (SE_2(3)), 3, 6 and the run-time SEKd<double, 6>
// with 0..6 columns: group axioms, Exp/Log (also against Eigen's matrix exponential), adjoint,
// plus/minus, interpolation, and the checked construction and column editing with their errors.
// The calculus (Jacobians, optional Jacobian outputs) is in sek3_calculus_test.cpp.
#include <rapidcheck/catch.h>
#include <catch2/catch.hpp>

#include <unsupported/Eigen/MatrixFunctions>

#include "lie_test_support.hpp"

using Eigen::Matrix3d;
using Eigen::Vector3d;
using lietest::maxAbsDiff;
using lietest::tangents;

using SEK3_3 = lie::SEK3<double, 3>;
using SEK3_6 = lie::SEK3<double, 6>;
using SEKd6 = lie::SEKd<double, 6>;

namespace {

template <typename Group>
bool passesFromMatrix(const Group& X) {
  try {
    Group::fromMatrix(X.matrix(), 1e-12);
    return true;
  } catch (const lie::NotInGroup&) {
    return false;
  }
}

// The message of the NotInGroup that fromMatrix throws, or "" if it accepts the matrix.
template <typename Group>
std::string rejection(const typename Group::Matrix& M) {
  try {
    Group::fromMatrix(M);
  } catch (const lie::NotInGroup& e) {
    return e.what();
  }
  return "";
}

// Size of a group element for relative tolerances: 1 + largest column norm.
template <typename Group>
double scaleOf(const Group& X) {
  return 1 + (X.numCols() > 0 ? X.columns().colwise().norm().maxCoeff() : 0.0);
}

}  // namespace

TEMPLATE_TEST_CASE("SEK3 group axioms", "[lie][sek3]", lie::SE3d, lie::SE23d, SEK3_3, SEK3_6,
                   SEKd6) {
  using G = TestType;
  // Products, inverses and Exp are in the group to 1e-12: fromMatrix accepts them.
  rc::prop("closure", [] {
    const auto xs = *tangents<G>(2);
    const G X = G::Exp(xs[0]), Y = G::Exp(xs[1]);
    RC_ASSERT(passesFromMatrix(X));
    RC_ASSERT(passesFromMatrix(X * Y));
    RC_ASSERT(passesFromMatrix(X.inverse()));
    RC_ASSERT(passesFromMatrix(G::Identity(X.numCols())));
  });
  rc::prop("the group law is the matrix product", [] {
    const auto xs = *tangents<G>(2);
    const G X = G::Exp(xs[0]), Y = G::Exp(xs[1]);
    const double scale = scaleOf(X) * scaleOf(Y);
    RC_ASSERT(maxAbsDiff((X * Y).matrix(), X.matrix() * Y.matrix()) <= 1e-15 * scale);
    RC_ASSERT(maxAbsDiff(X.inverse().matrix(), X.matrix().inverse()) <= 1e-14 * scale);
  });
  rc::prop("identity is neutral", [] {
    const G X = G::Exp(*lietest::tangent<G>());
    const G I = G::Identity(X.numCols());
    RC_ASSERT((X * I).isApprox(X, 0.0));
    RC_ASSERT((I * X).isApprox(X, 0.0));
    RC_ASSERT(I.matrix() == G::Matrix::Identity(3 + X.numCols(), 3 + X.numCols()));
  });
  rc::prop("inverse", [] {
    const G X = G::Exp(*lietest::tangent<G>());
    const G I = G::Identity(X.numCols());
    RC_ASSERT((X * X.inverse()).isApprox(I, 1e-14 * scaleOf(X)));
    RC_ASSERT((X.inverse() * X).isApprox(I, 1e-14 * scaleOf(X)));
  });
  rc::prop("associativity", [] {
    const auto xs = *tangents<G>(3);
    const G X = G::Exp(xs[0]), Y = G::Exp(xs[1]), Z = G::Exp(xs[2]);
    RC_ASSERT(((X * Y) * Z).isApprox(X * (Y * Z), 1e-14 * scaleOf(X) * scaleOf(Y)));
  });
  rc::prop("act uses column i as the translation", [] {
    const G X = G::Exp(*lietest::tangent<G>());
    RC_PRE(X.numCols() > 0);
    const Eigen::Index i = *rc::gen::inRange<int>(0, int(X.numCols()));
    const Vector3d x = *lietest::translation();
    RC_ASSERT(maxAbsDiff(X.act(x, i), X.R() * x + X.col(i)) == 0.0);
  });
}

TEMPLATE_TEST_CASE("SEK3 Exp and Log", "[lie][sek3]", lie::SE3d, lie::SE23d, SEK3_3, SEK3_6,
                   SEKd6) {
  using G = TestType;
  // Rotation angle < pi, so Log must return xi. The rotation part keeps the relative precision
  // of SO(3)'s Log even at tiny angles; the columns are relative to the largest column.
  rc::prop("Log(Exp(xi)) = xi", [] {
    const typename G::Tangent xi = *lietest::tangent<G>();
    const typename G::Tangent back = G::Exp(xi).Log();
    RC_ASSERT(back.size() == xi.size());
    const double theta = xi.template head<3>().norm();
    RC_ASSERT((back.template head<3>() - xi.template head<3>()).norm() <=
              1e-15 * theta + 1e-15 * (theta > 1e-3));
    RC_ASSERT(maxAbsDiff(back, xi) <= 1e-14 * (1 + xi.template lpNorm<Eigen::Infinity>()));
  });
  rc::prop("Exp(Log(X)) = X", [] {
    const G X = G::Exp(*lietest::tangent<G>());
    RC_ASSERT(G::Exp(X.Log()).isApprox(X, 1e-14));
  });
  // Rotations beyond pi: Log takes the other way round, and Exp brings back the same element.
  rc::prop("Exp(Log(X)) = X beyond pi", [] {
    typename G::Tangent xi =
        *lietest::tangentWithCols<G>(*lietest::numCols<G>(), lietest::uniform(2.5, 6.0));
    const G X = G::Exp(xi);
    const typename G::Tangent back = X.Log();
    RC_ASSERT(back.template head<3>().norm() <= lietest::kPi + 1e-15);
    RC_ASSERT(G::Exp(back).isApprox(X, 1e-13));
  });
  rc::prop("Exp(xi) = matrix exponential of hat(xi)", [] {
    const typename G::Tangent xi = *lietest::tangent<G>();
    const Eigen::MatrixXd M = G::hat(xi);
    const Eigen::MatrixXd E = M.exp();
    RC_ASSERT(maxAbsDiff(G::Exp(xi).matrix(), E) <= 1e-14 * (1 + xi.norm()));
  });
  rc::prop("hat and vee", [] {
    const typename G::Tangent xi = *lietest::tangent<G>();
    const typename G::Matrix M = G::hat(xi);
    RC_ASSERT(G::vee(M) == xi);
    RC_ASSERT((M.template topLeftCorner<3, 3>() == lie::SO3d::hat(xi.template head<3>())));
    RC_ASSERT(M.bottomRows(M.rows() - 3).isZero(0.0));
  });
  rc::prop("the rotation part of Exp is SO(3)'s Exp, the columns are Jl(phi) rho_i", [] {
    const typename G::Tangent xi = *lietest::tangent<G>();
    const G X = G::Exp(xi);
    const Vector3d phi = xi.template head<3>();
    RC_ASSERT(X.R() == lie::SO3d::Exp(phi).matrix());
    RC_ASSERT(X.rotation().isApprox(lie::SO3d::Exp(phi), 0.0));
    const Matrix3d Jl = lie::SO3d::Jl(phi);
    for (Eigen::Index i = 0; i < X.numCols(); ++i) {
      const Vector3d rho = xi.template segment<3>(3 + 3 * i);
      RC_ASSERT(maxAbsDiff(X.col(i), Jl * rho) <= 1e-15 * (1 + rho.norm()));
    }
  });
  rc::prop("Exp is a homomorphism on a line", [] {
    const typename G::Tangent xi = *lietest::tangent<G>();
    const double s = *lietest::uniform(-1, 1), t = *lietest::uniform(-1, 1);
    const typename G::Tangent a = s * xi, b = t * xi, c = (s + t) * xi;
    RC_ASSERT((G::Exp(a) * G::Exp(b)).isApprox(G::Exp(c), 1e-14));
  });
}

TEMPLATE_TEST_CASE("SEK3 adjoint", "[lie][sek3]", lie::SE3d, lie::SE23d, SEK3_3, SEK3_6, SEKd6) {
  using G = TestType;
  rc::prop("X Exp(xi) X^-1 = Exp(Ad_X xi)", [] {
    const auto xs = *tangents<G>(2);
    const G X = G::Exp(xs[0]);
    const typename G::Tangent adXi = X.Adj() * xs[1];
    RC_ASSERT((X * G::Exp(xs[1]) * X.inverse()).isApprox(G::Exp(adXi), 1e-13 * scaleOf(X)));
  });
  rc::prop("Ad_{XY} = Ad_X Ad_Y, Ad_{X^-1} = Ad_X^-1", [] {
    const auto xs = *tangents<G>(2);
    const G X = G::Exp(xs[0]), Y = G::Exp(xs[1]);
    const double scale = scaleOf(X) * scaleOf(Y);
    RC_ASSERT(maxAbsDiff((X * Y).Adj(), X.Adj() * Y.Adj()) <= 1e-14 * scale);
    const typename G::Jacobian I = G::Jacobian::Identity(X.dof(), X.dof());
    RC_ASSERT(maxAbsDiff(X.inverse().Adj() * X.Adj(), I) <= 1e-14 * scale * scale);
  });
  // ad is the adjoint of the Lie algebra: hat(ad_a b) = [hat a, hat b].
  rc::prop("ad(a) b is the commutator", [] {
    const auto xs = *tangents<G>(2);
    const typename G::Matrix A = G::hat(xs[0]), B = G::hat(xs[1]);
    const typename G::Matrix commutator = A * B - B * A;
    const typename G::Tangent adab = G::ad(xs[0]) * xs[1];
    RC_ASSERT(maxAbsDiff(G::hat(adab), commutator) <=
              1e-14 * (1 + xs[0].squaredNorm() + xs[1].squaredNorm()));
  });
}

TEMPLATE_TEST_CASE("SEK3 plus, minus, interpolation", "[lie][sek3]", lie::SE3d, lie::SE23d, SEK3_3,
                   SEK3_6, SEKd6) {
  using G = TestType;
  rc::prop("rplus/rminus and lplus/lminus round trips", [] {
    const auto xs = *tangents<G>(2);
    const G X = G::Exp(xs[0]), Y = G::Exp(xs[1]);
    const typename G::Tangent& tau = xs[1];
    const double scale = scaleOf(X) * (1 + tau.norm());
    RC_ASSERT(maxAbsDiff(X.rplus(tau).rminus(X), tau) <= 1e-13 * scale);
    RC_ASSERT(maxAbsDiff(X.lplus(tau).lminus(X), tau) <= 1e-13 * scale * scaleOf(X));
    RC_ASSERT(X.rplus(Y.rminus(X)).isApprox(Y, 1e-13 * scaleOf(X)));
    RC_ASSERT(X.lplus(Y.lminus(X)).isApprox(Y, 1e-13 * scaleOf(X)));
    RC_ASSERT(X.rplus(tau).isApprox(X * G::Exp(tau), 0.0));
    RC_ASSERT(X.lplus(tau).isApprox(G::Exp(tau) * X, 0.0));
  });
  rc::prop("interpolate: endpoints and the geodesic", [] {
    const auto xs = *tangents<G>(2);
    const G X = G::Exp(xs[0]), Y = G::Exp(xs[1]);
    const double t = *lietest::uniform(0, 1);
    RC_ASSERT(X.interpolate(Y, 0.0).isApprox(X, 0.0));
    RC_ASSERT(X.interpolate(Y, 1.0).isApprox(Y, 1e-13 * scaleOf(X)));
    const typename G::Tangent delta = Y.rminus(X);
    const typename G::Tangent tdelta = t * delta;
    RC_ASSERT(maxAbsDiff(X.interpolate(Y, t).rminus(X), tdelta) <=
              1e-13 * scaleOf(X) * (1 + delta.norm()));
  });
  rc::prop("normalized removes rotation drift and keeps the columns", [] {
    const G X = G::Exp(*lietest::tangent<G>());
    typename G::Matrix M = X.matrix();
    M.template topLeftCorner<3, 3>() += 1e-7 * Matrix3d::Random();
    const G fixed = G::fromMatrix(M, 1e-6).normalized();
    RC_ASSERT(passesFromMatrix(fixed));
    RC_ASSERT(fixed.isApprox(X, 1e-6));
    RC_ASSERT(fixed.columns() == X.columns());
  });
}

TEMPLATE_TEST_CASE("SEK3 Random and the matrix layout", "[lie][sek3]", lie::SE3d, lie::SE23d,
                   SEK3_3, SEK3_6, SEKd6) {
  using G = TestType;
  std::mt19937 gen(11);
  for (int k = G::kDynamic ? 0 : G::K; k <= G::MaxK; ++k) {
    const G X = G::Random(gen, 10.0, k);
    CHECK(X.numCols() == k);
    CHECK(X.dof() == 3 + 3 * k);
    CHECK(passesFromMatrix(X));
    const typename G::Matrix M = X.matrix();
    CHECK(M.template topLeftCorner<3, 3>() == X.R());
    CHECK(M.topRightCorner(3, k) == X.columns());
    CHECK(M.bottomRows(k).isApprox(M.bottomRows(k)));
    for (Eigen::Index r = 0; r < k; ++r)
      for (Eigen::Index c = 0; c < 3 + k; ++c) CHECK(M(3 + r, c) == (c == 3 + r ? 1.0 : 0.0));
  }
}

TEST_CASE("SE3 translation is column 0", "[lie][sek3]") {
  const lie::SE3d X = lie::SE3d::Exp((lie::SE3d::Tangent() << 0.1, 0.2, 0.3, 1, 2, 3).finished());
  CHECK(X.translation() == X.col(0));
}

TEMPLATE_TEST_CASE("SEK3 fromMatrix rejects what is not in the group, saying why", "[lie][sek3]",
                   lie::SE3d, lie::SE23d, SEK3_3, SEK3_6, SEKd6) {
  using G = TestType;
  for (int k = G::kDynamic ? 0 : G::K; k <= G::MaxK; ++k) {
    CAPTURE(k);
    typename G::Tangent xi(3 + 3 * k);
    for (Eigen::Index i = 0; i < xi.size(); ++i) xi(i) = 0.3 * std::sin(1.0 + 2.0 * i);
    const typename G::Matrix M = G::Exp(xi).matrix();
    CHECK(rejection<G>(M).empty());
    CHECK(G::fromMatrix(M).matrix() == M);

    typename G::Matrix bad = M;
    bad(0, 1) = std::numeric_limits<double>::quiet_NaN();
    CHECK_THAT(rejection<G>(bad), Catch::Contains("NaN"));
    if (k > 0) {
      bad = M;
      bad(2, 3 + k - 1) = std::numeric_limits<double>::infinity();  // in a column, not in R
      CHECK_THAT(rejection<G>(bad), Catch::Contains("inf"));
    }
    bad = M;
    bad.template topLeftCorner<3, 3>() *= 1.01;
    CHECK_THAT(rejection<G>(bad), Catch::Contains("not orthonormal"));
    bad = M;
    bad.template topLeftCorner<3, 3>() =
        M.template topLeftCorner<3, 3>() * Vector3d(1, -1, 1).asDiagonal();
    CHECK_THAT(rejection<G>(bad), Catch::Contains("reflection"));
    if (k > 0) {
      bad = M;
      bad(3 + k - 1, 0) = 1e-6;  // last row must be [0 ... 0 1]
      CHECK_THAT(rejection<G>(bad), Catch::Contains("rows must be [0 | I]"));
      bad = M;
      bad(3, 3) = 2;  // the identity block
      CHECK_THAT(rejection<G>(bad), Catch::Contains("rows must be [0 | I]"));
      CHECK_NOTHROW(G::fromMatrix(bad, 1.5));  // the tolerance is honoured
    }
  }
}

TEST_CASE("SEKd: wrong sizes are rejected with a message", "[lie][sek3]") {
  // A non-square matrix is no element of any SE_K(3).
  const SEKd6::Matrix nonSquare = SEKd6::Matrix::Identity(4, 5);
  CHECK_THAT(rejection<SEKd6>(nonSquare),
             Catch::Contains("expected a square matrix") && Catch::Contains("4x5"));
  const SEKd6::Matrix tooSmall = SEKd6::Matrix::Identity(2, 2);
  CHECK_THAT(rejection<SEKd6>(tooSmall), Catch::Contains("expected a square matrix"));
  // The run-time group holds 0 columns too (its default): a 3x3 rotation is its matrix.
  CHECK(SEKd6().numCols() == 0);
  CHECK(rejection<SEKd6>(SEKd6::Matrix::Identity(3, 3)).empty());

  // A tangent vector whose size is not 3 + 3k.
  SEKd6::Tangent xi = SEKd6::Tangent::Zero(5);
  CHECK_THROWS_WITH(SEKd6::Exp(xi), Catch::Contains("not 3 + 3K"));
  CHECK_THROWS_WITH(SEKd6::ad(xi), Catch::Contains("not 3 + 3K"));
  // Fixed K: a column count other than K.
  CHECK_THROWS_WITH(lie::SE23d(3), Catch::Contains("exactly 2"));
  // (volatile: GCC would otherwise propagate the constant 7 past the throw and warn about
  // the unreachable setZero(3, 7).)
  volatile Eigen::Index tooMany = 7;
  CHECK_THROWS_WITH(SEKd6(tooMany), Catch::Contains("at most 6"));
  // Operands with different numbers of columns.
  CHECK_THROWS_WITH(SEKd6(2) * SEKd6(3), Catch::Contains("2 and 3 columns"));
}

TEST_CASE("SEKd: appendColumn and removeColumn", "[lie][sek3]") {
  std::mt19937 gen(5);
  SEKd6 X = SEKd6::Random(gen, 3.0, 0);
  const Matrix3d R = X.R();
  std::vector<Vector3d> cols;
  for (int k = 1; k <= 6; ++k) {
    const Vector3d c(k, -2.0 * k, 0.5 + k);
    X.appendColumn(c);
    cols.push_back(c);
    REQUIRE(X.numCols() == k);
    CHECK(X.dof() == 3 + 3 * k);
    CHECK(X.col(k - 1) == c);
    CHECK(X.R() == R);
    CHECK(passesFromMatrix(X));
  }
  // Beyond MaxK: an error that says so, and X is unchanged.
  CHECK_THROWS_WITH(X.appendColumn(Vector3d::Ones()), Catch::Contains("at most 6"));
  CHECK(X.numCols() == 6);

  // Removing column i shifts the later columns down and keeps the order.
  X.removeColumn(2);
  cols.erase(cols.begin() + 2);
  REQUIRE(X.numCols() == 5);
  for (int i = 0; i < 5; ++i) CHECK(X.col(i) == cols[i]);
  X.removeColumn(4);  // the last one
  cols.pop_back();
  X.removeColumn(0);  // the first one
  cols.erase(cols.begin());
  REQUIRE(X.numCols() == 3);
  for (int i = 0; i < 3; ++i) CHECK(X.col(i) == cols[i]);
  CHECK(X.R() == R);
  CHECK_THROWS_AS(X.removeColumn(3), std::out_of_range);
  CHECK_THROWS_AS(X.removeColumn(-1), std::out_of_range);
  CHECK_THROWS_WITH(X.removeColumn(3), Catch::Contains("no such column"));
  CHECK(X.numCols() == 3);
  while (X.numCols() > 0) X.removeColumn(0);
  CHECK(X.matrix() == (SEKd6::Matrix(3, 3) << R).finished());
  CHECK_THROWS_AS(X.removeColumn(0), std::out_of_range);

  // The edited element is a group element like any other: Exp/Log and products work at every k.
  for (int k = 0; k <= 6; ++k) {
    const SEKd6 Y = SEKd6::Random(gen, 3.0, k);
    CHECK(SEKd6::Exp(Y.Log()).isApprox(Y, 1e-13));
    CHECK((Y * Y.inverse()).isApprox(SEKd6::Identity(k), 1e-13));
  }
}

// Appending a column c to X is the same as building the larger element directly: the existing
// part of the Log is unchanged (each column couples to the rotation only).
TEST_CASE("SEKd: Log of an appended element extends the old Log", "[lie][sek3]") {
  rc::prop("appendColumn", [] {
    const SEKd6::Tangent xi = *lietest::tangentWithCols<SEKd6>(
        *rc::gen::resize(rc::kNominalSize, rc::gen::inRange(0, 6)), lietest::hardAngle());
    SEKd6 X = SEKd6::Exp(xi);
    const Vector3d c = *lietest::translation();
    X.appendColumn(c);
    const SEKd6::Tangent back = X.Log();
    RC_ASSERT(maxAbsDiff(back.head(xi.size()), xi) <= 1e-14 * (1 + xi.norm()));
    RC_ASSERT(maxAbsDiff(back.tail<3>(), lie::SO3d::JlInv(xi.head<3>()) * c) <=
              1e-14 * (1 + c.norm()));
  });
}
