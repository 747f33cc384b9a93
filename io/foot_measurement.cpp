#include "io/foot_measurement.hpp"

#include <stdexcept>
#include <string>

namespace legkit::io {

ContactMeasurement footMeasurement(const LogLayout& layout, const LogRow& row, int foot) {
  if (layout.foot_columns == FootCovariance::kNone) {
    throw std::invalid_argument("footMeasurement: the log has no body-frame foot columns");
  }
  if (foot < 0 || foot >= layout.num_feet) {
    throw std::invalid_argument("footMeasurement: foot " + std::to_string(foot) +
                                " is not in the log (it has " + std::to_string(layout.num_feet) +
                                " feet)");
  }
  ContactMeasurement m;
  m.foot = foot;
  m.p_body = row.feet[foot].p_body;
  m.cov = row.feet[foot].cov;
  return m;
}

}  // namespace legkit::io
