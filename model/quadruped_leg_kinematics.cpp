#include "model/quadruped_leg_kinematics.hpp"

#include <stdexcept>

#include "model/quadruped_inertia.hpp"

namespace legkit::model {

QuadrupedLegKinematics::QuadrupedLegKinematics(const QuadrupedGeometry& g) : kin_(g) {}

std::string QuadrupedLegKinematics::footName(int foot) const {
  return legName(foot);
}

std::string QuadrupedLegKinematics::jointName(int joint) const {
  if (joint < 0 || joint >= numJoints()) {
    throw std::invalid_argument("joint id " + std::to_string(joint) + " is not 0..11");
  }
  return "q_" + std::string(legName(joint / 3)) + "_" + std::to_string(joint % 3);
}

double QuadrupedLegKinematics::mass() const {
  return QuadrupedInertia::go2().totalMass();
}

void QuadrupedLegKinematics::foot(int foot, const LegJointVector& q, Eigen::Vector3d& p_B,
                                  FootJacobian& J) const {
  legName(foot);  // throws std::invalid_argument for an id outside 0..3, before q is indexed
  const Eigen::Vector3d q_leg = q.segment<3>(3 * foot);
  p_B = kin_.footPosition(foot, q_leg);
  J.setZero();
  J.middleCols<3>(3 * foot) = kin_.footJacobian(foot, q_leg);
}

}  // namespace legkit::model
