// lie::ceres manifolds (SO3Manifold, SE3Manifold, SEK3Manifold<2>, SEK3Manifold<3>) checked with
// Ceres's own manifold test helpers (manifold_test_utils.h, GoogleTest + GoogleMock): every
// identity of EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD at points and steps from angle 0 through
// 1e-12 .. 1e-4 to moderate angles and to within 1e-6 of pi, with columns from 0 to 10 m; the
// worst errors of the same identities measured and bounded; Plus against lie/'s Exp; non-finite
// input rejected; and one small Ceres problem per manifold solved to its known answer.
#include <ceres/ceres.h>
#include <ceres/manifold_test_utils.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

#include <lie/ceres/manifolds.hpp>
#include <lie/lie.hpp>

namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;
// Relative tolerance of the Ceres matchers (their Jacobian checks use Ridders differences).
constexpr double kTolerance = 1e-9;

// Rotation angles of the points: 0, tiny, lie/'s series switches, moderate, and near pi.
const std::vector<double> kAngles = {0.0, 1e-12, 1e-8, 1e-5,       1e-4,      0.3,
                                     1.0, 2.5,   3.0,  kPi - 1e-3, kPi - 1e-6};
// Rotation angles of the steps: Minus(Plus(x, d), x) = d needs |d| < pi, and Ceres's check is
// relative to |d|, against an absolute rounding of a few 1e-16: hence no step below 1e-7.
const std::vector<double> kStepAngles = {1e-7, 1e-5, 0.1, 1.0, 2.5, 3.0};
// Sizes of the SE_K(3) columns (metres).
const std::vector<double> kColumnScales = {0.0, 1e-6, 1.0, 10.0};

Eigen::Vector3d randomVector(double norm, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Vector3d u(n(rng), n(rng), n(rng));
  return norm * u.normalized();
}

// Per-group helpers: a tangent vector of given angle and column scale; the ambient numbers.
template <typename Group>
struct GroupTraits;

template <>
struct GroupTraits<lie::SO3d> {
  using Manifold = lie::ceres::SO3Manifold;
  static lie::SO3d::Tangent tangent(double angle, double, std::mt19937& rng) {
    return randomVector(angle, rng);
  }
  static lie::SO3d::Tangent screw(double angle, double, std::mt19937& rng) {
    return randomVector(angle, rng);
  }
  static Eigen::Matrix<double, 9, 1> ambient(const lie::SO3d& R) {
    return Eigen::Map<const Eigen::Matrix<double, 9, 1>>(R.matrix().data());
  }
};

template <int K>
struct GroupTraits<lie::SEK3<double, K>> {
  using Group = lie::SEK3<double, K>;
  using Manifold = lie::ceres::SEK3Manifold<K>;
  static typename Group::Tangent tangent(double angle, double scale, std::mt19937& rng) {
    typename Group::Tangent xi;
    xi.template head<3>() = randomVector(angle, rng);
    for (int i = 0; i < K; ++i) xi.template segment<3>(3 + 3 * i) = randomVector(scale, rng);
    return xi;
  }
  // A screw: every rho_i along phi (lengths scale, 2 scale, ...), so that ad_xi^T xi = 0.
  static typename Group::Tangent screw(double angle, double scale, std::mt19937& rng) {
    typename Group::Tangent xi;
    const Eigen::Vector3d axis = randomVector(1.0, rng);
    xi.template head<3>() = angle * axis;
    for (int i = 0; i < K; ++i) xi.template segment<3>(3 + 3 * i) = (i + 1) * scale * axis;
    return xi;
  }
  static Eigen::Matrix<double, 9 + 3 * K, 1> ambient(const Group& X) {
    Eigen::Matrix<double, 9 + 3 * K, 1> a;
    a.template head<9>() = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(X.R().data());
    for (int i = 0; i < K; ++i) a.template segment<3>(9 + 3 * i) = X.col(i);
    return a;
  }
};

// Every identity of Ceres's manifold test helpers at (x, delta, y); the macro names its matchers
// unqualified, so it runs with namespace ceres in scope.
void expectInvariants(const ::ceres::Manifold& manifold, const ::ceres::Vector& x,
                      const ::ceres::Vector& delta, const ::ceres::Vector& y) {
  using namespace ::ceres;
  EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, x, delta, y, kTolerance);
}

// Cost r = Log(X_i^-1 X) of one noisy element X_i, with the analytic Jacobian handed to Ceres in
// the ambient space: J_a = J_t MinusJacobian(X), J_t = Jr^-1(r), so that J_a PlusJacobian = J_t.
template <typename Group>
class LogDistance final
    : public ::ceres::SizedCostFunction<GroupTraits<Group>::Manifold::kTangentSize,
                                        GroupTraits<Group>::Manifold::kAmbientSize> {
 public:
  using Manifold = typename GroupTraits<Group>::Manifold;
  static constexpr int N = Manifold::kTangentSize;
  static constexpr int A = Manifold::kAmbientSize;

  explicit LogDistance(const Eigen::Matrix<double, A, 1>& x_i) : x_i_(x_i) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const Manifold manifold;
    if (!manifold.Minus(parameters[0], x_i_.data(), residuals)) return false;
    if (jacobians && jacobians[0]) {
      const Eigen::Map<const Eigen::Matrix<double, N, 1>> r(residuals);
      Eigen::Matrix<double, N, A, Eigen::RowMajor> minusJacobian;
      manifold.MinusJacobian(parameters[0], minusJacobian.data());
      Eigen::Map<Eigen::Matrix<double, N, A, Eigen::RowMajor>> J(jacobians[0]);
      J = Group::JrInv(typename Group::Tangent(r)) * minusJacobian;
    }
    return true;
  }

 private:
  Eigen::Matrix<double, A, 1> x_i_;
};

template <typename Group>
class CeresManifold : public ::testing::Test {};
using Groups = ::testing::Types<lie::SO3d, lie::SE3d, lie::SE23d, lie::SEK3<double, 3>>;
TYPED_TEST_SUITE(CeresManifold, Groups);

TYPED_TEST(CeresManifold, InvariantsHoldFromZeroToNearPi) {
  using T = GroupTraits<TypeParam>;
  const typename T::Manifold manifold;
  std::mt19937 rng(15);
  for (const double angle : kAngles) {
    for (const double step : kStepAngles) {
      for (const double scale : kColumnScales) {
        SCOPED_TRACE(::testing::Message()
                     << "angle " << angle << ", step " << step << ", columns " << scale);
        const ::ceres::Vector x = T::ambient(TypeParam::Exp(T::tangent(angle, scale, rng)));
        const ::ceres::Vector delta = T::tangent(step, scale, rng);
        const double yAngle = kAngles[rng() % kAngles.size()];
        const ::ceres::Vector y = T::ambient(TypeParam::Exp(T::tangent(yAngle, scale, rng)));
        expectInvariants(manifold, x, delta, y);
        if (std::is_same_v<TypeParam, lie::SO3d>) break;  // no columns: one scale is enough
      }
    }
  }
}

// The same identities measured (worst absolute errors over the grid), and bounded tighter than
// the matchers' 1e-9: rounding for the algebraic ones, central differences (h = 1e-6, error
// O(h^2 |x|)) for the Jacobians.
TYPED_TEST(CeresManifold, WorstErrorsOfTheIdentities) {
  using T = GroupTraits<TypeParam>;
  using Manifold = typename T::Manifold;
  constexpr int N = Manifold::kTangentSize;
  constexpr int A = Manifold::kAmbientSize;
  using Ambient = Eigen::Matrix<double, A, 1>;
  using Tangent = Eigen::Matrix<double, N, 1>;
  const Manifold manifold;
  std::mt19937 rng(57);
  double minusPlus = 0, plusMinus = 0, plusJac = 0, minusJac = 0, identity = 0, rightMul = 0,
         exp = 0;
  for (const double angle : kAngles) {
    for (const double step : kStepAngles) {
      const double scale = kColumnScales[rng() % kColumnScales.size()];
      const TypeParam X = TypeParam::Exp(T::tangent(angle, scale, rng));
      const Ambient x = T::ambient(X);
      const Tangent d = T::tangent(step, scale, rng);
      const Ambient y =
          T::ambient(TypeParam::Exp(T::tangent(kAngles[rng() % kAngles.size()], scale, rng)));
      Ambient xd, back;
      Tangent diff;
      ASSERT_TRUE(manifold.Plus(x.data(), d.data(), xd.data()));
      exp = std::max(exp, (xd - T::ambient(X * TypeParam::Exp(d))).cwiseAbs().maxCoeff());
      ASSERT_TRUE(manifold.Minus(xd.data(), x.data(), diff.data()));
      minusPlus = std::max(minusPlus, (diff - d).cwiseAbs().maxCoeff());
      ASSERT_TRUE(manifold.Minus(y.data(), x.data(), diff.data()));
      ASSERT_TRUE(manifold.Plus(x.data(), diff.data(), back.data()));
      plusMinus = std::max(plusMinus, (back - y).cwiseAbs().maxCoeff());

      Eigen::Matrix<double, A, N, Eigen::RowMajor> P;
      Eigen::Matrix<double, N, A, Eigen::RowMajor> M;
      ASSERT_TRUE(manifold.PlusJacobian(x.data(), P.data()));
      ASSERT_TRUE(manifold.MinusJacobian(x.data(), M.data()));
      identity = std::max(identity,
                          (M * P - Eigen::Matrix<double, N, N>::Identity()).cwiseAbs().maxCoeff());
      constexpr double h = 1e-6;
      for (int j = 0; j < N; ++j) {
        const Tangent e = Tangent::Unit(j) * h;
        const Tangent me = -e;
        Ambient plus, minus;
        manifold.Plus(x.data(), e.data(), plus.data());
        manifold.Plus(x.data(), me.data(), minus.data());
        plusJac = std::max(plusJac, ((plus - minus) / (2 * h) - P.col(j)).cwiseAbs().maxCoeff());
      }
      // d Minus(y, x) / d y at y = x, along the manifold (y = Plus(x, +-h e_j)) and off it (each
      // ambient coordinate moved on its own).
      for (int j = 0; j < A; ++j) {
        Ambient yp = x, ym = x;
        yp(j) += h;
        ym(j) -= h;
        Tangent rp, rm;
        manifold.Minus(yp.data(), x.data(), rp.data());
        manifold.Minus(ym.data(), x.data(), rm.data());
        minusJac = std::max(minusJac, ((rp - rm) / (2 * h) - M.col(j)).cwiseAbs().maxCoeff());
      }
      const Eigen::Matrix<double, 3, A, Eigen::RowMajor> G =
          Eigen::Matrix<double, 3, A, Eigen::RowMajor>::Random();
      Eigen::Matrix<double, 3, N, Eigen::RowMajor> GP;
      ASSERT_TRUE(manifold.RightMultiplyByPlusJacobian(x.data(), 3, G.data(), GP.data()));
      rightMul = std::max(rightMul, (GP - G * P).cwiseAbs().maxCoeff());
    }
  }
  std::printf(
      "%-16s worst |Minus(Plus(x,d),x) - d| %.1e, |Plus(x,Minus(y,x)) - y| %.1e, "
      "|Plus - X Exp| %.1e,\n%-16s |PlusJacobian - central diff| %.1e, |MinusJacobian - central "
      "diff| %.1e, |M P - I| %.1e, |RightMultiply - G P| %.1e\n",
      ::testing::UnitTest::GetInstance()->current_test_info()->type_param(), minusPlus, plusMinus,
      exp, "", plusJac, minusJac, identity, rightMul);
  EXPECT_LT(minusPlus, 1e-13);
  EXPECT_LT(plusMinus, 1e-13);
  EXPECT_LT(exp, 1e-14);
  EXPECT_LT(plusJac, 1e-8);
  EXPECT_LT(minusJac, 1e-8);
  EXPECT_LT(identity, 4e-15);
  EXPECT_LT(rightMul, 1e-14);
}

TYPED_TEST(CeresManifold, NonFiniteInputIsRejected) {
  using T = GroupTraits<TypeParam>;
  const typename T::Manifold manifold;
  std::mt19937 rng(3);
  const auto x = T::ambient(TypeParam::Exp(T::tangent(0.5, 1.0, rng)));
  auto d = T::tangent(0.5, 1.0, rng);
  auto bad = x;
  decltype(d) diff;
  decltype(bad) out;
  d(d.size() - 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(manifold.Plus(x.data(), d.data(), out.data()));
  bad(bad.size() - 1) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(manifold.Minus(bad.data(), x.data(), diff.data()));
  EXPECT_FALSE(manifold.Minus(x.data(), bad.data(), diff.data()));
}

// Elements X0 Exp(+-xi_k) in symmetric pairs, each xi_k a screw (rho_i along phi): X0 is their
// Karcher mean, the minimiser of sum |Log(X_i^-1 X)|^2. The gradient at X0 is
// sum Jr^-1(r_i)^T r_i with r_i = -+xi_k, and Jr^-1(xi)^T xi = xi when ad_xi^T xi = 0, which holds
// for every xi on SO(3) and for screws on SE_K(3) (ad_xi^T xi = (0, -phi x rho_i)); so the
// gradient is sum (xi_k - xi_k) = 0. (For a general xi on SE_K(3) it is not, and X0 is not the
// mean.)
TYPED_TEST(CeresManifold, CeresAveragesSymmetricPairsToTheirCentre) {
  using T = GroupTraits<TypeParam>;
  using Manifold = typename T::Manifold;
  std::mt19937 rng(8);
  const TypeParam X0 = TypeParam::Exp(T::tangent(2.0, 3.0, rng));
  auto x = T::ambient(X0 * TypeParam::Exp(T::tangent(0.5, 0.5, rng)));
  ::ceres::Problem problem;
  for (int k = 0; k < 5; ++k) {
    const auto xi = T::screw(0.05 + 0.1 * k, 0.1 + 0.2 * k, rng);
    for (const double sign : {1.0, -1.0}) {
      problem.AddResidualBlock(
          new LogDistance<TypeParam>(T::ambient(X0 * TypeParam::Exp(sign * xi))), nullptr,
          x.data());
    }
  }
  problem.SetManifold(x.data(), new Manifold);
  ::ceres::Solver::Options options;
  options.function_tolerance = 0.0;  // the cost at the mean is not 0: stop on the gradient
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  ::ceres::Solver::Summary summary;
  ::ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  typename TypeParam::Tangent error;
  ASSERT_TRUE(Manifold().Minus(x.data(), T::ambient(X0).data(), error.data()));
  std::printf("%-16s Karcher mean after %d iterations: |Log(X0^-1 X)| = %.1e\n",
              ::testing::UnitTest::GetInstance()->current_test_info()->type_param(),
              int(summary.iterations.size()), error.norm());
  // The cost is not 0 at the mean and is flat to second order about it: Ceres stops once the cost
  // no longer changes in double precision, which leaves about sqrt(eps) = 1.5e-8 (times the size
  // of the problem, columns of a few metres) unresolved. X0 Exp(+-xi) with a general xi instead of
  // a screw moves the mean by 3e-2 (SE(3)), 5e-2 (SE_2(3)).
  EXPECT_LT(error.norm(), 1e-7);
  const Eigen::Map<const Eigen::Matrix3d> R(x.data());
  EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-14);
}

}  // namespace
