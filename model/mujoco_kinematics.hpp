// A robot's legs from its own URDF or MJCF file, through MuJoCo's kinematics (Debian's
// libmujoco-dev 2.2.2 loads both formats with mj_loadXML).
//
// The base frame is the frame of the named base body; each foot is a named site (MJCF) or body
// (URDF has no sites: name the foot links); the leg joints are hinge or slide joints below the
// base body in the kinematic tree. For joint angles q (joint k = the k-th leg joint, in MuJoCo's
// qpos convention: the angle whose zero is the model's reference pose) the foot's point in the
// base frame and its Jacobian are
//   B_p_f = R_WB^T (x_f - x_B),   B_J = R_WB^T (J_f - J_B),
// with world-frame points x and translational Jacobians J from mj_kinematics and mj_jac. The leg
// joints lie below the base, so J_B is zero in their columns and R_WB does not depend on q. The
// base is held still: a free joint (any number of them, or none) sits at the identity pose.
//
// URDF: MuJoCo fuses links joined by fixed joints unless told otherwise, which would take away
// the root link (welded to the world) and every foot link on a fixed joint. The loader therefore
// adds compiler settings to the URDF text it hands to MuJoCo (the file itself is not changed):
// fusestatic="false", and boundmass / boundinertia (1e-6 kg, 1e-10 kg m^2) so that a
// kinematics-only URDF whose links carry no <inertial> still compiles; a setting the file's own
// <mujoco><compiler> already gives is left alone. It also removes every <visual> and
// <collision> element (their meshes are what a URDF taken out of its ROS package no longer has,
// and kinematics never need them; <inertial> stays). An MJCF file is handed to MuJoCo as it is:
// its meshes must be where it says.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "model/leg_kinematics.hpp"
#include "model/mujoco.hpp"

namespace legkit::model {

constexpr int kMaxLegFeet = 6;  // feet a MujocoLegKinematics may have (io::kMaxFeet)

class MujocoLegKinematics final : public LegKinematics {
 public:
  // Loads `path` (URDF or MJCF) and finds the base body, the foot frames (in foot-id order) and
  // the leg joints (in joint<k> column order; empty: every hinge and slide joint below the base
  // body, in model order). Throws std::runtime_error naming the file and what is wrong: the file
  // cannot be opened; MuJoCo cannot load it (MuJoCo's message); an unknown base, foot or joint
  // name (the known ones listed); a name given twice; a joint that is not a hinge or slide or not
  // below the base; a foot not below the base; two feet on one leg (on one body, or one below the
  // other); no foot, more than kMaxLegFeet feet, no joint or more than kMaxLegJoints joints; a
  // URDF <origin>, <axis>, <limit>, <mass>, <inertia> or <dynamics> number that is not finite
  // (MuJoCo would read "nan" as 0), naming its line and joint or link; a warning from MuJoCo while
  // loading (an MJCF "nan"); a body, joint or site whose compiled numbers are not finite.
  static MujocoLegKinematics fromFile(const std::string& path, const std::string& base,
                                      const std::vector<std::string>& feet,
                                      const std::vector<std::string>& joints = {});

  int numFeet() const override { return static_cast<int>(feet_.size()); }
  int numJoints() const override { return static_cast<int>(joints_.size()); }
  std::string footName(int foot) const override;    // the site or body name
  std::string jointName(int joint) const override;  // the model joint behind column `joint`
  double mass() const override;                     // mj_getTotalmass of the model
  const std::string& path() const { return path_; }

  // B_p_f and B_J at q (entries >= numJoints() ignored). Kinematics run once per distinct q: the
  // feet of one sample share them. No allocation. Throws std::out_of_range for a foot id outside
  // 0..numFeet()-1, std::invalid_argument for non-finite leg joint angles.
  void foot(int foot, const LegJointVector& q, Eigen::Vector3d& p_B,
            FootJacobian& J) const override;
  // The foot frame's (the site's, or the foot body's) orientation in the base frame and its
  // rotational Jacobian, R_BF = R_WB^T R_WF and B_J_w = R_WB^T J_w,F (mj_jac's rotational part;
  // the base's is zero in the leg columns). Throws as foot() does.
  bool footRotation(int foot, const LegJointVector& q, Eigen::Matrix3d& R_BF,
                    FootJacobian& J_w) const override;

 private:
  struct Frame {
    std::string name;
    bool is_site = false;
    int id = -1;    // site or body id
    int body = -1;  // the body that carries it
  };
  struct Joint {
    std::string name;
    int qpos = -1;  // address in qpos
    int dof = -1;   // column in MuJoCo's Jacobians
  };

  MujocoLegKinematics() = default;
  void update(const LegJointVector& q) const;  // qpos from q, mj_kinematics, mj_comPos

  std::string path_;
  MjModelPtr model_;
  MjDataPtr data_;  // one per instance: foot() writes it (not thread-safe)
  int base_ = -1;   // base body id
  std::vector<Frame> feet_;
  std::vector<Joint> joints_;
  const Frame& footFrame(int foot, const LegJointVector& q) const;  // checked id, kinematics at q
  mutable std::vector<mjtNum> jacp_;  // 3 x nv, row-major (mj_jac's layout), allocated once
  mutable LegJointVector q_last_;     // the q the kinematics in data_ belong to
  mutable bool have_q_ = false;
};

// The legs a settings file's `robot:` section describes: the analytic Go2 of model/quadruped.hpp
// (QuadrupedLegKinematics) when `model` is empty, else MujocoLegKinematics::fromFile(model, base,
// feet, joints). Throws std::runtime_error as fromFile does, and for base, feet or joints given
// without a model.
std::unique_ptr<LegKinematics> makeLegKinematics(const std::string& model, const std::string& base,
                                                 const std::vector<std::string>& feet,
                                                 const std::vector<std::string>& joints);

}  // namespace legkit::model
