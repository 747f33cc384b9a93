// The filters the studies compare, built with the one parameter each study varies.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "estimation/estimator.hpp"
#include "estimation/invariant/filter_params.hpp"
#include "estimation/log_frontend.hpp"

namespace legkit::tools {

// The estimators that keep a covariance (sections 57.4 and 57.5), in the chapter's order.
std::vector<std::string> filterNames();

// A filter of filterNames() with its default parameters, except what `adjust` changes in the
// block the three filters of 57.5 share (the linear KF, not of that family, keeps its defaults).
std::unique_ptr<Estimator> makeFamilyFilter(
    const std::string& name, const std::function<void(invariant::FilterParams&)>& adjust);

// A filter with its default parameters except its initial attitude standard deviation [rad],
// which the convergence study sets to the initial error it applies. Only for the filters that
// estimate attitude (or, for the linear KF, whose attitude filter starts with that error).
std::unique_ptr<Estimator> makeWithInitialAttitudeSigma(const std::string& name, double sigma);

// The linear KF with three of its noise variances multiplied by a factor each (exercise 57.4.2):
// the stance feet's process noise sigma_f^2, the accelerometer noise that drives its prediction,
// and the kinematic measurement noise R. R has two sources: the front end's contact covariance
// (scaledFrontendNoise) and the filter's own leg-velocity noise; both are scaled.
struct LinearKfScales {
  double foot_process_noise = 1.0;
  double accel_noise = 1.0;
  double measurement_noise = 1.0;
};
std::unique_ptr<Estimator> makeLinearKf(const LinearKfScales& scales);
FrontendNoise scaledFrontendNoise(const FrontendNoise& nominal, const LinearKfScales& scales);

}  // namespace legkit::tools
