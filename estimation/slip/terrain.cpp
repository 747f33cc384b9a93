#include "estimation/slip/terrain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace legkit::slip {

const char* terrainClassName(TerrainClass c) {
  switch (c) {
    case TerrainClass::kIce:
      return "ice";
    case TerrainClass::kNormal:
      return "normal";
    case TerrainClass::kHighGrip:
      return "high-grip";
    case TerrainClass::kUnknown:
      break;
  }
  return "unknown";
}

TerrainParams estimatedForceParams() {
  TerrainParams p;
  p.min_loaded_time = 0.03;
  p.min_slip_time = 0.005;
  return p;
}

TerrainClassifier::TerrainClassifier(const TerrainParams& params) : params_(params) {
  if (!(params.ice_mu > 0.0 && params.ice_mu < params.high_grip_mu) ||
      !std::isfinite(params.high_grip_mu) || !(params.min_normal_force >= 0.0) ||
      params.min_onsets < 1 || !(params.min_stance_time >= 0.0) ||
      !(params.min_loaded_time >= 0.0) || !(params.min_slip_time >= 0.0)) {
    throw std::invalid_argument(
        "TerrainParams: need 0 < ice_mu < high_grip_mu, min_normal_force >= 0, min_onsets >= 1, "
        "min_stance_time, min_loaded_time, min_slip_time >= 0");
  }
  onset_ratio_.fill(std::numeric_limits<double>::quiet_NaN());
}

void TerrainClassifier::reset() {
  *this = TerrainClassifier(params_);
}

TerrainClass TerrainClassifier::update(const SlipReport& report, const Eigen::Vector3d* forces,
                                       int num_forces, double dt) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  constexpr double kTimeTol = 1e-9;  // [s] so that five 1 ms samples hold for 5 ms
  std::array<bool, kMaxFeet> slipping_now{}, in_stance{};
  for (int k = 0; k < report.num_feet; ++k) {
    const FootSlip& f = report.feet[k];
    if (f.foot < 0 || f.foot >= kMaxFeet) continue;
    const int i = f.foot;
    in_stance[i] = true;
    slipping_now[i] = f.slipping;
    stance_time_ += dt;
    slip_time_ += f.slipping ? dt : 0.0;
    const bool onset = f.slipping && !was_slipping_[i];
    slip_onsets_ += onset ? 1 : 0;

    // |f_t| / f_n of a loaded foot, NaN when the force is missing or light.
    double ratio = kNaN;
    if (i < num_forces && forces[i].allFinite()) {
      const double f_n = forces[i].dot(normal_);  // f_n = f . n
      if (f_n >= params_.min_normal_force) ratio = (forces[i] - f_n * normal_).norm() / f_n;
    }
    loaded_time_[i] = std::isnan(ratio) ? 0.0 : loaded_time_[i] + dt;
    const bool settled = loaded_time_[i] >= params_.min_loaded_time - kTimeTol;
    const double sample = settled ? ratio : kNaN;

    if (onset) {
      slip_held_[i] = dt;
      onset_ratio_[i] = sample;  // a sample of mu once the slip has held min_slip_time
    } else if (f.slipping) {
      slip_held_[i] += dt;
    } else if (!std::isnan(sample)) {
      mu_lower_ = std::max(mu_lower_, sample);  // held at this ratio: mu >= ratio
    }
    if (f.slipping && !std::isnan(onset_ratio_[i]) &&
        slip_held_[i] >= params_.min_slip_time - kTimeTol) {
      onset_mu_[onsets_ % kOnsetMemory] = onset_ratio_[i];
      ++onsets_;
      onset_ratio_[i] = kNaN;
    }
    if (!f.slipping) onset_ratio_[i] = kNaN;  // the slip ended before it held
  }
  for (int i = 0; i < kMaxFeet; ++i) {
    if (in_stance[i]) continue;
    loaded_time_[i] = 0.0;  // a swing foot starts over at its next touchdown
    onset_ratio_[i] = kNaN;
  }
  was_slipping_ = slipping_now;
  class_ = classify();
  return class_;
}

double TerrainClassifier::frictionEstimate() const {
  const int n = std::min(onsets_, kOnsetMemory);
  if (n == 0) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0;
  for (int k = 0; k < n; ++k) sum += onset_mu_[k];
  return sum / n;
}

double TerrainClassifier::slipRate() const {
  return stance_time_ > 0.0 ? slip_onsets_ / stance_time_ : 0.0;
}

double TerrainClassifier::slipFraction() const {
  return stance_time_ > 0.0 ? slip_time_ / stance_time_ : 0.0;
}

TerrainClass TerrainClassifier::classify() const {
  if (onsets_ >= params_.min_onsets) {
    const double mu = frictionEstimate();
    if (mu < params_.ice_mu) return TerrainClass::kIce;
    return mu > params_.high_grip_mu ? TerrainClass::kHighGrip : TerrainClass::kNormal;
  }
  if (mu_lower_ > params_.high_grip_mu) return TerrainClass::kHighGrip;
  if (stance_time_ >= params_.min_stance_time && mu_lower_ >= params_.ice_mu) {
    return TerrainClass::kNormal;
  }
  return TerrainClass::kUnknown;
}

}  // namespace legkit::slip
