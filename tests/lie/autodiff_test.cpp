// lie/ with automatic differentiation: every group operation evaluated in ceres::Jet and in
// Eigen::AutoDiffScalar (dynamic and fixed-size derivative vectors) must give the closed-form
// Jacobians that lie/ computes in double:
//   Exp:     vee(Exp(phi)^-1 dExp(phi + d)/dd)          = Jr(phi)          (J_out_xi of Exp)
//   Log:     dLog(X Exp(d))/dd                           = Jr^-1(Log X)     (J_out_this of Log)
//   act:     d(X Exp(d)) (x + dx)/d(d, dx)               = [J_out_this, J_out_x]
//   compose: vee((XY)^-1 d(X Exp(d1) Y Exp(d2))/d(d1, d2)) = [J_out_this, J_out_other]
//   inverse: vee(X d(X Exp(d))^-1/dd)                    = J_out_this
// at random tangents whose angles include 0, 1e-9 .. 1e-4 (the series paths: no sqrt(0) may
// reach a derivative) and pi - 1e-2 .. pi - 1e-3. The derivatives are read at d = 0.
// Tolerance: 1e-12 relative to max(1, largest entry of the closed form), Log near pi included
// (kLogNearPiTol, see there). The worst errors are printed when the program ends.
#include <ceres/jet.h>
#include <rapidcheck/catch.h>
#include <catch2/catch.hpp>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <string>
#include <type_traits>
#include <unsupported/Eigen/AutoDiff>

#include "lie_test_support.hpp"

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

namespace {

constexpr double kTol = 1e-12;
// Log's derivative where theta > pi - 1e-2, kept apart so that its worst error is reported on
// its own. The same 1e-12 holds: beyond theta = 2.69 Log takes the axis from the symmetric part
// of R (no division by sin theta), and theta = pi - asin|s| divides only by cos(asin|s|) ~ 1.
// Measured: 1.2e-15 (SE23, Jet).
constexpr double kLogNearPiTol = 1e-12;

using AdDynamic = Eigen::AutoDiffScalar<VectorXd>;
template <int N>
using AdFixed = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;

// Seeding and reading of the two autodiff scalar kinds: value v with derivative e_i of R^n.
template <typename T, int N>
ceres::Jet<T, N> seed(double v, int i, int /*n*/, ceres::Jet<T, N>* /*tag*/) {
  return ceres::Jet<T, N>(v, i);
}
template <typename D>
Eigen::AutoDiffScalar<D> seed(double v, int i, int n, Eigen::AutoDiffScalar<D>* /*tag*/) {
  constexpr int kSize = D::SizeAtCompileTime;  // a fixed-size derivative vector keeps its size
  return Eigen::AutoDiffScalar<D>(v, kSize == Eigen::Dynamic ? n : kSize, i);
}
template <typename T, int N>
double valueOf(const ceres::Jet<T, N>& s) {
  return s.a;
}
template <typename D>
double valueOf(const Eigen::AutoDiffScalar<D>& s) {
  return s.value();
}
template <typename T, int N>
double derivativeOf(const ceres::Jet<T, N>& s, int i) {
  return s.v(i);
}
template <typename D>
double derivativeOf(const Eigen::AutoDiffScalar<D>& s, int i) {
  // An AutoDiffScalar that never met a seeded input keeps an empty derivative vector.
  return i < s.derivatives().size() ? s.derivatives()(i) : 0.0;
}

// x0 + d with d seeded as the n independent variables.
template <typename S>
Eigen::Matrix<S, Eigen::Dynamic, 1> seeded(const VectorXd& x0) {
  const int n = int(x0.size());
  Eigen::Matrix<S, Eigen::Dynamic, 1> x(n);
  for (int i = 0; i < n; ++i) x(i) = seed(x0(i), i, n, static_cast<S*>(nullptr));
  return x;
}

template <typename Derived>
MatrixXd valuesOf(const Eigen::MatrixBase<Derived>& m) {
  MatrixXd out(m.rows(), m.cols());
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    for (Eigen::Index c = 0; c < m.cols(); ++c) out(r, c) = valueOf(m(r, c));
  return out;
}
template <typename Derived>
MatrixXd derivativesOf(const Eigen::MatrixBase<Derived>& m, int i) {
  MatrixXd out(m.rows(), m.cols());
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    for (Eigen::Index c = 0; c < m.cols(); ++c) out(r, c) = derivativeOf(m(r, c), i);
  return out;
}

// Jacobian of a vector-valued result: column i is the derivative with respect to input i.
template <typename Derived>
MatrixXd jacobianOf(const Eigen::MatrixBase<Derived>& y, int n) {
  MatrixXd J(y.size(), n);
  for (int i = 0; i < n; ++i) J.col(i) = derivativesOf(y, i);
  return J;
}

// Right-tangent Jacobian of a group-valued result Y: column i is vee(Y^-1 dY/d_i).
template <typename GroupD, typename Derived>
MatrixXd tangentJacobianOf(const Eigen::MatrixBase<Derived>& Y, int n) {
  const typename GroupD::Matrix Y0 = valuesOf(Y);
  const typename GroupD::Matrix Yinv = GroupD::fromMatrix(Y0, 1e-6).inverse().matrix();
  MatrixXd J(GroupD::DoF, n);
  for (int i = 0; i < n; ++i) {
    const typename GroupD::Matrix dY = derivativesOf(Y, i);
    J.col(i) = GroupD::vee(Yinv * dY);
  }
  return J;
}

// Error of an autodiff Jacobian against the closed form, relative to max(1, largest entry).
double relativeError(const MatrixXd& autodiff, const MatrixXd& closedForm) {
  const double scale = std::max(1.0, closedForm.cwiseAbs().maxCoeff());
  return (autodiff - closedForm).cwiseAbs().maxCoeff() / scale;
}

// Worst error per (operation, scalar kind), printed when the test program ends.
struct WorstErrors {
  std::map<std::string, double> worst;
  void record(const std::string& what, double e) {
    double& w = worst[what];
    w = std::max(w, e);
  }
  ~WorstErrors() {
    for (const auto& [what, e] : worst) std::cout << "worst " << what << ": " << e << "\n";
  }
};
WorstErrors& worstErrors() {
  static WorstErrors w;
  return w;
}
bool within(const std::string& what, double e, double tol = kTol) {
  worstErrors().record(what, e);
  return e <= tol;
}

// The group with scalar S whose matrix is the double group X's.
template <typename S>
lie::SO3<S> cast(const lie::SO3d& X) {
  return lie::SO3<S>::fromMatrix(X.matrix().cast<S>());
}
template <typename S, int K>
lie::SEK3<S, K> cast(const lie::SEK3<double, K>& X) {
  return lie::SEK3<S, K>(cast<S>(X.rotation()), X.columns().template cast<S>());
}

// Angles: exactly 0, the small-angle series region 1e-9 .. 1e-4, moderate, and near pi.
rc::Gen<double> autodiffAngle() {
  return rc::gen::weightedOneOf<double>({
      {1, rc::gen::just(0.0)},
      {3, lietest::logUniform(1e-9, 1e-4)},
      {3, lietest::uniform(1e-4, 3.0)},
      {1, rc::gen::map(lietest::logUniform(1e-3, 1e-2),
                       [](double gap) { return lietest::kPi - gap; })},
  });
}

// A tangent of the double group: a rotation vector for SO3, (phi, rho_1..rho_K) for SE_K(3).
template <typename GD>
typename GD::Tangent randomTangent() {
  if constexpr (std::is_same_v<GD, lie::SO3d>) {
    return *lietest::rotationVector(autodiffAngle());
  } else {
    return *lietest::tangent<GD>(autodiffAngle());
  }
}

// The five checks of the file comment for one group and one autodiff scalar S; `name` labels
// the worst errors.
template <template <typename> class Group, typename S>
void checkGroup(const std::string& name) {
  using GD = Group<double>;
  using GS = Group<S>;
  constexpr int n = GD::DoF;
  using TangentS = typename GS::Tangent;

  rc::prop(name + " Exp", [&] {
    const auto xi = randomTangent<GD>();
    typename GD::Jacobian Jr;
    GD::Exp(xi, &Jr);
    const TangentS d = seeded<S>(VectorXd::Zero(n));
    const auto Y = GS::Exp(TangentS(xi.template cast<S>() + d)).matrix();
    RC_ASSERT(within(name + " Exp", relativeError(tangentJacobianOf<GD>(Y, n), Jr)));
  });

  rc::prop(name + " Log", [&] {
    const GD X = GD::Exp(randomTangent<GD>());
    typename GD::Jacobian JrInv;
    const typename GD::Tangent phi = X.Log(&JrInv);
    const TangentS d = seeded<S>(VectorXd::Zero(n));
    const TangentS y = (cast<S>(X) * GS::Exp(d)).Log();
    const bool nearPi = phi.template head<3>().norm() > lietest::kPi - 1e-2;
    RC_ASSERT(within(name + (nearPi ? " Log near pi" : " Log"),
                     relativeError(jacobianOf(y, n), JrInv), nearPi ? kLogNearPiTol : kTol));
  });

  rc::prop(name + " act", [&] {
    const GD X = GD::Exp(randomTangent<GD>());
    const Vector3d x = *lietest::translation();
    Eigen::Matrix<double, 3, n> J_this;
    Matrix3d J_x;
    MatrixXd closedForm(3, n + 3);
    const auto d = seeded<S>(VectorXd::Zero(n + 3));
    const TangentS dX = d.head(n);
    const lie::Vector3<S> dx = d.tail(3);
    lie::Vector3<S> y;
    if constexpr (std::is_same_v<GD, lie::SO3d>) {
      X.act(x, &J_this, &J_x);
      y = (cast<S>(X) * GS::Exp(dX)).act(x.cast<S>() + dx);
    } else {
      const int column = *rc::gen::inRange(0, int(GD::K));
      X.act(x, column, &J_this, &J_x);
      y = (cast<S>(X) * GS::Exp(dX)).act(x.cast<S>() + dx, column);
    }
    closedForm << J_this, J_x;
    RC_ASSERT(within(name + " act", relativeError(jacobianOf(y, n + 3), closedForm)));
  });

  rc::prop(name + " compose", [&] {
    const GD X = GD::Exp(randomTangent<GD>());
    const GD Y = GD::Exp(randomTangent<GD>());
    typename GD::Jacobian J_X, J_Y;
    X.compose(Y, &J_X, &J_Y);
    MatrixXd closedForm(n, 2 * n);
    closedForm << J_X, J_Y;
    const auto d = seeded<S>(VectorXd::Zero(2 * n));
    const auto Z = (cast<S>(X) * GS::Exp(TangentS(d.head(n))))
                       .compose(cast<S>(Y) * GS::Exp(TangentS(d.tail(n))))
                       .matrix();
    RC_ASSERT(
        within(name + " compose", relativeError(tangentJacobianOf<GD>(Z, 2 * n), closedForm)));
  });

  rc::prop(name + " inverse", [&] {
    const GD X = GD::Exp(randomTangent<GD>());
    typename GD::Jacobian J;
    X.inverse(&J);
    const TangentS d = seeded<S>(VectorXd::Zero(n));
    const auto Z = (cast<S>(X) * GS::Exp(d)).inverse().matrix();
    RC_ASSERT(within(name + " inverse", relativeError(tangentJacobianOf<GD>(Z, n), J)));
  });
}

template <typename S>
using SE3 = lie::SEK3<S, 1>;
template <typename S>
using SE23 = lie::SEK3<S, 2>;
template <typename S>
using SEK3_3 = lie::SEK3<S, 3>;

// The free functions of lie/ (Gamma, the IMU dynamics) in scalar S, for the instantiations below.
template <typename S>
void instantiateFreeFunctions() {
  const lie::Vector3<S> w(S(0.1), S(0.2), S(0.3)), a(S(1), S(2), S(3)), g(S(0), S(0), S(-9.81));
  const S dt(0.01);
  lie::Gamma<0>(w);
  lie::Gamma<1>(w);
  lie::Gamma<2>(w);
  const lie::SEK3<S, 2> X;
  lie::imu::phi<lie::SEK3<S, 2>>(2, g, dt);
  lie::imu::phiWithBias(lie::imu::propagate(X, w, a, g, dt), w, a, g, dt);
  const lie::SEKd<S, 4> Z(3);
  lie::imu::phiWithBias(lie::imu::propagate(Z, w, a, g, dt), w, a, g, dt);
}
// (instantiated here: an explicit instantiation belongs to the template's own namespace)
template void instantiateFreeFunctions<ceres::Jet<double, 3>>();
template void instantiateFreeFunctions<AdDynamic>();

}  // namespace

// Every member of SO3 and of SE_K(3) (the run-time K, which has all of the fixed-K members and
// the column edits) compiles with both autodiff scalars, and so do the free functions.
template class lie::SO3<ceres::Jet<double, 3>>;
template class lie::SO3<AdDynamic>;
template class lie::SEK3<ceres::Jet<double, 3>, Eigen::Dynamic, 4>;
template class lie::SEK3<AdDynamic, Eigen::Dynamic, 4>;

TEST_CASE("SO3 autodiff derivatives equal the closed-form Jacobians", "[lie][autodiff]") {
  checkGroup<lie::SO3, ceres::Jet<double, 6>>("SO3 Jet");
  checkGroup<lie::SO3, AdDynamic>("SO3 AutoDiffScalar<VectorXd>");
  checkGroup<lie::SO3, AdFixed<6>>("SO3 AutoDiffScalar<Vector6d>");
}

TEST_CASE("SE3 autodiff derivatives equal the closed-form Jacobians", "[lie][autodiff]") {
  checkGroup<SE3, ceres::Jet<double, 12>>("SE3 Jet");
  checkGroup<SE3, AdDynamic>("SE3 AutoDiffScalar<VectorXd>");
}

TEST_CASE("SE23 autodiff derivatives equal the closed-form Jacobians", "[lie][autodiff]") {
  checkGroup<SE23, ceres::Jet<double, 18>>("SE23 Jet");
  checkGroup<SE23, AdDynamic>("SE23 AutoDiffScalar<VectorXd>");
}

TEST_CASE("SE_K(3) with K = 3 in AutoDiffScalar<VectorXd>", "[lie][autodiff]") {
  checkGroup<SEK3_3, AdDynamic>("SEK3<3> AutoDiffScalar<VectorXd>");
}

// normalized() of an autodiff rotation (Newton's polar iteration: Eigen's SVD takes no autodiff
// scalar) is the double SVD's nearest rotation, and its derivative is that of the polar factor.
// At P = X (I + E), E symmetric (a pure drift): along X E the polar factor X does not move, and
// along [w] P (a rotation from the left, Exp(t [w]) P has the factor Exp(t [w]) X) it turns by w.
TEST_CASE("normalized() with autodiff scalars", "[lie][autodiff]") {
  using S = ceres::Jet<double, 2>;
  rc::prop("value and derivative of the polar factor", [] {
    const lie::SO3d X = lie::SO3d::Exp(*lietest::rotationVector(autodiffAngle()));
    const Vector3d w = *lietest::translation();
    Matrix3d E = Matrix3d::Zero();
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) E(r, c) = E(c, r) = *lietest::uniform(-1e-3, 1e-3);
    const Matrix3d P = X.matrix() * (Matrix3d::Identity() + E);
    const Matrix3d alongDrift = X.matrix() * E, alongRotation = lie::SO3d::hat(w) * P;
    lie::Matrix3<S> R;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        R(r, c) = S(P(r, c));
        R(r, c).v << alongDrift(r, c), alongRotation(r, c);
      }
    }
    const auto Q = lie::SO3<S>::fromMatrix(R, S(1e-2)).normalized().matrix();
    const Matrix3d Q0 = valuesOf(Q);
    const Matrix3d Qsvd = lie::SO3d::fromMatrix(P, 1e-2).normalized().matrix();
    RC_ASSERT(within("normalized value", (Q0 - Qsvd).cwiseAbs().maxCoeff()));
    RC_ASSERT(within("normalized d/d(drift)", derivativesOf(Q, 0).cwiseAbs().maxCoeff()));
    const Matrix3d turn = derivativesOf(Q, 1) * Q0.transpose();
    const double scale = std::max(1.0, w.cwiseAbs().maxCoeff());
    RC_ASSERT(within("normalized d/d(rotation)",
                     (lie::SO3d::vee(turn) - w).cwiseAbs().maxCoeff() / scale));
  });
}
