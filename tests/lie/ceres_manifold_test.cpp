// lie::ceres manifolds checked with Ceres's own manifold test helpers (manifold_test_utils.h,
// GoogleTest + GoogleMock): every identity of EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD at points and
// steps from angle 0 through 1e-12 .. 1e-4 to moderate angles and to within 1e-6 of pi; Plus
// against lie/'s Exp; and one small Ceres problem per manifold, solved to its known answer.
#include <ceres/ceres.h>
#include <ceres/manifold_test_utils.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <lie/ceres/manifolds.hpp>
#include <lie/lie.hpp>

namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;
// Relative tolerance of the Ceres matchers. The Jacobian checks compare with Ridders numeric
// differences, good to about 1e-11 here; the identities hold to a few 1e-16 absolute, which is
// relative to |delta| in Minus(Plus(x, delta), x) = delta, hence the floor on |delta| below.
constexpr double kTolerance = 1e-9;

// Rotation angles: 0, tiny, the series switches of lie/, moderate, and near pi.
const std::vector<double> kAngles = {0.0, 1e-12, 1e-8, 1e-5,       1e-4,      0.3,
                                     1.0, 2.5,   3.0,  kPi - 1e-3, kPi - 1e-6};
// Step angles: Minus(Plus(x, d), x) = d needs |d| < pi; below 1e-7 the check is relative to |d|.
const std::vector<double> kStepAngles = {1e-7, 1e-5, 0.1, 1.0, 2.5, 3.0};

Eigen::Vector3d rotationVector(double angle, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Vector3d u(n(rng), n(rng), n(rng));
  return angle * u.normalized();
}

Eigen::Matrix<double, 9, 1> ambient(const lie::SO3d& R) {
  return Eigen::Map<const Eigen::Matrix<double, 9, 1>>(R.matrix().data());
}

// Cost r = Log(R_i^-1 R) of one noisy rotation R_i, with the analytic Jacobian handed to Ceres in
// the ambient space: J_a = J_t MinusJacobian(R), J_t = Jr^-1(r).
template <typename Manifold, typename Group>
class LogDistance final
    : public ::ceres::SizedCostFunction<Manifold::kTangentSize, Manifold::kAmbientSize> {
 public:
  explicit LogDistance(const Eigen::Matrix<double, Manifold::kAmbientSize, 1>& x_i) : x_i_(x_i) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    constexpr int N = Manifold::kTangentSize;
    constexpr int A = Manifold::kAmbientSize;
    const Manifold manifold;
    Eigen::Map<Eigen::Matrix<double, N, 1>> r(residuals);
    if (!manifold.Minus(parameters[0], x_i_.data(), residuals)) return false;
    if (jacobians && jacobians[0]) {
      Eigen::Matrix<double, N, A, Eigen::RowMajor> minusJacobian;
      manifold.MinusJacobian(parameters[0], minusJacobian.data());
      Eigen::Map<Eigen::Matrix<double, N, A, Eigen::RowMajor>> J(jacobians[0]);
      J = Group::JrInv(typename Group::Tangent(r)) * minusJacobian;
    }
    return true;
  }

 private:
  Eigen::Matrix<double, Manifold::kAmbientSize, 1> x_i_;
};

// Every identity of Ceres's manifold test helpers at (x, delta, y); the macro names its matchers
// unqualified, so it runs inside namespace ceres's scope.
void expectInvariants(const ::ceres::Manifold& manifold, const ::ceres::Vector& x,
                      const ::ceres::Vector& delta, const ::ceres::Vector& y) {
  using namespace ::ceres;
  EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, x, delta, y, kTolerance);
}

// ---------------------------------------------------------------------------------------------
// SO3Manifold

TEST(SO3Manifold, InvariantsHoldFromZeroToNearPi) {
  std::mt19937 rng(15);
  const lie::ceres::SO3Manifold manifold;
  for (const double angle : kAngles) {
    for (const double step : kStepAngles) {
      SCOPED_TRACE(::testing::Message() << "angle " << angle << ", step " << step);
      const ::ceres::Vector x = ambient(lie::SO3d::Exp(rotationVector(angle, rng)));
      const ::ceres::Vector delta = rotationVector(step, rng);
      const ::ceres::Vector y = ambient(lie::SO3d::Exp(rotationVector(kAngles[rng() % 11], rng)));
      expectInvariants(manifold, x, delta, y);
    }
  }
}

TEST(SO3Manifold, PlusIsRightMultiplicationByExp) {
  std::mt19937 rng(57);
  const lie::ceres::SO3Manifold manifold;
  double worst = 0;
  for (const double angle : kAngles) {
    for (const double step : kStepAngles) {
      const lie::SO3d R = lie::SO3d::Exp(rotationVector(angle, rng));
      const Eigen::Vector3d phi = rotationVector(step, rng);
      Eigen::Matrix3d plus;
      ASSERT_TRUE(manifold.Plus(R.matrix().data(), phi.data(), plus.data()));
      worst = std::max(worst, (plus - (R * lie::SO3d::Exp(phi)).matrix()).cwiseAbs().maxCoeff());
    }
  }
  std::printf("SO3Manifold: Plus vs lie Exp, worst |entry| error %.1e\n", worst);
  EXPECT_LT(worst, 1e-15);
}

TEST(SO3Manifold, NonFiniteInputIsRejected) {
  const lie::ceres::SO3Manifold manifold;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d nanStep(std::nan(""), 0.0, 0.0);
  Eigen::Matrix3d out;
  EXPECT_FALSE(manifold.Plus(R.data(), nanStep.data(), out.data()));
  Eigen::Matrix3d bad = R;
  bad(1, 2) = std::nan("");
  Eigen::Vector3d phi;
  EXPECT_FALSE(manifold.Minus(bad.data(), R.data(), phi.data()));
}

// Rotations R0 Exp(+-d_k) in symmetric pairs: their Karcher mean (the minimiser of
// sum |Log(R_i^-1 R)|^2) is R0, since the gradient at R0 is sum Jl(r_i) r_i = sum r_i = 0.
TEST(SO3Manifold, CeresAveragesSymmetricRotationsToTheirCentre) {
  std::mt19937 rng(8);
  const lie::SO3d R0 = lie::SO3d::Exp(Eigen::Vector3d(0.4, -1.1, 2.0));
  ::ceres::Problem problem;
  Eigen::Matrix<double, 9, 1> x = ambient(R0 * lie::SO3d::Exp(rotationVector(0.5, rng)));
  for (int k = 0; k < 5; ++k) {
    const Eigen::Vector3d d = rotationVector(0.05 + 0.1 * k, rng);
    for (const double sign : {1.0, -1.0}) {
      problem.AddResidualBlock(new LogDistance<lie::ceres::SO3Manifold, lie::SO3d>(
                                   ambient(R0 * lie::SO3d::Exp(sign * d))),
                               nullptr, x.data());
    }
  }
  problem.SetManifold(x.data(), new lie::ceres::SO3Manifold);
  ::ceres::Solver::Options options;
  options.function_tolerance = 0.0;  // the cost at the mean is not 0: stop on the gradient
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  ::ceres::Solver::Summary summary;
  ::ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  Eigen::Vector3d error;
  ASSERT_TRUE(lie::ceres::SO3Manifold().Minus(x.data(), ambient(R0).data(), error.data()));
  std::printf("SO3Manifold: Karcher mean after %d iterations, |Log(R0^-1 R)| = %.1e\n",
              int(summary.iterations.size()), error.norm());
  // The cost is not 0 at the mean and is flat to second order about it: Ceres stops once the cost
  // no longer changes in double precision, which leaves about sqrt(eps) of the answer unresolved.
  EXPECT_LT(error.norm(), 1e-8);
  const Eigen::Map<const Eigen::Matrix3d> R(x.data());
  EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-14);
}

}  // namespace
