// Fitting the logistic contact probability (logistic_contact.hpp) to labelled samples: maximum
// likelihood with a small L2 penalty, by Newton's method (iteratively reweighted least squares).
// With z_n = w . x_n (x_n = (1, scaled features)), p_n = sigma(z_n) and labels y_n in {0, 1},
// it minimizes
//   L(w) = -sum_n [y_n log p_n + (1 - y_n) log(1 - p_n)] + l2/2 |w_1..3|^2  (the bias is free)
// with the Newton step  (X^T W X + l2 I') dw = -(X^T (p - y) + l2 I' w),  W = diag(p (1 - p)),
// shortened by halving until L decreases enough (Armijo, c = 1e-4): plain Newton from the
// log-odds start overshoots on data the features nearly separate (4 s of the physics trot, seed
// 1: the weights reached 1e11 and every sample came out "contact"); near the optimum the full
// step is always taken, so the result there is plain Newton's.
// The features are scaled by their own mean and standard deviation first (stored in the model);
// a feature that is constant over the set, or switched off in the options, gets weight 0.
// Deterministic: the same samples give the same weights, bit for bit.
#pragma once

#include <vector>

#include "estimation/contact/logistic_contact.hpp"

namespace legkit::contact {

struct TrainingOptions {
  double l2 = 1e-3;            // L2 weight on the scaled features' weights (not on the bias)
  int max_iterations = 50;     // Newton steps at most
  double tolerance = 1e-10;    // stop when the step's largest component is below this
  bool use_force = true;       // F_n; false: a model for a robot without foot sensors
  bool use_foot_speed = true;  // |v_foot|
  bool use_phase = true;       // phi; false: a model for a robot without a gait schedule
};

// Throws std::invalid_argument (saying which) for: no samples, as many labels as samples not
// given, a used feature that is not finite in some sample (its index), labels all of one class,
// no feature in use, or options out of range (l2 < 0, max_iterations < 1, tolerance <= 0); and
// std::runtime_error when max_iterations steps did not converge (never a model that did not).
LogisticModel trainLogistic(const std::vector<ContactFeatures>& samples,
                            const std::vector<bool>& labels, const TrainingOptions& options = {});

}  // namespace legkit::contact
