#include "estimation/health_guard.hpp"

#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace legkit {
namespace {

[[noreturn]] __attribute__((noinline, cold)) void fail(const char* who, double t,
                                                       const std::string& what) {
  std::ostringstream os;
  os << who << "::step at t = " << t << ": " << what;
  throw std::invalid_argument(os.str());
}

bool isSymmetric(const Eigen::Matrix3d& C) {
  return (C - C.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * (1.0 + C.cwiseAbs().maxCoeff());
}

bool inRange(const ContactMeasurement& c, const InputLimits& limits) {
  return c.p_body.norm() <= limits.foot_distance_max &&
         c.cov.diagonal().maxCoeff() <= limits.foot_variance_max &&
         (!c.v_body || c.v_body->norm() <= limits.foot_speed_max);
}

}  // namespace

void checkLimits(const InputLimits& l, const char* who) {
  for (const double x : {l.gyro_max, l.accel_max, l.max_dt, l.foot_distance_max,
                         l.foot_variance_max, l.foot_speed_max, l.speed_max, l.position_max}) {
    if (!(x > 0.0)) {
      throw std::invalid_argument(std::string(who) +
                                  ": every InputLimits bound must be positive (inf: no bound)");
    }
  }
}

void checkStepInput(const StepInput& in, int max_feet, const char* who) {
  const double t = in.t;
  if (!std::isfinite(t)) fail(who, t, "time t is not finite");
  if (!std::isfinite(in.dt) || in.dt < 0.0) {
    std::ostringstream os;
    os << "dt must be finite and non-negative, got " << in.dt;
    fail(who, t, os.str());
  }
  if (!in.imu.w_m.allFinite()) fail(who, t, "gyro reading w_m is not finite");
  if (!in.imu.a_m.allFinite()) fail(who, t, "accelerometer reading a_m is not finite");
  if (in.num_contacts < 0 || in.num_contacts > static_cast<int>(in.contacts.size())) {
    fail(who, t,
         "num_contacts = " + std::to_string(in.num_contacts) + " is out of range [0, " +
             std::to_string(in.contacts.size()) + "]");
  }
  std::array<bool, leg_odometry::kMaxContacts> seen{};
  for (const ContactMeasurement& c : in.stance()) {
    const auto footFail = [&](const std::string& what) {
      fail(who, t, "foot id " + std::to_string(c.foot) + " " + what);
    };
    if (c.foot < 0 || c.foot >= max_feet) {
      footFail("is out of range [0, " + std::to_string(max_feet) + ") (this estimator's feet)");
    }
    if (seen[c.foot]) footFail("appears twice among the contacts");
    seen[c.foot] = true;
    if (!c.p_body.allFinite()) footFail("p_body is not finite");
    if (!(c.probability >= 0.0 && c.probability <= 1.0)) {  // also NaN
      std::ostringstream os;
      os << "probability (p_c) must lie in [0, 1], got " << c.probability;
      footFail(os.str());
    }
    if (c.v_body && !c.v_body->allFinite()) footFail("v_body is not finite");
    // `name` stays a C string until a check fails: a std::string of it would allocate on every
    // step ("orientation covariance" is past the short-string buffer).
    const auto checkCovariance = [&](const Eigen::Matrix3d& C, const char* name) {
      if (!C.allFinite()) footFail(std::string(name) + " is not finite");
      if (!isSymmetric(C)) footFail(std::string(name) + " is not symmetric");
      // Sylvester's criterion: the three leading principal minors are positive (LLT decides
      // where the minors overflow).
      const bool minors =
          C(0, 0) > 0.0 && C(0, 0) * C(1, 1) - C(0, 1) * C(1, 0) > 0.0 && C.determinant() > 0.0;
      if (minors) return;
      // An overflowing pivot can leave a NaN in the factor while info() says Success.
      const Eigen::LLT<Eigen::Matrix3d> llt(C);
      if (llt.info() != Eigen::Success || !llt.matrixLLT().allFinite()) {
        footFail(std::string(name) + " is not positive definite");
      }
    };
    checkCovariance(c.cov, "covariance");
    if (c.R_body) {  // a flat foot's orientation: a rotation to 1e-6, and its covariance
      const Eigen::Matrix3d& Z = *c.R_body;
      if (!Z.allFinite() || !(Z.transpose() * Z).isIdentity(1e-6) || !(Z.determinant() > 0.0)) {
        footFail("orientation R_body is not a rotation matrix");
      }
      checkCovariance(c.rot_cov, "orientation covariance");
    }
  }
}

bool admitImu(const StepInput& in, const InputLimits& limits, Health& health) {
  if (in.imu.w_m.cwiseAbs().maxCoeff() > limits.gyro_max) {
    health.record(Fault::kGyroRange, in.t);
    return false;
  }
  if (in.imu.a_m.cwiseAbs().maxCoeff() > limits.accel_max) {
    health.record(Fault::kAccelRange, in.t);
    return false;
  }
  return true;
}

const StepInput& admitContacts(const StepInput& in, const InputLimits& limits, Health& health,
                               std::optional<StepInput>& storage) {
  bool all = true;
  for (const ContactMeasurement& c : in.stance()) all = all && inRange(c, limits);
  if (all) return in;
  StepInput& kept = storage.emplace(in);
  kept.num_contacts = 0;
  for (int k = 0; k < in.num_contacts; ++k) {
    const ContactMeasurement& c = in.contacts[k];
    if (!inRange(c, limits)) {
      health.record(Fault::kContactRange, in.t);
      continue;
    }
    kept.normal_force[kept.num_contacts] = in.normal_force[k];
    kept.contacts[kept.num_contacts++] = c;
  }
  return kept;
}

bool isSane(const EstimateSample& x, const InputLimits& limits) {
  return std::isfinite(x.t) && x.q.coeffs().allFinite() &&
         std::abs(x.q.squaredNorm() - 1.0) < 1e-6 && x.v.allFinite() &&
         x.v.norm() <= limits.speed_max && x.p.allFinite() && x.p.norm() <= limits.position_max;
}

bool HealthGuard::check(const EstimateSample& x, const InputLimits& limits) {
  if (!isSane(x, limits)) return false;
  if (++steps_since_full_check_ >= kFullCheckInterval) {
    steps_since_full_check_ = 0;
    last_good_ = x;
  }
  return true;
}

}  // namespace legkit
