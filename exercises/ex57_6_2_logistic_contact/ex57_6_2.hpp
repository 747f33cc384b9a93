// Exercise 57.6.2: the logistic contact probability p_c = sigma(w . x) of section 57.6, trained
// on labelled samples by Newton's method.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "estimation/contact/logistic_contact.hpp"

namespace ex57_6_2 {

using legkit::contact::ContactFeatures;  // force F_n [N], foot_speed |v_foot| [m/s], phase phi
using legkit::contact::LogisticModel;    // w = (b, w_F, w_v, w_phi) on the scaled features

// One Newton step on the L2-penalised negative log-likelihood of the labels,
//   L(w) = -sum_n [y_n log p_n + (1 - y_n) log(1 - p_n)] + l2/2 (w_1^2 + w_2^2 + w_3^2),
//   p_n = sigma(w . x_n),   sigma(z) = 1 / (1 + e^-z),
// for samples x_n = (1, scaled F_n, scaled |v_foot|, scaled phi) (the bias w_0 is not penalised):
//   w+ = w - (X^T W X + l2 I')^-1 (X^T (p - y) + l2 I' w),   W = diag(p_n (1 - p_n)),
// I' = diag(0, 1, 1, 1). x and y have the same length (at least one sample).
Eigen::Vector4d newtonStep(const Eigen::Vector4d& w, const std::vector<Eigen::Vector4d>& x,
                           const std::vector<bool>& y, double l2);

// The whole fit, all three features used: per feature its mean and standard deviation over the
// samples (divide by n, not n - 1) into model.mean and model.scale; every sample scaled,
// x_n = (1, (F - mean_F) / scale_F, ...); from w = (log(positives / negatives), 0, 0, 0), Newton
// steps until the largest component of a step is below 1e-10 (at most 50 steps).
LogisticModel trainContactProbability(const std::vector<ContactFeatures>& samples,
                                      const std::vector<bool>& labels, double l2 = 1e-3);

}  // namespace ex57_6_2
