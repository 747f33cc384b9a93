// Argument checks shared by the IMU module: bad input throws std::invalid_argument naming the
// function and the offending value, never a silently corrupted estimate.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace legkit::imu::detail {

inline void requirePositiveStep(double dt, const char* where) {
  if (dt > 0.0 && std::isfinite(dt)) return;
  std::ostringstream os;
  os << where << ": time step dt must be positive and finite, got " << dt;
  throw std::invalid_argument(os.str());
}

template <typename Derived>
void requireFinite(const Eigen::MatrixBase<Derived>& x, const char* where, const char* what) {
  if (x.allFinite()) return;
  std::ostringstream os;
  os << where << ": " << what << " has a NaN or inf entry: [" << x.transpose() << "]";
  throw std::invalid_argument(os.str());
}

}  // namespace legkit::imu::detail
