#include "estimation/estimators.hpp"

#include <functional>
#include <stdexcept>
#include <utility>

#include "estimation/imu/dead_reckoning_estimator.hpp"
#include "estimation/invariant/eskf.hpp"
#include "estimation/invariant/invariant_ekf.hpp"
#include "estimation/invariant/tsif.hpp"
#include "estimation/leg_odometry/leg_odometry_estimator.hpp"
#include "estimation/linear_kf/linear_kf.hpp"

namespace legkit {
namespace {

using Factory = std::function<std::unique_ptr<Estimator>()>;

const std::vector<std::pair<std::string, Factory>>& registry() {
  static const std::vector<std::pair<std::string, Factory>> all = {
      {"imu-dead-reckoning", [] { return std::make_unique<imu::DeadReckoningEstimator>(); }},
      {"leg-odometry", [] { return std::make_unique<leg_odometry::LegOdometryEstimator>(); }},
      {"linear-kf", [] { return std::make_unique<linear_kf::LinearKf>(); }},
      {"eskf", [] { return std::make_unique<invariant::Eskf>(); }},
      {"invariant-ekf", [] { return std::make_unique<invariant::InvariantEkf>(); }},
      {"tsif", [] { return std::make_unique<invariant::Tsif>(); }},
  };
  return all;
}

}  // namespace

std::vector<std::string> estimatorNames() {
  std::vector<std::string> names;
  for (const auto& [name, make] : registry()) names.push_back(name);
  return names;
}

std::unique_ptr<Estimator> makeEstimator(const std::string& name) {
  std::string known;
  for (const auto& [n, make] : registry()) {
    if (n == name) return make();
    known += (known.empty() ? "" : ", ") + n;
  }
  throw std::invalid_argument("unknown estimator '" + name + "' (known: " + known + ")");
}

}  // namespace legkit
