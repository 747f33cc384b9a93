#include "model/quadruped_inertia.hpp"

#include <Eigen/Geometry>

namespace legkit::model {
namespace {

// A link given as published: mass, centre of mass, principal moments and the rotation from the
// principal axes to the link frame (quaternion w, x, y, z). Full inertia I = R diag(d) R^T, made
// exactly symmetric (rounding leaves the two triangles a few ulp apart).
LinkInertia fromPrincipal(double mass, const Eigen::Vector3d& com, const Eigen::Quaterniond& axes,
                          const Eigen::Vector3d& principal) {
  const Eigen::Matrix3d R = axes.normalized().toRotationMatrix();
  const Eigen::Matrix3d I = R * principal.asDiagonal() * R.transpose();
  return {mass, com, 0.5 * (I + I.transpose())};
}

// The mirror image of a link through a coordinate plane, S = diag(sign): the centre of mass maps
// to S c and the inertia tensor to S I S (a reflection keeps the tensor's transformation law).
LinkInertia mirrored(const LinkInertia& link, const Eigen::Vector3d& sign) {
  const Eigen::Matrix3d S = sign.asDiagonal();
  return {link.mass, S * link.com, S * link.inertia * S};
}

}  // namespace

double QuadrupedInertia::totalMass() const {
  double m = trunk.mass;
  for (int leg = 0; leg < kNumLegs; ++leg) m += hip[leg].mass + thigh[leg].mass + calf[leg].mass;
  return m;
}

// Figures of the Go2's public MJCF (MuJoCo Menagerie unitree_go2/go2.xml, the same numbers as
// Unitree's own unitree_mujoco go2.xml): <inertial> of "base" and of the FL leg's bodies, whose
// frames coincide with ours (hip at (0.1934, 0.0465, 0), thigh 0.0955 m outward, calf 0.213 m
// down).
QuadrupedInertia QuadrupedInertia::go2() {
  using Eigen::Quaterniond;
  using Eigen::Vector3d;
  QuadrupedInertia in;
  in.trunk = fromPrincipal(6.921, Vector3d(0.021112, 0.0, -0.005366),
                           Quaterniond(-0.000543471, 0.713435, -0.00173769, 0.700719),
                           Vector3d(0.107027, 0.0980771, 0.0244531));
  const LinkInertia hip_fl = fromPrincipal(0.678, Vector3d(-0.0054, 0.00194, -0.000105),
                                           Quaterniond(0.497014, 0.499245, 0.505462, 0.498237),
                                           Vector3d(0.00088403, 0.000596003, 0.000479967));
  const LinkInertia thigh_l = fromPrincipal(1.152, Vector3d(-0.00374, -0.0223, -0.0327),
                                            Quaterniond(0.829533, 0.0847635, -0.0200632, 0.551623),
                                            Vector3d(0.00594973, 0.00584149, 0.000878787));
  const LinkInertia calf_l = fromPrincipal(0.241352, Vector3d(0.00629595, -0.000622121, -0.141417),
                                           Quaterniond(0.710672, 0.00154099, -0.00450087, 0.703508),
                                           Vector3d(0.0014901, 0.00146356, 5.31397e-05));
  const Vector3d flip_y(1.0, -1.0, 1.0), flip_x(-1.0, 1.0, 1.0);
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const bool right = lateralSign(leg) < 0.0, rear = (leg == RL || leg == RR);
    const LinkInertia hip_front = right ? mirrored(hip_fl, flip_y) : hip_fl;
    in.hip[leg] = rear ? mirrored(hip_front, flip_x) : hip_front;
    in.thigh[leg] = right ? mirrored(thigh_l, flip_y) : thigh_l;
    in.calf[leg] = right ? mirrored(calf_l, flip_y) : calf_l;
  }
  // Motor torque limits of the Go2's joints (abduction and hip 23.7 N m, knee 45 N m; the public
  // model's knee ctrlrange is 45.43 N m). Armature 0.01 kg m^2 per joint and damping 0.1 N m s/rad
  // from Unitree's unitree_mujoco go2.xml (the Menagerie model uses the same armature and a
  // damping of 2, which would take ~20 N m of a 23.7 N m budget at a swing leg's 10 rad/s).
  in.torque_limit = Vector3d(23.7, 23.7, 45.0);
  in.armature = Vector3d::Constant(0.01);
  in.damping = Vector3d::Constant(0.1);
  return in;
}

}  // namespace legkit::model
