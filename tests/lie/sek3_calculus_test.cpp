// Calculus of lie::SEK3 for K = 1, 2, 3, 6 and the run-time SEKd<double, 6>: the Jacobians
// Jr, Jl and their inverses (identities and central differences) and the optional Jacobian
// outputs of compose, inverse, act, Exp and Log against central differences.
// tests/lie/jacobian_test.cpp compares the same Jacobians with a long-double series to 1e-12.
#include <rapidcheck/catch.h>
#include <catch2/catch.hpp>

#include "lie_test_support.hpp"

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using lietest::centralDifference;
using lietest::maxAbsDiff;
using lietest::tangents;

using SEK3_3 = lie::SEK3<double, 3>;
using SEK3_6 = lie::SEK3<double, 6>;
using SEKd6 = lie::SEKd<double, 6>;

namespace {

// Right-perturbation difference as a tangent vector: Log(A^-1 B).
template <typename Group>
VectorXd rdiff(const Group& A, const Group& B) {
  return (A.inverse() * B).Log();
}

template <typename Group>
typename Group::Tangent plusVec(const typename Group::Tangent& xi, const VectorXd& d) {
  return xi + d;
}

// Central differences with step 1e-6 in a function of scale s (columns up to ~10 here): the
// rounding error is ~eps s / h ~ 1e-9 s and the truncation ~h^2 s, so 1e-7 s is a safe bound
// that still catches any wrong term of a Jacobian.
double ndTol(double scale) {
  return 1e-7 * scale;
}

}  // namespace

TEMPLATE_TEST_CASE("SEK3 Jacobian identities", "[lie][sek3][jacobian]", lie::SE3d, lie::SE23d,
                   SEK3_3, SEK3_6, SEKd6) {
  using G = TestType;
  using Tangent = typename G::Tangent;
  rc::prop("Jr(xi) = Jl(-xi)", [] {
    const Tangent xi = *lietest::tangent<G>();
    const Tangent minus = -xi;
    RC_ASSERT(G::Jr(xi) == G::Jl(minus));
    RC_ASSERT(G::JrInv(xi) == G::JlInv(minus));
  });
  rc::prop("J J^-1 = I for Jr and Jl", [] {
    const Tangent xi = *lietest::tangent<G>();
    const auto I = G::Jacobian::Identity(xi.size(), xi.size());
    const double scale = 1 + xi.squaredNorm();
    RC_ASSERT(maxAbsDiff(G::Jr(xi) * G::JrInv(xi), I) <= 1e-14 * scale);
    RC_ASSERT(maxAbsDiff(G::Jl(xi) * G::JlInv(xi), I) <= 1e-14 * scale);
    RC_ASSERT(maxAbsDiff(G::JlInv(xi) * G::Jl(xi), I) <= 1e-14 * scale);
  });
  // Jl(xi) = Ad_{Exp(xi)} Jr(xi): the two perturbation sides are related by the adjoint.
  rc::prop("Jl = Ad_{Exp(xi)} Jr", [] {
    const Tangent xi = *lietest::tangent<G>();
    RC_ASSERT(maxAbsDiff(G::Jl(xi), G::Exp(xi).Adj() * G::Jr(xi)) <=
              1e-14 * (1 + xi.squaredNorm()));
  });
  // The defining property Exp(xi + d) = Exp(xi) Exp(Jr d) = Exp(Jl d) Exp(xi).
  rc::prop("Jr and Jl by central differences", [] {
    const Tangent xi = *lietest::tangent<G>();
    const G X = G::Exp(xi);
    const MatrixXd Jr = centralDifference(
        [&](const VectorXd& d) { return rdiff(X, G::Exp(plusVec<G>(xi, d))); }, xi.size());
    const MatrixXd Jl = centralDifference(
        [&](const VectorXd& d) {
          return VectorXd((G::Exp(plusVec<G>(xi, d)) * X.inverse()).Log());
        },
        xi.size());
    const double tol = ndTol(1 + xi.squaredNorm());
    RC_ASSERT(maxAbsDiff(G::Jr(xi), Jr) <= tol);
    RC_ASSERT(maxAbsDiff(G::Jl(xi), Jl) <= tol);
  });
}

TEMPLATE_TEST_CASE("SEK3 optional Jacobian outputs", "[lie][sek3][jacobian]", lie::SE3d, lie::SE23d,
                   SEK3_3, SEK3_6, SEKd6) {
  using G = TestType;
  using Tangent = typename G::Tangent;
  using Jacobian = typename G::Jacobian;
  rc::prop("compose and inverse", [] {
    const auto xs = *tangents<G>(2);
    const G X = G::Exp(xs[0]), Y = G::Exp(xs[1]);
    const Eigen::Index n = X.dof();
    Jacobian J_XY_X, J_XY_Y, J_inv;
    const G XY = X.compose(Y, &J_XY_X, &J_XY_Y);
    const G Xi = X.inverse(&J_inv);
    RC_ASSERT(XY.isApprox(X * Y, 0.0));
    RC_ASSERT(Xi.isApprox(X.inverse(), 0.0));
    const double tol = ndTol((1 + xs[0].squaredNorm()) * (1 + xs[1].squaredNorm()));
    const auto num = [n](auto f) { return centralDifference(f, n); };
    RC_ASSERT(maxAbsDiff(J_XY_X,
                         num([&](const VectorXd& d) { return rdiff(XY, X.rplus(d) * Y); })) <= tol);
    RC_ASSERT(maxAbsDiff(J_XY_Y,
                         num([&](const VectorXd& d) { return rdiff(XY, X * Y.rplus(d)); })) <= tol);
    RC_ASSERT(maxAbsDiff(J_inv, num([&](const VectorXd& d) {
                           return rdiff(Xi, X.rplus(d).inverse());
                         })) <= tol);
  });
  rc::prop("act", [] {
    const G X = G::Exp(*lietest::tangent<G>());
    RC_PRE(X.numCols() > 0);
    const Eigen::Index i = *rc::gen::inRange<int>(0, int(X.numCols()));
    const Vector3d x = *lietest::translation();
    Eigen::Matrix<double, 3, G::DoF, 0, 3, G::MaxDoF> J_X;
    Matrix3d J_x;
    const Vector3d y = X.act(x, i, &J_X, &J_x);
    RC_ASSERT(y == X.act(x, i));
    const MatrixXd numX = centralDifference(
        [&](const VectorXd& d) { return VectorXd(X.rplus(d).act(x, i)); }, X.dof());
    const MatrixXd numx =
        centralDifference([&](const VectorXd& d) { return VectorXd(X.act(x + d, i)); }, 3);
    const double tol = ndTol(1 + x.norm());
    RC_ASSERT(maxAbsDiff(J_X, numX) <= tol);
    RC_ASSERT(maxAbsDiff(J_x, numx) <= tol);
  });
  rc::prop("Exp", [] {
    const Tangent xi = *lietest::tangent<G>();
    Jacobian J;
    const G X = G::Exp(xi, &J);
    RC_ASSERT(X.isApprox(G::Exp(xi), 0.0));
    const MatrixXd num = centralDifference(
        [&](const VectorXd& d) { return rdiff(X, G::Exp(plusVec<G>(xi, d))); }, xi.size());
    RC_ASSERT(maxAbsDiff(J, num) <= ndTol(1 + xi.squaredNorm()));
  });
  // Log is differentiated away from pi, where it is not continuous.
  rc::prop("Log", [] {
    const Tangent xi = *lietest::tangent<G>(lietest::hardAngle(1e-2));
    const G X = G::Exp(xi);
    Jacobian J;
    const Tangent back = X.Log(&J);
    RC_ASSERT(back == X.Log());
    const MatrixXd num =
        centralDifference([&](const VectorXd& d) { return VectorXd(X.rplus(d).Log()); }, xi.size());
    RC_ASSERT(maxAbsDiff(J, num) <= ndTol(1 + xi.squaredNorm()));
  });
}
