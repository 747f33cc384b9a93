#include "model/quadruped.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace legkit::model {
namespace {

constexpr double kPi = 3.14159265358979323846;

void checkLeg(int leg, const char* who) {
  if (leg < 0 || leg >= kNumLegs) {
    throw std::invalid_argument(std::string(who) + ": leg id " + std::to_string(leg) +
                                " is out of range (expected 0..3: FL, FR, RL, RR)");
  }
}

std::string format(const Eigen::Vector3d& x) {
  std::ostringstream s;
  s.precision(6);
  s << "(" << x.x() << ", " << x.y() << ", " << x.z() << ")";
  return s.str();
}

void checkFinite(const Eigen::Vector3d& x, const char* who, const char* what, int leg) {
  if (!x.allFinite()) {
    throw std::invalid_argument(std::string(who) + ": " + what + " of leg " + legName(leg) +
                                " is not finite: " + format(x));
  }
}

}  // namespace

const char* legName(int leg) {
  checkLeg(leg, "legName");
  static constexpr const char* kNames[kNumLegs] = {"FL", "FR", "RL", "RR"};
  return kNames[leg];
}

double lateralSign(int leg) {
  checkLeg(leg, "lateralSign");
  return (leg == FL || leg == RL) ? 1.0 : -1.0;
}

QuadrupedGeometry QuadrupedGeometry::go2() {
  QuadrupedGeometry g;
  g.hip_offset = {Eigen::Vector3d(0.1934, 0.0465, 0.0), Eigen::Vector3d(0.1934, -0.0465, 0.0),
                  Eigen::Vector3d(-0.1934, 0.0465, 0.0), Eigen::Vector3d(-0.1934, -0.0465, 0.0)};
  g.abduction_offset = 0.0955;
  g.thigh_length = 0.213;
  g.calf_length = 0.213;
  g.foot_radius = 0.022;
  // Go2 joint ranges: abduction +-60 deg; hip flexion wider backwards on the rear legs; the knee
  // only bends one way (negative angles).
  const Eigen::Vector3d front_min(-1.0472, -1.5708, -2.7227), front_max(1.0472, 3.4907, -0.83776);
  const Eigen::Vector3d rear_min(-1.0472, -0.5236, -2.7227), rear_max(1.0472, 4.5379, -0.83776);
  g.q_min = {front_min, front_min, rear_min, rear_min};
  g.q_max = {front_max, front_max, rear_max, rear_max};
  return g;
}

bool QuadrupedGeometry::withinLimits(int leg, const Eigen::Vector3d& q, double tol) const {
  checkLeg(leg, "QuadrupedGeometry::withinLimits");
  return (q.array() >= q_min[leg].array() - tol).all() &&
         (q.array() <= q_max[leg].array() + tol).all();
}

QuadrupedKinematics::QuadrupedKinematics(const QuadrupedGeometry& g) : g_(g) {
  const bool positive = g.thigh_length > 0.0 && g.calf_length > 0.0 && g.abduction_offset >= 0.0 &&
                        g.foot_radius >= 0.0;
  bool finite = std::isfinite(g.thigh_length) && std::isfinite(g.calf_length) &&
                std::isfinite(g.abduction_offset) && std::isfinite(g.foot_radius);
  for (int i = 0; i < kNumLegs; ++i) {
    finite = finite && g.hip_offset[i].allFinite() && g.q_min[i].allFinite() &&
             g.q_max[i].allFinite() && (g.q_min[i].array() <= g.q_max[i].array()).all();
  }
  if (!positive || !finite) {
    throw std::invalid_argument(
        "QuadrupedKinematics: geometry needs finite, positive link lengths, a non-negative "
        "abduction offset and foot radius, and finite limits with q_min <= q_max");
  }
}

// FK, written in the leg's own frame first. With s = lateralSign(leg), d = abduction_offset,
// l1 = thigh, l2 = calf and the sagittal coordinates
//   x  = -l1 sin(q2) - l2 sin(q2 + q3),   z0 = -l1 cos(q2) - l2 cos(q2 + q3),
// the foot is the leg-plane point (x, s d, z0) turned by the abduction angle about x:
//   B_p_f = hip + Rx(q1) (x, s d, z0).
Eigen::Vector3d QuadrupedKinematics::footPosition(int leg, const Eigen::Vector3d& q) const {
  checkLeg(leg, "QuadrupedKinematics::footPosition");
  checkFinite(q, "QuadrupedKinematics::footPosition", "joint angles q", leg);
  const double l1 = g_.thigh_length, l2 = g_.calf_length;
  const double y0 = lateralSign(leg) * g_.abduction_offset;
  const double c1 = std::cos(q.x()), s1 = std::sin(q.x());
  const double x = -l1 * std::sin(q.y()) - l2 * std::sin(q.y() + q.z());
  const double z0 = -l1 * std::cos(q.y()) - l2 * std::cos(q.y() + q.z());
  return g_.hip_offset[leg] + Eigen::Vector3d(x, c1 * y0 - s1 * z0, s1 * y0 + c1 * z0);
}

// Differentiating the FK above term by term (p_y = c1 y0 - s1 z0, p_z = s1 y0 + c1 z0):
//   column q1: (0, -p_z, p_y) relative to the hip (a rotation about x),
//   column q2: dx/dq2 = z0, dz0/dq2 = -x          -> (z0,  s1 x, -c1 x),
//   column q3: dx/dq3 = -l2 cos(q2+q3), dz0/dq3 = l2 sin(q2+q3)
//                                               -> (-l2 c23, -s1 l2 s23, c1 l2 s23).
Eigen::Matrix3d QuadrupedKinematics::footJacobian(int leg, const Eigen::Vector3d& q) const {
  checkLeg(leg, "QuadrupedKinematics::footJacobian");
  checkFinite(q, "QuadrupedKinematics::footJacobian", "joint angles q", leg);
  const double l1 = g_.thigh_length, l2 = g_.calf_length;
  const double y0 = lateralSign(leg) * g_.abduction_offset;
  const double c1 = std::cos(q.x()), s1 = std::sin(q.x());
  const double s23 = std::sin(q.y() + q.z()), c23 = std::cos(q.y() + q.z());
  const double x = -l1 * std::sin(q.y()) - l2 * s23;
  const double z0 = -l1 * std::cos(q.y()) - l2 * c23;
  const double py = c1 * y0 - s1 * z0, pz = s1 * y0 + c1 * z0;
  Eigen::Matrix3d J;
  J << 0.0, z0, -l2 * c23,          //
      -pz, s1 * x, -s1 * l2 * s23,  //
      py, -c1 * x, c1 * l2 * s23;
  return J;
}

// IK undoes the FK in three steps. (1) In the plane across the body x axis the leg-plane point
// (s d, z0) is turned by q1 onto (p_y, p_z), so |z0| = sqrt(p_y^2 + p_z^2 - d^2), with z0 <= 0 on
// our branch, and q1 is the difference of the two polar angles. (2) The hip-to-foot distance r in
// the sagittal plane fixes the knee: r^2 = l1^2 + l2^2 + 2 l1 l2 cos(q3), q3 = -acos(.) on the
// knee-backward branch. (3) With a = l1 + l2 cos(q3), b = l2 sin(q3) the sagittal point is
// (-x, -z0) = r (sin(q2 + beta), cos(q2 + beta)), beta = atan2(b, a).
Eigen::Vector3d QuadrupedKinematics::inverseKinematics(int leg,
                                                       const Eigen::Vector3d& p_body) const {
  checkLeg(leg, "QuadrupedKinematics::inverseKinematics");
  checkFinite(p_body, "QuadrupedKinematics::inverseKinematics", "target foot position", leg);
  const auto unreachable = [&](const std::string& why) {
    return std::domain_error("QuadrupedKinematics::inverseKinematics: leg " +
                             std::string(legName(leg)) + " cannot reach the body-frame point " +
                             format(p_body) + " m: " + why);
  };
  const double l1 = g_.thigh_length, l2 = g_.calf_length, d = g_.abduction_offset;
  const double y0 = lateralSign(leg) * d;
  const Eigen::Vector3d p = p_body - g_.hip_offset[leg];

  const double rho2 = p.y() * p.y() + p.z() * p.z();
  if (rho2 < d * d) throw unreachable("it lies inside the abduction offset cylinder");
  const double z0 = -std::sqrt(rho2 - d * d);
  double q1 = std::atan2(p.z(), p.y()) - std::atan2(z0, y0);
  q1 = std::remainder(q1, 2.0 * kPi);

  const double x = p.x();
  const double r2 = x * x + z0 * z0;
  const double c3 = (r2 - l1 * l1 - l2 * l2) / (2.0 * l1 * l2);
  if (c3 > 1.0 || c3 < -1.0) throw unreachable("it is out of the thigh + calf reach");
  const double q3 = -std::acos(c3);
  const double a = l1 + l2 * std::cos(q3), b = l2 * std::sin(q3);
  double q2 = std::atan2(-x, -z0) - std::atan2(b, a);
  // Bring q2 into the leg's range when it is one turn away (the rear hips reach past pi).
  constexpr double kTol = 1e-9;
  if (q2 < g_.q_min[leg].y() - kTol) q2 += 2.0 * kPi;
  if (q2 > g_.q_max[leg].y() + kTol) q2 -= 2.0 * kPi;

  const Eigen::Vector3d q(q1, q2, q3);
  if (!g_.withinLimits(leg, q, kTol)) {
    throw unreachable("the solution " + format(q) + " rad is outside the joint limits");
  }
  return q;
}

}  // namespace legkit::model
