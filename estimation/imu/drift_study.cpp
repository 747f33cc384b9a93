#include "estimation/imu/drift_study.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "estimation/imu/dead_reckoning.hpp"
#include "estimation/imu/input_checks.hpp"

namespace legkit::imu {

std::vector<DriftSample> runStationaryDrift(const StationaryDriftStudy& study) {
  detail::requirePositiveStep(study.dt, "runStationaryDrift (dt)");
  detail::requirePositiveStep(study.duration, "runStationaryDrift (duration)");
  detail::requirePositiveStep(study.report_every, "runStationaryDrift (report_every)");
  const long steps = std::lround(study.duration / study.dt);
  const long every = std::max(1L, std::lround(study.report_every / study.dt));

  const Eigen::Matrix3d R_true = study.R0.matrix();
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();  // true a and w: standing still
  const model::ImuBias b_hat;                            // the integrator assumes no bias
  model::ImuBias bias = study.bias;
  std::mt19937_64 gen(study.seed);

  NavState x{study.R0, zero, zero};
  std::vector<DriftSample> out;
  out.reserve(static_cast<std::size_t>(steps / every + 1));
  for (long k = 0;; ++k) {
    if (k % every == 0) {
      const double deg = study.R0.rminus(x.R).norm() * 180.0 / M_PI;
      out.push_back({k * study.dt, x.p.norm(), x.v.norm(), deg});
    }
    if (k == steps) break;
    const model::ImuReading m =
        model::synthesiseReading(study.noise, study.dt, R_true, zero, zero, bias, gen);
    x = deadReckoningStep(x, m, b_hat, study.dt);
  }
  return out;
}

DriftSample driftAt(const std::vector<DriftSample>& samples, double t) {
  if (samples.empty()) throw std::invalid_argument("driftAt: no samples");
  const DriftSample* best = &samples.front();
  for (const DriftSample& s : samples)
    if (std::abs(s.t - t) < std::abs(best->t - t)) best = &s;
  return *best;
}

}  // namespace legkit::imu
