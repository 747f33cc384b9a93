// Two robots the kit writes itself, each with its own forward kinematics computed without MuJoCo,
// to test model::MujocoLegKinematics on robots other than the Go2:
//  - a biped as URDF (no free joint, no sites: the feet are sole links on fixed joints, rotated
//    joint origins, a prismatic shin), whose FK composes the URDF transforms joint by joint;
//  - a hexapod as MJCF (a free joint, the feet are sites), whose FK is written in closed form.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace legkit::test {

// ----------------------------------------------------------------------------------------------
// Biped (URDF). Each leg: hip yaw (z), hip roll (x), hip pitch (y), knee (y), a shin slide (z),
// ankle pitch (y), ankle roll (x), then a fixed joint to the sole link: 7 movable joints per leg,
// 14 in all, left leg first.

struct UrdfJoint {
  std::string name, parent, child;
  Eigen::Vector3d xyz, rpy;  // <origin>: the child frame in the parent's, before the motion
  Eigen::Vector3d axis;      // in the joint frame
  const char* type;          // "revolute", "prismatic" or "fixed"
};

struct Biped {
  std::vector<UrdfJoint> joints;  // in the file's order; the movable ones are the leg joints
  std::vector<std::string> feet{"l_sole", "r_sole"};

  Biped() {
    for (const double s : {1.0, -1.0}) {  // left, right
      const std::string p = s > 0 ? "l_" : "r_";
      const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(),
                            z = Eigen::Vector3d::UnitZ(), o = Eigen::Vector3d::Zero();
      joints.push_back({p + "hip_yaw",
                        "pelvis",
                        p + "hip1",
                        {0.0, s * 0.09, -0.06},
                        {0.0, 0.0, s * 0.05},
                        z,
                        "revolute"});
      joints.push_back(
          {p + "hip_roll", p + "hip1", p + "hip2", {0.0, 0.0, -0.04}, o, x, "revolute"});
      joints.push_back(
          {p + "hip_pitch", p + "hip2", p + "thigh", {0.0, s * 0.02, 0.0}, o, y, "revolute"});
      joints.push_back({p + "knee",
                        p + "thigh",
                        p + "shin",
                        {0.01, 0.0, -0.32},
                        {0.0, 0.02, 0.0},
                        y,
                        "revolute"});
      joints.push_back(
          {p + "shin_slide", p + "shin", p + "shin2", {0.0, 0.0, -0.15}, o, z, "prismatic"});
      joints.push_back(
          {p + "ankle_pitch", p + "shin2", p + "ankle", {0.0, 0.0, -0.15}, o, y, "revolute"});
      joints.push_back({p + "ankle_roll",
                        p + "ankle",
                        p + "foot",
                        {0.0, 0.0, 0.0},
                        {0.03, -0.02, 0.01},
                        x,
                        "revolute"});
      joints.push_back(
          {p + "sole_fixed", p + "foot", p + "sole", {0.03, 0.0, -0.05}, o, x, "fixed"});
    }
  }

  // The names of the movable joints, in the file's order (the column order of the tests).
  std::vector<std::string> legJoints() const {
    std::vector<std::string> names;
    for (const UrdfJoint& j : joints) {
      if (std::string(j.type) != "fixed") names.push_back(j.name);
    }
    return names;
  }

  // The URDF document. `mujoco_element` goes right after <robot ...> (e.g. a user's own
  // <mujoco><compiler .../></mujoco>). Only the pelvis has an <inertial>: the loader's bounds
  // make a kinematics-only URDF compile.
  std::string urdf(const std::string& mujoco_element = "") const {
    std::ostringstream s;
    s.precision(17);
    const auto v = [&](const Eigen::Vector3d& a) {
      std::ostringstream t;
      t.precision(17);
      t << a.x() << " " << a.y() << " " << a.z();
      return t.str();
    };
    s << "<?xml version=\"1.0\"?>\n<!-- the kit's test biped -->\n<robot name=\"biped\">"
      << mujoco_element << "\n";
    s << "  <link name=\"pelvis\"><inertial><mass value=\"8\"/><inertia ixx=\"0.1\" iyy=\"0.1\" "
         "izz=\"0.1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>\n";
    for (const UrdfJoint& j : joints) s << "  <link name=\"" << j.child << "\"/>\n";
    for (const UrdfJoint& j : joints) {
      s << "  <joint name=\"" << j.name << "\" type=\"" << j.type << "\"><parent link=\""
        << j.parent << "\"/><child link=\"" << j.child << "\"/><origin xyz=\"" << v(j.xyz)
        << "\" rpy=\"" << v(j.rpy) << "\"/><axis xyz=\"" << v(j.axis) << "\"/>";
      if (std::string(j.type) != "fixed") {
        s << "<limit lower=\"-3\" upper=\"3\" effort=\"100\" velocity=\"10\"/>";
      }
      s << "</joint>\n";
    }
    s << "</robot>\n";
    return s.str();
  }

  // The sole link's origin in the pelvis frame at joint values q (q[k]: the k-th movable joint),
  // by URDF's own rule: child = parent * Trans(xyz) * Rz(yaw) Ry(pitch) Rx(roll) * motion(q).
  Eigen::Vector3d foot(int foot, const Eigen::VectorXd& q) const {
    std::vector<const UrdfJoint*> chain;  // from the sole up to the pelvis
    std::string link = feet[foot];
    while (link != "pelvis") {
      for (const UrdfJoint& j : joints) {
        if (j.child == link) {
          chain.push_back(&j);
          link = j.parent;
          break;
        }
      }
    }
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const UrdfJoint& j = **it;
      T.translate(j.xyz);
      T.rotate(Eigen::AngleAxisd(j.rpy.z(), Eigen::Vector3d::UnitZ()) *
               Eigen::AngleAxisd(j.rpy.y(), Eigen::Vector3d::UnitY()) *
               Eigen::AngleAxisd(j.rpy.x(), Eigen::Vector3d::UnitX()));
      const std::string type = j.type;
      if (type == "fixed") continue;
      int k = 0;  // the joint's column: its rank among the movable joints
      while (&joints[index(k)] != &j) ++k;
      if (type == "revolute") T.rotate(Eigen::AngleAxisd(q[k], j.axis));
      if (type == "prismatic") T.translate(q[k] * j.axis);
    }
    return T.translation();
  }

 private:
  // The index in `joints` of the k-th movable joint.
  std::size_t index(int k) const {
    for (std::size_t i = 0; i < joints.size(); ++i) {
      if (std::string(joints[i].type) != "fixed" && k-- == 0) return i;
    }
    return joints.size();
  }
};

// ----------------------------------------------------------------------------------------------
// Hexapod (MJCF). A thorax on a free joint "root"; six legs at angles theta around it, each a
// coxa hinge about z, a femur hinge about y and a tibia hinge about y, the foot a site at the
// tibia's end. In the leg's plane (x outward, z up), with coxa c, femur f, tibia t (hanging down
// at q = 0):
//   x = c + f cos(q2) - t sin(q2 + q3),   z = -f sin(q2) - t cos(q2 + q3),
//   B_p_f = hip + Rz(theta + q1) (x, 0, z).
struct Hexapod {
  static constexpr int kLegs = 6;
  const char* names[kLegs] = {"L1", "L2", "L3", "R1", "R2", "R3"};
  double theta[kLegs] = {0.8, 1.5707963267948966, 2.3, -0.8, -1.5707963267948966, -2.3};
  double a = 0.15, b = 0.08;  // the hips lie on an ellipse (a cos, b sin, -0.01)
  double coxa = 0.05, femur = 0.1, tibia = 0.14;

  Eigen::Vector3d hip(int leg) const {
    return {a * std::cos(theta[leg]), b * std::sin(theta[leg]), -0.01};
  }

  std::vector<std::string> feet() const {
    std::vector<std::string> f;
    for (const char* n : names) f.push_back(std::string(n) + "_foot");
    return f;
  }

  // `extra` goes into the thorax body (e.g. more bodies for the error tests).
  std::string mjcf(const std::string& extra = "") const {
    std::ostringstream s;
    s.precision(17);
    const char* inertial = "<inertial pos='0 0 0' mass='0.1' diaginertia='1e-4 1e-4 1e-4'/>";
    s << "<mujoco model='hexapod'>\n  <compiler angle='radian'/>\n  <worldbody>\n"
      << "    <body name='thorax' pos='0.3 -0.2 0.25' quat='0.9 0.1 0.3 0.2'>\n"
      << "      <freejoint name='root'/>\n"
      << "      <inertial pos='0 0 0' mass='1.5' diaginertia='0.01 0.02 0.02'/>\n"
      << "      <site name='imu'/>\n";
    for (int leg = 0; leg < kLegs; ++leg) {
      const std::string n = names[leg];
      const Eigen::Vector3d h = hip(leg);
      s << "      <body name='" << n << "_coxa' pos='" << h.x() << " " << h.y() << " " << h.z()
        << "' quat='" << std::cos(theta[leg] / 2) << " 0 0 " << std::sin(theta[leg] / 2) << "'>"
        << inertial << "<joint name='" << n << "_coxa' type='hinge' axis='0 0 1'/>\n"
        << "        <body name='" << n << "_femur' pos='" << coxa << " 0 0'>" << inertial
        << "<joint name='" << n << "_femur' type='hinge' axis='0 1 0'/>\n"
        << "          <body name='" << n << "_tibia' pos='" << femur << " 0 0'>" << inertial
        << "<joint name='" << n << "_tibia' type='hinge' axis='0 1 0'/>\n"
        << "            <site name='" << n << "_foot' pos='0 0 " << -tibia << "'/>\n"
        << "          </body>\n        </body>\n      </body>\n";
    }
    s << extra << "    </body>\n  </worldbody>\n</mujoco>\n";
    return s.str();
  }

  // Closed-form FK of the header comment; q holds the 18 joints, leg by leg (coxa, femur, tibia).
  Eigen::Vector3d foot(int leg, const Eigen::VectorXd& q) const {
    const double q1 = q[3 * leg], q2 = q[3 * leg + 1], q3 = q[3 * leg + 2];
    const double x = coxa + femur * std::cos(q2) - tibia * std::sin(q2 + q3);
    const double z = -femur * std::sin(q2) - tibia * std::cos(q2 + q3);
    const double psi = theta[leg] + q1;
    return hip(leg) + Eigen::Vector3d(std::cos(psi) * x, std::sin(psi) * x, z);
  }
};

}  // namespace legkit::test
