// Exercise 57.7.1: a slip detector on the Mahalanobis distance of each stance foot's velocity
// residual, judged by a chi-square test.
#pragma once

#include <Eigen/Core>
#include <array>

namespace ex57_7_1 {

// The filter's base error state in the kit's BaseCovariance order, e = (dtheta, dv, dp)
// (estimation/estimator.hpp), and the covariance P the filter claims for it.
using Matrix9 = Eigen::Matrix<double, 9, 9>;
// How a foot's velocity residual depends on that error, to first order: r = H e + noise.
using Matrix3x9 = Eigen::Matrix<double, 3, 9>;

// One stance foot at one sample.
struct FootResidual {
  int foot = 0;                                     // foot id
  Eigen::Vector3d r = Eigen::Vector3d::Zero();      // v_leg,i - v_hat, world frame [m/s]
  Matrix3x9 H = Matrix3x9::Zero();                  // dr / de
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // the leg velocity's own noise [m^2/s^2]
};

// The squared Mahalanobis distance of the residual with the filter's own covariance:
//   d2 = r^T S^-1 r,   S = H P H^T + R.
double mahalanobisSquared(const FootResidual& foot, const Matrix9& P);

// The alpha-quantile of the chi-square distribution with 3 degrees of freedom: the x for which
// P(chi2_3 <= x) = alpha (11.345 at alpha = 0.99), to 1e-9 relative, for 0 < alpha < 1.
double chiSquare3Quantile(double alpha);

// Every stance foot's verdict: slipping when d2 exceeds the alpha-quantile of chi2_3.
struct FootVerdict {
  int foot = 0;
  double d2 = 0.0;
  bool slipping = false;
};
struct SlipVerdict {
  int num_feet = 0;
  std::array<FootVerdict, 8> feet{};  // the first num_feet are used, in the order given
};
// feet[0 .. n-1], 0 <= n <= 8.
SlipVerdict detectSlip(const FootResidual* feet, int n, const Matrix9& P, double alpha = 0.99);

}  // namespace ex57_7_1
