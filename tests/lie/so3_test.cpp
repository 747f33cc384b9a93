// Properties of lie::SO3: group axioms, Exp/Log, adjoint, Jacobians and the optional Jacobian
// outputs (against central differences), plus/minus, interpolation, checked construction.
// Every property draws angles from lietest::hardAngle(): 0, ~1e-12, ~1e-8, the series switch
// points, moderate angles and pi - 1e-9 .. pi - 1e-4.
#include <rapidcheck/catch.h>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <unsupported/Eigen/MatrixFunctions>
#include <vector>

#include "lie_test_support.hpp"

using Eigen::Matrix3d;
using Eigen::Vector3d;
using lie::SO3d;
using lietest::centralDifference;
using lietest::hardAngle;
using lietest::maxAbsDiff;
using lietest::rotationVector;
using lietest::rotationVectors;

namespace {

// Right-perturbation difference of two rotations as a rotation vector: Log(A^-1 B).
Vector3d rdiff(const SO3d& A, const SO3d& B) {
  return (A.inverse() * B).Log();
}

bool passesFromMatrix(const SO3d& X) {
  try {
    SO3d::fromMatrix(X.matrix(), 1e-12);
    return true;
  } catch (const lie::NotInGroup&) {
    return false;
  }
}

// The message of the NotInGroup that fromMatrix throws, or "" if it accepts the matrix.
std::string rejection(const Matrix3d& M) {
  try {
    SO3d::fromMatrix(M);
  } catch (const lie::NotInGroup& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("SO3 group axioms", "[lie][so3]") {
  // Products, inverses and Exp stay orthonormal to 1e-12: fromMatrix accepts them.
  rc::prop("closure", [] {
    const auto phis = *rotationVectors(2);
    const SO3d X = SO3d::Exp(phis[0]), Y = SO3d::Exp(phis[1]);
    RC_ASSERT(passesFromMatrix(X));
    RC_ASSERT(passesFromMatrix(X * Y));
    RC_ASSERT(passesFromMatrix(X.inverse()));
  });
  rc::prop("identity is neutral", [] {
    const SO3d X = SO3d::Exp(*rotationVector());
    RC_ASSERT((X * SO3d::Identity()).isApprox(X, 0.0));
    RC_ASSERT((SO3d::Identity() * X).isApprox(X, 0.0));
    RC_ASSERT(SO3d().matrix() == Matrix3d::Identity());
  });
  rc::prop("inverse", [] {
    const SO3d X = SO3d::Exp(*rotationVector());
    RC_ASSERT((X * X.inverse()).isApprox(SO3d::Identity(), 1e-14));
    RC_ASSERT((X.inverse() * X).isApprox(SO3d::Identity(), 1e-14));
  });
  rc::prop("associativity", [] {
    const auto phis = *rotationVectors(3);
    const SO3d X = SO3d::Exp(phis[0]), Y = SO3d::Exp(phis[1]), Z = SO3d::Exp(phis[2]);
    RC_ASSERT(((X * Y) * Z).isApprox(X * (Y * Z), 1e-14));
  });
  rc::prop("act is the matrix product, and a homomorphism", [] {
    const auto phis = *rotationVectors(2);
    const SO3d X = SO3d::Exp(phis[0]), Y = SO3d::Exp(phis[1]);
    const Vector3d x = *lietest::translation();
    RC_ASSERT(maxAbsDiff(X.act(x), X.matrix() * x) <= 1e-14 * (1 + x.norm()));
    RC_ASSERT(maxAbsDiff(X * x, X.matrix() * x) <= 1e-14 * (1 + x.norm()));
    RC_ASSERT(maxAbsDiff((X * Y).act(x), X.act(Y.act(x))) <= 1e-14 * (1 + x.norm()));
  });
}

TEST_CASE("SO3 Exp and Log", "[lie][so3]") {
  // theta < pi, so Log must return phi itself; the error is relative to |phi| (tiny angles
  // keep full relative precision) with a floor of a few ulp of pi.
  rc::prop("Log(Exp(phi)) = phi", [] {
    const Vector3d phi = *rotationVector();
    const Vector3d back = SO3d::Exp(phi).Log();
    RC_ASSERT((back - phi).norm() <= 1e-15 * phi.norm() + 1e-15 * (phi.norm() > 1e-3));
  });
  rc::prop("Exp(Log(X)) = X", [] {
    const SO3d X = SO3d::Exp(*rotationVector());
    RC_ASSERT(SO3d::Exp(X.Log()).isApprox(X, 1e-14));
  });
  // Near pi, X and Exp(phi') with |phi'| > pi are the same rotation: compare rotations.
  rc::prop("Log is in the closed ball of radius pi", [] {
    const Vector3d phi = *rotationVector(lietest::uniform(2.5, 2 * lietest::kPi - 0.1));
    const SO3d X = SO3d::Exp(phi);
    const Vector3d back = X.Log();
    RC_ASSERT(back.norm() <= lietest::kPi + 1e-15);
    RC_ASSERT(SO3d::Exp(back).isApprox(X, 1e-14));
  });
  rc::prop("Exp(phi) = matrix exponential of hat(phi)", [] {
    const Vector3d phi = *rotationVector();
    const Matrix3d E = SO3d::hat(phi).exp();
    RC_ASSERT(maxAbsDiff(SO3d::Exp(phi).matrix(), E) <= 1e-14);
  });
  rc::prop("hat and vee", [] {
    const Vector3d phi = *rotationVector(), x = *lietest::translation();
    RC_ASSERT(SO3d::vee(SO3d::hat(phi)) == phi);
    RC_ASSERT(maxAbsDiff(SO3d::hat(phi) * x, phi.cross(x)) <= 1e-15 * phi.norm() * x.norm());
  });
  rc::prop("quaternion round trip", [] {
    const SO3d X = SO3d::Exp(*rotationVector());
    RC_ASSERT(SO3d::fromQuaternion(X.quaternion()).isApprox(X, 1e-14));
    // fromQuaternion normalises its input.
    RC_ASSERT(
        SO3d::fromQuaternion(Eigen::Quaterniond(X.quaternion().coeffs() * 3.0)).isApprox(X, 1e-14));
  });
  // One-parameter subgroup: Exp(s phi) Exp(t phi) = Exp((s+t) phi).
  rc::prop("Exp is a homomorphism on a line", [] {
    const Vector3d phi = *rotationVector();
    const double s = *lietest::uniform(-1, 1), t = *lietest::uniform(-1, 1);
    RC_ASSERT((SO3d::Exp(s * phi) * SO3d::Exp(t * phi)).isApprox(SO3d::Exp((s + t) * phi), 1e-14));
  });
}

// SO3::logOfMatrix changes formula where sin theta = |cos theta| (theta = pi/4 and 3 pi/4: which
// asin is taken) and at cos theta = SO3::kNearPiCos (theta ~ 2.69: where the axis comes from).
// On both sides of each switch, and at the ends 0 and pi, Log of the double matrix R must agree
// with an independent long-double Log of the same R (Eigen's AngleAxis: quaternion and atan2),
// so the comparison measures Log alone, not the rounding of Exp.
TEST_CASE("SO3 Log is accurate on both sides of its switches", "[lie][so3]") {
  using LD = long double;
  const double nearPi = std::acos(double(SO3d::kNearPiCos));
  std::vector<double> angles = {0.0, 1e-300, 1e-150, 1e-12, 1e-4, 0.3, 1.7, 3.0, lietest::kPi};
  for (const double sw : {lietest::kPi / 4, 3 * lietest::kPi / 4, nearPi}) {
    for (const double rel : {0.0, 1e-15, 1e-12, 1e-6, 1e-3}) {
      angles.push_back(sw * (1 + rel));
      angles.push_back(sw * (1 - rel));
    }
  }
  std::mt19937 gen(5);
  std::normal_distribution<double> n01;
  double worst = 0;
  for (const double theta : angles) {
    for (int r = 0; r < 200; ++r) {
      Vector3d u(n01(gen), n01(gen), n01(gen));
      if (r < 6) u = Vector3d::Unit(r % 3) * (r < 3 ? 1.0 : -1.0);  // the axes, both signs
      const Matrix3d R = SO3d::Exp(theta * u.normalized()).matrix();
      const Eigen::AngleAxis<LD> ref(R.cast<LD>());
      const Eigen::Matrix<LD, 3, 1> phiRef = ref.angle() * ref.axis();
      const Vector3d phi = SO3d::fromMatrix(R).Log();
      // At pi, phi and -phi are the same rotation: compare with the nearer one.
      const LD err = std::min((phi.cast<LD>() - phiRef).norm(), (phi.cast<LD>() + phiRef).norm());
      const double rel = double(err / std::max(LD(1e-300), phiRef.norm()));
      CAPTURE(theta, u.transpose(), phi.transpose(), rel);
      CHECK(rel <= 1e-15);
      worst = std::max(worst, rel);
    }
  }
  // Just below and above kNearPiCos the two axis formulas agree to rounding.
  const Vector3d u = Vector3d(0.3, -0.5, 0.8).normalized();
  const Vector3d below = SO3d::Exp(std::nextafter(nearPi, 0.0) * u).Log();
  const Vector3d above = SO3d::Exp(std::nextafter(nearPi, 4.0) * u).Log();
  CHECK((below - above).norm() <= 2e-15);
  CHECK(worst > 0);  // the grid did reach angles where rounding shows
}

TEST_CASE("SO3 adjoint", "[lie][so3]") {
  rc::prop("X Exp(phi) X^-1 = Exp(Ad_X phi)", [] {
    const auto phis = *rotationVectors(2);
    const SO3d X = SO3d::Exp(phis[0]);
    RC_ASSERT((X * SO3d::Exp(phis[1]) * X.inverse()).isApprox(SO3d::Exp(X.Adj() * phis[1]), 1e-14));
  });
  rc::prop("Ad_{XY} = Ad_X Ad_Y", [] {
    const auto phis = *rotationVectors(2);
    const SO3d X = SO3d::Exp(phis[0]), Y = SO3d::Exp(phis[1]);
    RC_ASSERT(maxAbsDiff((X * Y).Adj(), X.Adj() * Y.Adj()) <= 1e-14);
  });
  rc::prop("ad(phi) = hat(phi), the commutator", [] {
    const auto phis = *rotationVectors(2);
    const Matrix3d commutator =
        SO3d::hat(phis[0]) * SO3d::hat(phis[1]) - SO3d::hat(phis[1]) * SO3d::hat(phis[0]);
    RC_ASSERT(maxAbsDiff(SO3d::hat(SO3d::ad(phis[0]) * phis[1]), commutator) <= 1e-14);
  });
}

TEST_CASE("SO3 Jacobians", "[lie][so3]") {
  rc::prop("Jr(phi) = Jl(-phi)", [] {
    const Vector3d phi = *rotationVector();
    RC_ASSERT(SO3d::Jr(phi) == SO3d::Jl(-phi));
    RC_ASSERT(SO3d::JrInv(phi) == SO3d::JlInv(-phi));
  });
  rc::prop("J J^-1 = I", [] {
    const Vector3d phi = *rotationVector();
    RC_ASSERT(maxAbsDiff(SO3d::Jr(phi) * SO3d::JrInv(phi), Matrix3d::Identity()) <= 1e-14);
    RC_ASSERT(maxAbsDiff(SO3d::Jl(phi) * SO3d::JlInv(phi), Matrix3d::Identity()) <= 1e-14);
  });
  // Jl = Exp(phi) Jr, i.e. Jl = Ad_{Exp(phi)} Jr.
  rc::prop("Jl(phi) = Exp(phi) Jr(phi)", [] {
    const Vector3d phi = *rotationVector();
    RC_ASSERT(maxAbsDiff(SO3d::Jl(phi), SO3d::Exp(phi).matrix() * SO3d::Jr(phi)) <= 1e-14);
  });
  rc::prop("Gamma_0 = Exp, Gamma_1 = Jl", [] {
    const Vector3d phi = *rotationVector();
    RC_ASSERT(maxAbsDiff(lie::Gamma<0>(phi), SO3d::Exp(phi).matrix()) <= 1e-14);
    RC_ASSERT(maxAbsDiff(lie::Gamma<1>(phi), SO3d::Jl(phi)) <= 1e-14);
  });
  // The defining property, Exp(phi + d) = Exp(phi) Exp(Jr d) = Exp(Jl d) Exp(phi), by central
  // differences (truncation ~h^2, rounding ~eps/h: 1e-8 is far above both).
  rc::prop("Jr and Jl by central differences", [] {
    const Vector3d phi = *rotationVector();
    const SO3d X = SO3d::Exp(phi);
    const Eigen::MatrixXd Jr = centralDifference(
        [&](const Eigen::VectorXd& d) { return rdiff(X, SO3d::Exp(phi + d)); }, 3);
    const Eigen::MatrixXd Jl = centralDifference(
        [&](const Eigen::VectorXd& d) {
          return Vector3d((SO3d::Exp(phi + d) * X.inverse()).Log());
        },
        3);
    RC_ASSERT(maxAbsDiff(SO3d::Jr(phi), Jr) <= 1e-8);
    RC_ASSERT(maxAbsDiff(SO3d::Jl(phi), Jl) <= 1e-8);
  });
  rc::prop("optional Jacobians of compose, inverse, act", [] {
    const auto phis = *rotationVectors(2);
    const SO3d X = SO3d::Exp(phis[0]), Y = SO3d::Exp(phis[1]);
    const Vector3d x = *lietest::translation();
    Matrix3d J_XY_X, J_XY_Y, J_inv, J_act_X, J_act_x;
    const SO3d XY = X.compose(Y, &J_XY_X, &J_XY_Y);
    const SO3d Xi = X.inverse(&J_inv);
    const Vector3d y = X.act(x, &J_act_X, &J_act_x);
    RC_ASSERT(XY.isApprox(X * Y, 0.0));
    RC_ASSERT(maxAbsDiff(y, X.matrix() * x) == 0.0);
    const auto num = [](auto f) { return centralDifference(f, 3); };
    using V = Eigen::VectorXd;
    RC_ASSERT(maxAbsDiff(J_XY_X, num([&](const V& d) { return rdiff(XY, X.rplus(d) * Y); })) <=
              1e-8);
    RC_ASSERT(maxAbsDiff(J_XY_Y, num([&](const V& d) { return rdiff(XY, X * Y.rplus(d)); })) <=
              1e-8);
    RC_ASSERT(maxAbsDiff(J_inv, num([&](const V& d) { return rdiff(Xi, X.rplus(d).inverse()); })) <=
              1e-8);
    const double scale = 1 + x.norm();
    RC_ASSERT(maxAbsDiff(J_act_X, num([&](const V& d) { return Vector3d(X.rplus(d).act(x)); })) <=
              1e-8 * scale);
    RC_ASSERT(maxAbsDiff(J_act_x, num([&](const V& d) { return Vector3d(X.act(x + d)); })) <=
              1e-8 * scale);
  });
  // Log is differentiated away from pi, where it is not continuous.
  rc::prop("optional Jacobians of Exp and Log", [] {
    const Vector3d phi = *rotationVector(hardAngle(1e-2));
    Matrix3d J_exp, J_log;
    const SO3d X = SO3d::Exp(phi, &J_exp);
    const Vector3d back = X.Log(&J_log);
    RC_ASSERT(X.isApprox(SO3d::Exp(phi), 0.0));
    RC_ASSERT(back == X.Log());
    using V = Eigen::VectorXd;
    RC_ASSERT(maxAbsDiff(J_exp, centralDifference(
                                    [&](const V& d) { return rdiff(X, SO3d::Exp(phi + d)); }, 3)) <=
              1e-8);
    RC_ASSERT(maxAbsDiff(J_log, centralDifference(
                                    [&](const V& d) { return Vector3d(X.rplus(d).Log()); }, 3)) <=
              1e-8);
  });
}

TEST_CASE("SO3 plus, minus, interpolation", "[lie][so3]") {
  rc::prop("rplus/rminus and lplus/lminus round trips", [] {
    const auto phis = *rotationVectors(2);
    const SO3d X = SO3d::Exp(phis[0]);
    const Vector3d& tau = phis[1];
    // Both directions: tau -> Y -> tau (needs |tau| < pi), and Y -> tau -> Y.
    RC_ASSERT((X.rplus(tau).rminus(X) - tau).norm() <= 1e-14);
    RC_ASSERT((X.lplus(tau).lminus(X) - tau).norm() <= 1e-14);
    const SO3d Y = SO3d::Exp(tau);
    RC_ASSERT(X.rplus(Y.rminus(X)).isApprox(Y, 1e-14));
    RC_ASSERT(X.lplus(Y.lminus(X)).isApprox(Y, 1e-14));
    RC_ASSERT(X.rplus(tau).isApprox(X * SO3d::Exp(tau), 0.0));
    RC_ASSERT(X.lplus(tau).isApprox(SO3d::Exp(tau) * X, 0.0));
  });
  rc::prop("interpolate: endpoints and the geodesic", [] {
    const auto phis = *rotationVectors(2);
    const SO3d X = SO3d::Exp(phis[0]), Y = SO3d::Exp(phis[1]);
    const double t = *lietest::uniform(0, 1);
    RC_ASSERT(X.interpolate(Y, 0.0).isApprox(X, 0.0));
    RC_ASSERT(X.interpolate(Y, 1.0).isApprox(Y, 1e-14));
    // On the geodesic, the distance from X grows linearly with t.
    const Vector3d delta = Y.rminus(X);
    RC_ASSERT((X.interpolate(Y, t).rminus(X) - t * delta).norm() <= 1e-14);
  });
  rc::prop("normalized removes drift and keeps the rotation", [] {
    const SO3d X = SO3d::Exp(*rotationVector());
    const Matrix3d noise = 1e-7 * Matrix3d::Random();
    const SO3d fixed = SO3d::fromMatrix((X.matrix() + noise).eval(), 1e-6).normalized();
    RC_ASSERT(passesFromMatrix(fixed));
    RC_ASSERT(fixed.isApprox(X, 1e-6));
  });
}

TEST_CASE("SO3 Random is a rotation", "[lie][so3]") {
  std::mt19937 gen(7);
  for (int i = 0; i < 100; ++i) CHECK(passesFromMatrix(SO3d::Random(gen)));
}

TEST_CASE("SO3 fromMatrix rejects what is not a rotation, saying why", "[lie][so3]") {
  const Matrix3d R = SO3d::Exp(Vector3d(0.3, -0.2, 0.9)).matrix();
  CHECK(rejection(R).empty());
  CHECK(SO3d::fromMatrix(R).matrix() == R);

  Matrix3d nan = R;
  nan(1, 2) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THAT(rejection(nan), Catch::Contains("NaN"));
  Matrix3d inf = R;
  inf(0, 0) = std::numeric_limits<double>::infinity();
  CHECK_THAT(rejection(inf), Catch::Contains("inf"));

  CHECK_THAT(rejection(1.01 * R), Catch::Contains("not orthonormal"));
  CHECK_THAT(rejection(Matrix3d::Zero()), Catch::Contains("not orthonormal"));
  Matrix3d sheared = R;
  sheared(0, 1) += 1e-6;
  CHECK_THAT(rejection(sheared), Catch::Contains("not orthonormal"));
  // The tolerance is honoured both ways.
  CHECK_NOTHROW(SO3d::fromMatrix(sheared, 1e-5));

  const Matrix3d reflection = R * Eigen::Vector3d(1, 1, -1).asDiagonal();
  CHECK_THAT(rejection(reflection), Catch::Contains("reflection"));
  CHECK_THAT(rejection(-Matrix3d::Identity()), Catch::Contains("reflection"));
  CHECK_THROWS_AS(SO3d::fromMatrix(reflection), std::invalid_argument);
}
