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

TerrainClassifier::TerrainClassifier(const TerrainParams& params) : params_(params) {
  if (!(params.ice_mu > 0.0 && params.ice_mu < params.high_grip_mu) ||
      !std::isfinite(params.high_grip_mu) || !(params.min_normal_force >= 0.0) ||
      params.min_onsets < 1 || !(params.min_stance_time >= 0.0)) {
    throw std::invalid_argument(
        "TerrainParams: need 0 < ice_mu < high_grip_mu, min_normal_force >= 0, min_onsets >= 1, "
        "min_stance_time >= 0");
  }
}

void TerrainClassifier::reset() {
  *this = TerrainClassifier(params_);
}

TerrainClass TerrainClassifier::update(const SlipReport& report, const Eigen::Vector3d* forces,
                                       int num_forces, double dt) {
  std::array<bool, kMaxFeet> slipping_now{};
  for (int k = 0; k < report.num_feet; ++k) {
    const FootSlip& f = report.feet[k];
    if (f.foot < 0 || f.foot >= kMaxFeet) continue;
    slipping_now[f.foot] = f.slipping;
    stance_time_ += dt;
    slip_time_ += f.slipping ? dt : 0.0;
    const bool onset = f.slipping && !was_slipping_[f.foot];
    slip_onsets_ += onset ? 1 : 0;
    if (f.foot >= num_forces || !forces[f.foot].allFinite()) continue;
    const double f_n = forces[f.foot].dot(normal_);  // f_n = f . n
    if (f_n < params_.min_normal_force) continue;
    const double ratio = (forces[f.foot] - f_n * normal_).norm() / f_n;  // |f_t| / f_n
    if (onset) {
      onset_mu_[onsets_ % kOnsetMemory] = ratio;
      ++onsets_;
    } else if (!f.slipping) {
      mu_lower_ = std::max(mu_lower_, ratio);  // held at this ratio: mu >= ratio
    }
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
