#include "study_filters.hpp"

#include <cmath>
#include <stdexcept>

#include "estimation/estimators.hpp"
#include "estimation/invariant/eskf.hpp"
#include "estimation/invariant/invariant_ekf.hpp"
#include "estimation/invariant/tsif.hpp"
#include "estimation/linear_kf/linear_kf.hpp"

namespace legkit::tools {
namespace {

// Passes every step on with the contacts' covariances multiplied by `scale`: the measurement
// noise the filter assumes, while the simulated noise stays what it is.
class ScaledContactNoise final : public Estimator {
 public:
  ScaledContactNoise(std::unique_ptr<Estimator> inner, double scale)
      : inner_(std::move(inner)), scale_(scale) {}
  std::string name() const override { return inner_->name(); }
  void reset(const EstimateSample& x0) override { inner_->reset(x0); }
  void step(const StepInput& in) override {
    StepInput scaled = in;
    for (int i = 0; i < scaled.num_contacts; ++i) scaled.contacts[i].cov *= scale_;
    inner_->step(scaled);
  }
  EstimateSample estimate() const override { return inner_->estimate(); }
  std::optional<BaseCovariance> covariance() const override { return inner_->covariance(); }

 private:
  std::unique_ptr<Estimator> inner_;
  double scale_;
};

}  // namespace

std::vector<std::string> filterNames() { return {"linear-kf", "eskf", "invariant-ekf", "tsif"}; }

std::unique_ptr<Estimator> makeWithInitialAttitudeSigma(const std::string& name, double sigma) {
  if (name == "linear-kf") {
    linear_kf::LinearKfParams p;
    p.attitude.sigma_tilt = sigma;
    p.attitude.sigma_yaw = sigma;
    return std::make_unique<linear_kf::LinearKf>(p);
  }
  if (name == "eskf") {
    invariant::EskfParams p;
    p.sigma_attitude = sigma;
    return std::make_unique<invariant::Eskf>(p);
  }
  if (name == "invariant-ekf") {
    invariant::InvariantEkfParams p;
    p.sigma_attitude = sigma;
    return std::make_unique<invariant::InvariantEkf>(p);
  }
  if (name == "tsif") {
    invariant::TsifParams p;
    p.sigma_attitude = sigma;
    return std::make_unique<invariant::Tsif>(p);
  }
  throw std::invalid_argument("no filter '" + name + "' with an attitude prior");
}

std::unique_ptr<Estimator> makeLinearKf(const LinearKfScales& scales) {
  linear_kf::LinearKfParams p;
  p.foot_stance_density *= std::sqrt(scales.foot_process_noise);  // sigma_f^2 x scale
  p.imu.accel_noise_density *= std::sqrt(scales.accel_noise);     // sigma_a^2 x scale
  auto filter = std::make_unique<linear_kf::LinearKf>(p);
  if (scales.measurement_noise == 1.0) return filter;
  return std::make_unique<ScaledContactNoise>(std::move(filter), scales.measurement_noise);
}

}  // namespace legkit::tools
