// Consistency of a filter: does the error it makes match the covariance it claims?
//
//   NEES_k = e_k^T P_k^{-1} e_k        e = (dtheta, dv, dp) in the BaseCovariance convention
//                                      (estimation/estimator.hpp): R = Exp(dtheta) R_hat, ...
// For a consistent filter, e_k ~ N(0, P_k), so NEES_k ~ chi^2(n) with n = 9 (6 for a filter that
// takes attitude as an input). Averaged over M independent Monte Carlo runs,
//   ANEES_k = (1/M) sum_j NEES_k^(j),   M * ANEES_k ~ chi^2(M n),
// so the two-sided 95 % acceptance interval of ANEES_k is [chi2inv(0.025, Mn), chi2inv(0.975, Mn)]
// / M (Bar-Shalom, Li and Kirubarajan, "Estimation with applications to tracking and navigation").
#pragma once

#include "estimation/estimator.hpp"

namespace legkit::eval {

// The error e = truth (-) estimate in the BaseCovariance convention.
Eigen::Matrix<double, 9, 1> baseError(const EstimateSample& truth, const EstimateSample& estimate);

// e^T P^-1 e over the 9 (or, without attitude, the 6 velocity-position) components. Throws
// std::invalid_argument if that block of P is not symmetric positive definite.
double nees(const EstimateSample& truth, const EstimateSample& estimate, const BaseCovariance& cov);

// Degrees of freedom of the NEES: 9, or 6 without attitude.
int neesDof(const BaseCovariance& cov);

// The p-quantile of the chi-square distribution with k degrees of freedom (k > 0, 0 < p < 1):
// solves P(k/2, x/2) = p for the regularised lower incomplete gamma function by bisection, to
// about 1e-12 relative.
double chiSquareQuantile(double p, double k);

struct ChiSquareBounds {
  double lower = 0.0;
  double upper = 0.0;
};

// The two-sided acceptance interval of an ANEES averaged over `runs` runs of a dof-dimensional
// NEES: [chi2inv((1-c)/2, runs dof), chi2inv((1+c)/2, runs dof)] / runs.
ChiSquareBounds aneesBounds(int dof, int runs, double confidence = 0.95);

}  // namespace legkit::eval
