// Innovation gating (section 57.9): a measurement whose innovation is too unlikely under the
// filter's own innovation covariance is not used. The test is the Mahalanobis distance
// d^2 = r^T S^-1 r against the chi-square quantile of the innovation's dimension at the
// probability of the chapter's n-sigma rule (erf(n / sqrt 2): 3 sigma -> 0.9973).
#pragma once

namespace legkit::engineering {

struct GatingParams {
  bool enabled = false;  // off in the library's defaults; the settings file turns it on
  double n_sigma = 3.0;  // the chapter's rule: reject beyond n sigma (as a probability, per dof)
};

}  // namespace legkit::engineering
