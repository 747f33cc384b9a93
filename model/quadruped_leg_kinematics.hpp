// The analytic Go2-class quadruped of model/quadruped.hpp behind the robot-agnostic
// LegKinematics interface: four feet (FL, FR, RL, RR), twelve joints, joint k = 3 leg + j
// (j: abduction, hip flexion, knee), the very numbers of QuadrupedKinematics.
#pragma once

#include <string>

#include "model/leg_kinematics.hpp"
#include "model/quadruped.hpp"

namespace legkit::model {

class QuadrupedLegKinematics final : public LegKinematics {
 public:
  explicit QuadrupedLegKinematics(const QuadrupedGeometry& g = QuadrupedGeometry::go2());

  int numFeet() const override { return kNumLegs; }
  int numJoints() const override { return 3 * kNumLegs; }
  std::string footName(int foot) const override;  // "FL", ...; throws for an id outside 0..3
  // "q_FL_0", ... (the log's column); throws for an id outside 0..11.
  std::string jointName(int joint) const override;
  double mass() const override;  // QuadrupedInertia::go2().totalMass(), 15.206 kg
  // B_p_f = FK(q_leg) and B_J = d FK / d q_leg in columns 3 leg .. 3 leg + 2, zero elsewhere.
  // Throws std::invalid_argument for an id outside 0..3 or non-finite angles of that leg.
  void foot(int foot, const LegJointVector& q, Eigen::Vector3d& p_B,
            FootJacobian& J) const override;

  const QuadrupedKinematics& kinematics() const { return kin_; }

 private:
  QuadrupedKinematics kin_;
};

}  // namespace legkit::model
