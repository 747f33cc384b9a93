#include "study_filters.hpp"

#include <cmath>
#include <stdexcept>

#include "estimation/invariant/eskf.hpp"
#include "estimation/invariant/invariant_ekf.hpp"
#include "estimation/invariant/tsif.hpp"
#include "estimation/linear_kf/linear_kf.hpp"

namespace legkit::tools {

std::vector<std::string> filterNames() {
  return {"linear-kf", "eskf", "invariant-ekf", "tsif"};
}

namespace {

template <class Filter, class Params>
std::unique_ptr<Estimator> makeAdjusted(
    const std::function<void(invariant::FilterParams&)>& adjust) {
  Params p;
  adjust(p);
  return std::make_unique<Filter>(p);
}

}  // namespace

std::unique_ptr<Estimator> makeFamilyFilter(
    const std::string& name, const std::function<void(invariant::FilterParams&)>& adjust) {
  if (name == "linear-kf") return std::make_unique<linear_kf::LinearKf>();
  if (name == "eskf") return makeAdjusted<invariant::Eskf, invariant::EskfParams>(adjust);
  if (name == "invariant-ekf") {
    return makeAdjusted<invariant::InvariantEkf, invariant::InvariantEkfParams>(adjust);
  }
  if (name == "tsif") return makeAdjusted<invariant::Tsif, invariant::TsifParams>(adjust);
  throw std::invalid_argument("no filter '" + name + "' in the studies");
}

std::unique_ptr<Estimator> makeWithInitialAttitudeSigma(const std::string& name, double sigma) {
  if (name == "linear-kf") {
    linear_kf::LinearKfParams p;
    p.attitude.sigma_tilt = sigma;
    p.attitude.sigma_yaw = sigma;
    return std::make_unique<linear_kf::LinearKf>(p);
  }
  return makeFamilyFilter(name, [sigma](invariant::FilterParams& p) { p.sigma_attitude = sigma; });
}

std::unique_ptr<Estimator> makeLinearKf(const LinearKfScales& scales) {
  linear_kf::LinearKfParams p;
  p.foot_stance_density *= std::sqrt(scales.foot_process_noise);  // sigma_f^2 x scale
  p.imu.accel_noise_density *= std::sqrt(scales.accel_noise);     // sigma_a^2 x scale
  p.foot_velocity_sigma *= std::sqrt(scales.measurement_noise);   // R of the velocity rows
  return std::make_unique<linear_kf::LinearKf>(p);
}

FrontendNoise scaledFrontendNoise(const FrontendNoise& nominal, const LinearKfScales& scales) {
  const double k = std::sqrt(scales.measurement_noise);  // both terms of R_i scale as sigma^2
  return {nominal.encoder_angle_sigma * k, nominal.foot_point_sigma * k};
}

}  // namespace legkit::tools
