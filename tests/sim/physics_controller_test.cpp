// The walking controller on its own (no MuJoCo): the stance split holds the weight with no net
// moment, feet never pull, and the torques are -J^T f plus the bias the caller gives.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include "model/imu_model.hpp"
#include "sim/locomotion_controller.hpp"

using namespace legkit;

namespace {

constexpr double kMass = 15.2;

// Standing at height h, feet under the hips (the physics simulator's start).
sim::ControllerState standing(const model::QuadrupedKinematics& kin, double h) {
  sim::ControllerState s;
  s.p = {0.0, 0.0, h};
  const model::QuadrupedGeometry& g = kin.geometry();
  for (int leg = 0; leg < 4; ++leg) {
    const Eigen::Vector3d foot(g.hip_offset[leg].x(),
                               g.hip_offset[leg].y() + model::lateralSign(leg) * g.abduction_offset,
                               g.foot_radius - h);
    s.q.segment<3>(3 * leg) = kin.inverseKinematics(leg, foot);
  }
  return s;
}

sim::LocomotionCommand standCommand() {
  sim::LocomotionCommand c;
  c.gait = sim::Gait::stand();
  return c;
}

}  // namespace

TEST_CASE("Standing at rest: the feet hold the weight with no net moment", "[sim][physics]") {
  const model::QuadrupedKinematics kin;
  const sim::ControllerState s = standing(kin, 0.30);
  sim::LocomotionController controller(kin, kMass, standCommand(), s);
  const io::JointVector bias = io::JointVector::Constant(0.25);
  const io::JointVector tau = controller.torques(0.0, s, bias);
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
  for (int leg = 0; leg < 4; ++leg) {
    const Eigen::Vector3d f = controller.forces()[leg];
    CHECK(controller.stance()[leg]);
    CHECK(f.z() > 0.0);
    const Eigen::Vector3d q = s.q.segment<3>(3 * leg);
    const Eigen::Vector3d r = s.R * kin.footPosition(leg, q);
    force += f;
    moment += r.cross(f);
    // tau = -J^T f + bias, J the world-frame foot Jacobian of the leg's joints.
    const Eigen::Vector3d expected =
        -(s.R * kin.footJacobian(leg, q)).transpose() * f + bias.segment<3>(3 * leg);
    CHECK((tau.segment<3>(3 * leg) - expected).norm() < 1e-9);
  }
  CHECK((force - kMass * -model::gravity()).norm() < 0.02 * kMass * 9.81);
  CHECK(moment.norm() < 0.05);
}

TEST_CASE("A roll far beyond recovery never makes a foot pull", "[sim][physics]") {
  const model::QuadrupedKinematics kin;
  sim::ControllerState s = standing(kin, 0.30);
  sim::LocomotionController controller(kin, kMass, standCommand(), s);
  s.R = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()).toRotationMatrix();
  s.omega = {3.0, 0.0, 0.0};
  controller.torques(0.0, s, io::JointVector::Zero());
  int loaded = 0;
  for (const Eigen::Vector3d& f : controller.forces()) {
    CHECK(f.z() >= 0.0);
    CHECK(f.head<2>().norm() <= 0.6 * f.z() + 1e-12);  // inside the assumed friction cone
    loaded += f.z() > 0.0;
  }
  CHECK(loaded >= 2);
  CHECK(loaded < 4);  // the feet on one side are dropped, not asked to pull
}

TEST_CASE("The integral terms start at t = 0, whatever a settle before it did", "[sim][physics]") {
  const model::QuadrupedKinematics kin;
  sim::ControllerState s = standing(kin, 0.30);
  sim::LocomotionCommand trot;
  trot.gait = sim::Gait::trot(2.0);
  trot.gait.start = 1.0;  // all four feet down until then, the speed loop active
  s.v = {0.3, 0.1, 0.0};  // off the (zero) command: the integrals would grow
  sim::LocomotionController settled(kin, kMass, trot, s);
  for (int k = 0; k < 500; ++k) settled.torques(-0.5 + 1e-3 * k, s, io::JointVector::Zero());
  sim::LocomotionController fresh(kin, kMass, trot, s);
  for (double t : {0.0, 0.01}) {
    const io::JointVector a = settled.torques(t, s, io::JointVector::Zero());
    const io::JointVector b = fresh.torques(t, s, io::JointVector::Zero());
    CHECK((a - b).norm() < 1e-12);
  }
}
