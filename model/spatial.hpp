// Spatial (6D) vector algebra for rigid-body dynamics, in the kit's conventions (Featherstone,
// "Rigid Body Dynamics Algorithms", chapter 2, with his symbols).
//
// A spatial vector is ordered (angular, linear), like the kit's SE(3) tangent (phi, rho):
//   motion V = (w, v_O): the angular velocity and the velocity of the point at the frame origin O;
//   force  F = (n_O, f): the moment about O and the force.
// Both are expressed in the axes of one frame; their scalar product F . V is a power [W].
// Featherstone uses the same (angular, linear) order; Pinocchio puts linear first (swap 3x3 blocks
// when comparing with it, as chapters/00-conventions.md says for Sophus and manif).
//
// Header-only, fixed-size Eigen, nothing allocated.
#pragma once

#include <Eigen/Core>
#include <lie/so3.hpp>

#include "model/quadruped_inertia.hpp"

namespace legkit::model::spatial {

using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

inline Vector6 stack(const Eigen::Vector3d& angular, const Eigen::Vector3d& linear) {
  Vector6 x;
  x << angular, linear;
  return x;
}

// Motion cross product V x M (the rate of change of the motion vector M carried by a body moving
// with V): (w x m_w, w x m_v + v x m_w). Its matrix is crm(V) = [[w]x, 0; [v]x, [w]x].
inline Vector6 crossMotion(const Vector6& V, const Vector6& M) {
  const Eigen::Vector3d w = V.head<3>(), v = V.tail<3>();
  return stack(w.cross(M.head<3>()), w.cross(M.tail<3>()) + v.cross(M.head<3>()));
}

// Force cross product V x* F = -crm(V)^T F: (w x n + v x f, w x f). It is the rate of change of
// the force (or momentum) vector F carried by a body moving with V; V x* (I V) is the gyroscopic
// (velocity-product) force of a body of spatial inertia I.
inline Vector6 crossForce(const Vector6& V, const Vector6& F) {
  const Eigen::Vector3d w = V.head<3>(), v = V.tail<3>();
  return stack(w.cross(F.head<3>()) + v.cross(F.tail<3>()), w.cross(F.tail<3>()));
}

// Spatial inertia of a rigid body (or of several welded together) about a frame's origin, in
// that frame's axes (Featherstone, chapter 2):
//   I = [[Ibar, [h]x], [[h]x^T, m 1]],
// ten numbers: the mass m, the first moment h = m c (c the centre of mass) and the rotational
// inertia about the origin Ibar = I_c + m [c]x [c]x^T (parallel-axis theorem). I V is the body's
// momentum when it moves with V = (w, v_O): linear m (v_O + w x c), angular Ibar w + h x v_O.
struct RigidBodyInertia {
  double m = 0.0;
  Eigen::Vector3d h = Eigen::Vector3d::Zero();
  Eigen::Matrix3d Ibar = Eigen::Matrix3d::Zero();

  Vector6 operator*(const Vector6& V) const {
    const Eigen::Vector3d w = V.head<3>(), v = V.tail<3>();
    return stack(Ibar * w + h.cross(v), m * v + w.cross(h));
  }
  // Welding two bodies together adds their inertias (about the same origin, in the same axes).
  RigidBodyInertia& operator+=(const RigidBodyInertia& other) {
    m += other.m;
    h += other.h;
    Ibar += other.Ibar;
    return *this;
  }
  Matrix6 matrix() const {
    Matrix6 I;
    I << Ibar, lie::hat3(h), lie::hat3(h).transpose(), m * Eigen::Matrix3d::Identity();
    return I;
  }
};

// The spatial inertia of a link from its mass properties (LinkInertia: com and inertia about the
// com, in the link frame).
inline RigidBodyInertia spatialInertia(const LinkInertia& link) {
  const Eigen::Matrix3d C = lie::hat3(link.com);
  return {link.mass, link.mass * link.com, link.inertia + link.mass * C * C.transpose()};
}

// Placement of a child frame in its parent: the child's axes R (child to parent, the kit's
// "R maps body to world" read one level down) and the child's origin r in the parent's coordinates.
struct Transform {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
};

// A motion vector given in the parent frame, expressed in the child frame (Featherstone's
// X = [[R^T, 0], [-R^T [r]x, R^T]]): the angular part is only rotated, the linear part moves from
// the parent's origin to the child's, v_child_origin = v + w x r.
inline Vector6 motionToChild(const Transform& X, const Vector6& M) {
  const Eigen::Vector3d w = M.head<3>();
  return stack(X.R.transpose() * w, X.R.transpose() * (M.tail<3>() + w.cross(X.r)));
}

// A force given in the child frame, expressed in the parent frame (X^T, the dual of motionToChild,
// so that power is the same in both): f is rotated, its moment moves to the parent's origin,
// n_parent = R n + r x (R f).
inline Vector6 forceToParent(const Transform& X, const Vector6& F) {
  const Eigen::Vector3d f = X.R * F.tail<3>();
  return stack(X.R * F.head<3>() + X.r.cross(f), f);
}

// The 6x6 matrix X of motionToChild (for tests and for readers who want the matrices).
inline Matrix6 motionToChildMatrix(const Transform& X) {
  const Eigen::Matrix3d Rt = X.R.transpose();
  Matrix6 Xm;
  Xm << Rt, Eigen::Matrix3d::Zero(), -Rt * lie::hat3(X.r), Rt;
  return Xm;
}

// A spatial inertia given in the child frame, expressed in the parent frame: X^T I X, the matrix
// that gives the body's momentum X^T I X V for a parent-frame velocity V. Done on the ten numbers
// instead of 6x6 products: rotate (h1 = R h, R Ibar R^T), then move the origin by r. Writing out
// [[1, [r]x], [0, 1]] I_rotated [[1, 0], [-[r]x, 1]] gives h' = h1 + m r and
//   Ibar' = R Ibar R^T - [r]x [h1]x - [h1]x [r]x - m [r]x [r]x
// (the parallel-axis theorem when h = 0).
inline RigidBodyInertia inertiaToParent(const Transform& X, const RigidBodyInertia& I) {
  const Eigen::Vector3d h1 = X.R * I.h;
  const Eigen::Matrix3d rx = lie::hat3(X.r), h1x = lie::hat3(h1);
  return {I.m, h1 + I.m * X.r,
          X.R * I.Ibar * X.R.transpose() - rx * h1x - h1x * rx - I.m * rx * rx};
}

}  // namespace legkit::model::spatial
