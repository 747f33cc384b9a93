#include "estimation/fusion/delayed_pose.hpp"

#include <Eigen/Cholesky>
#include <sstream>
#include <stdexcept>

namespace legkit::fusion {

PoseCheck checkPose(const PoseMeasurement& z) {
  using Problem = PoseCheck::Problem;
  if (!std::isfinite(z.t)) return {Problem::kNotFinite, "t is not finite"};
  if (!z.R_MB.matrix().allFinite()) return {Problem::kNotFinite, "R_MB is not finite"};
  if (!z.p_MB.allFinite()) return {Problem::kNotFinite, "p_MB is not finite"};
  if (!z.cov.allFinite()) return {Problem::kNotFinite, "cov is not finite"};
  const double scale = 1.0 + z.cov.cwiseAbs().maxCoeff();
  if ((z.cov - z.cov.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale)
    return {Problem::kNotPositiveDefinite, "cov is not symmetric"};
  const Eigen::LLT<Matrix6d> llt(z.cov);
  if (llt.info() != Eigen::Success || !llt.matrixLLT().allFinite())
    return {Problem::kNotPositiveDefinite, "cov is not positive definite"};
  return {};
}

void checkPoseMeasurement(const PoseMeasurement& z, const char* who) {
  const PoseCheck check = checkPose(z);
  if (check) return;
  std::ostringstream os;
  os << who << "::updatePose at t = " << z.t << ": PoseMeasurement." << check.what;
  throw std::invalid_argument(os.str());
}

}  // namespace legkit::fusion
