// Reference solution to exercise 57.9.1.
#include <cmath>
#include <stdexcept>

#include "ex57_9_1.hpp"

namespace ex57_9_1 {

// answer.md says why each fault gets its response.
Response responseTo(Fault fault) {
  switch (fault) {
    case Fault::kImuDropout:
      return Response::kHold;
    case Fault::kImuSaturation:
      return Response::kHold;
    case Fault::kEncoderJump:
      return Response::kIgnoreSample;
    case Fault::kEncoderFrozen:
      return Response::kAlarm;
    case Fault::kForceSaturation:
      return Response::kIgnoreSample;
    case Fault::kForceDrift:
      return Response::kInflateR;
  }
  throw std::invalid_argument("responseTo: unknown fault");
}

// For 1 kHz rows (answer.md): a gap of 5 missed samples; 10 deg per step; 50 ms of a perfectly
// still encoder; 20 N of swing load, low-passed over 0.1 s.
Thresholds defaultThresholds() {
  return {5e-3, 10.0 * M_PI / 180.0, 0.05, 20.0, 0.1};
}

SensorMonitor::SensorMonitor(const Thresholds& thresholds) : th_(thresholds) {}

const Report& SensorMonitor::update(const legkit::io::LogRow& row) {
  report_.fill(false);
  const auto at = [&](Fault f) -> bool& { return report_[static_cast<int>(f)]; };
  const double dt = first_ ? 0.0 : row.t - t_prev_;
  at(Fault::kImuDropout) = !first_ && dt > th_.imu_max_gap;
  at(Fault::kImuSaturation) = row.gyro.cwiseAbs().maxCoeff() >= 0.99 * kGyroRange ||
                              row.acc.cwiseAbs().maxCoeff() >= 0.99 * kAccelRange;
  for (int j = 0; j < legkit::io::kNumJoints; ++j) {
    if (first_ || row.q[j] != q_prev_[j]) {
      t_change_[j] = row.t;
    } else if (row.t - t_change_[j] >= th_.encoder_frozen_time) {
      at(Fault::kEncoderFrozen) = true;
    }
    if (!first_ && std::abs(row.q[j] - q_prev_[j]) > th_.encoder_max_step)
      at(Fault::kEncoderJump) = true;
  }
  const double alpha = 1.0 - std::exp(-dt / th_.force_drift_tau);  // the swing force's low-pass
  for (int k = 0; k < legkit::io::kNumLegs; ++k) {
    if (row.force[k] >= 0.99 * kForceRange) at(Fault::kForceSaturation) = true;
    if (!row.contact[k]) f_lp_[k] += alpha * (row.force[k] - f_lp_[k]);
    if (std::abs(f_lp_[k]) > th_.force_drift) at(Fault::kForceDrift) = true;
  }
  first_ = false;
  t_prev_ = row.t;
  q_prev_ = row.q;
  return report_;
}

}  // namespace ex57_9_1
