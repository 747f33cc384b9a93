#include "model/floating_base_dynamics.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace legkit::model {

using spatial::Matrix6;
using spatial::Transform;
using spatial::Vector6;

namespace {

constexpr int kBase = 0;

void checkLink(const LinkInertia& link, const std::string& name) {
  if (!(std::isfinite(link.mass) && link.mass >= 0.0) || !link.com.allFinite() ||
      !link.inertia.allFinite()) {
    throw std::invalid_argument("QuadrupedDynamics: link " + name +
                                " needs a finite, non-negative mass and a finite com and inertia");
  }
}

// Phi^T F: a body-frame spatial force F = (n, f) on the base as generalized force on (v, omega):
// the world force R f, then the body moment n.
Vector6 baseGeneralizedForce(const Eigen::Matrix3d& R, const Vector6& F) {
  return spatial::stack(R * F.tail<3>(), F.head<3>());
}

}  // namespace

GeneralizedVector FloatingBaseState::nu() const {
  GeneralizedVector n;
  n << v, omega, dq;
  return n;
}

QuadrupedDynamics::QuadrupedDynamics(const QuadrupedGeometry& geometry,
                                     const QuadrupedInertia& inertia, double gravity)
    : kin_(geometry), g_(0.0, 0.0, -gravity) {
  if (!std::isfinite(gravity)) {
    throw std::invalid_argument("QuadrupedDynamics: gravity " + std::to_string(gravity) +
                                " is not finite");
  }
  if (!inertia.armature.allFinite() || (inertia.armature.array() < 0.0).any()) {
    throw std::invalid_argument("QuadrupedDynamics: armature must be finite and non-negative");
  }
  checkLink(inertia.trunk, "trunk");
  parent_[kBase] = -1;
  axis_[kBase] = 0;
  joint_origin_[kBase].setZero();
  I_[kBase] = spatial::spatialInertia(inertia.trunk);
  // Link frames of model/quadruped_inertia.hpp (they reproduce QuadrupedKinematics' FK).
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const int hip = 1 + 3 * leg, thigh = hip + 1, calf = hip + 2;
    const std::string name = legName(leg);
    checkLink(inertia.hip[leg], name + " hip");
    checkLink(inertia.thigh[leg], name + " thigh");
    checkLink(inertia.calf[leg], name + " calf");
    parent_[hip] = kBase;
    parent_[thigh] = hip;
    parent_[calf] = thigh;
    axis_[hip] = 0;    // abduction about x
    axis_[thigh] = 1;  // hip flexion about y
    axis_[calf] = 1;   // knee about y
    joint_origin_[hip] = geometry.hip_offset[leg];
    joint_origin_[thigh] = Eigen::Vector3d(0.0, lateralSign(leg) * geometry.abduction_offset, 0.0);
    joint_origin_[calf] = Eigen::Vector3d(0.0, 0.0, -geometry.thigh_length);
    I_[hip] = spatial::spatialInertia(inertia.hip[leg]);
    I_[thigh] = spatial::spatialInertia(inertia.thigh[leg]);
    I_[calf] = spatial::spatialInertia(inertia.calf[leg]);
    armature_.segment<3>(Eigen::Index{3} * leg) = inertia.armature;
  }
}

Transform QuadrupedDynamics::placement(int i, double qi) const {
  const double c = std::cos(qi), s = std::sin(qi);
  Transform X;
  if (axis_[i] == 0) {
    X.R << 1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c;  // Rx(qi)
  } else {
    X.R << c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c;  // Ry(qi)
  }
  X.r = joint_origin_[i];
  return X;
}

// CRBA (Featherstone, chapter 6). At rest and without gravity h = 0, so column j of M is the
// generalized force that gives joint j alone a unit acceleration: the subtree below j moves as one
// rigid body (its composite inertia Ic_j) accelerated by S_j, which takes F = Ic_j S_j; the links
// between j and the root do not accelerate and pass F on, so every joint i on the way feels
// S_i^T F and the base Phi^T F. Links not below j do not move: that is the whole column.
GeneralizedMatrix QuadrupedDynamics::massMatrix(const FloatingBaseState& x) const {
  std::array<Transform, kNumBodies> X;
  for (int i = 1; i < kNumBodies; ++i) X[i] = placement(i, x.q[i - 1]);

  // Composite inertias, leaves first: Ic_parent += X^T Ic_i X (bodies are numbered root first).
  std::array<spatial::RigidBodyInertia, kNumBodies> Ic = I_;
  for (int i = kNumBodies - 1; i >= 1; --i) Ic[parent_[i]] += spatial::inertiaToParent(X[i], Ic[i]);

  GeneralizedMatrix M = GeneralizedMatrix::Zero();
  for (int i = kNumBodies - 1; i >= 1; --i) {
    const int di = 5 + i;
    const Vector6 S_i = Vector6::Unit(axis_[i]);  // (axis, 0)
    Vector6 F = Ic[i] * S_i;
    M(di, di) = F[axis_[i]] + armature_[i - 1];  // S_i^T Ic_i S_i, plus the rotor's inertia
    int j = i;
    while (parent_[j] != kBase) {
      F = spatial::forceToParent(X[j], F);
      j = parent_[j];
      M(5 + j, di) = M(di, 5 + j) = F[axis_[j]];  // S_j^T F
    }
    F = spatial::forceToParent(X[j], F);                  // now in the base frame
    M.block<6, 1>(0, di) = baseGeneralizedForce(x.R, F);  // Phi^T F
    M.block<1, 6>(di, 0) = M.block<6, 1>(0, di).transpose();
  }

  // Base block Phi^T Ic_0 Phi, column by column: Phi e_k = (0, R^T e_k) for the three v's and
  // (e_k, 0) for the three omega's. It is symmetric in exact arithmetic; rounding in R and in
  // X^T Ic X leaves its triangles a few ulps apart, so it is symmetrized.
  const Eigen::Matrix3d Rt = x.R.transpose();
  for (int k = 0; k < 3; ++k) {
    M.block<6, 1>(0, k) =
        baseGeneralizedForce(x.R, Ic[kBase] * spatial::stack(Eigen::Vector3d::Zero(), Rt.col(k)));
    M.block<6, 1>(0, 3 + k) = baseGeneralizedForce(x.R, Ic[kBase] * Vector6::Unit(k));
  }
  const Matrix6 base = M.topLeftCorner<6, 6>();
  M.topLeftCorner<6, 6>() = 0.5 * (base + base.transpose());
  return M;
}

// RNEA (Featherstone, chapter 5) with nudot = 0. Gravity enters as a fictitious upward
// acceleration -g of the base: relative to the accelerating base every link falls as under
// gravity, so the forces found include the links' weights. Outward pass: each link's velocity and
// acceleration from its parent's,
//   V_i = X_i V_parent + S_i dq_i,   a_i = X_i a_parent + V_i x S_i dq_i,
// and the net force it needs, f_i = I_i a_i + V_i x* I_i V_i (Newton-Euler in spatial form).
// Inward pass: a joint supplies the force of its whole subtree, h_i = S_i^T f_i, and the parent
// adds it: f_parent += X_i^T f_i.
GeneralizedVector QuadrupedDynamics::biasForces(const FloatingBaseState& x) const {
  std::array<Transform, kNumBodies> X;
  std::array<Vector6, kNumBodies> V, a, f;

  const Eigen::Matrix3d Rt = x.R.transpose();
  const Eigen::Vector3d v_body = Rt * x.v;
  V[kBase] = spatial::stack(x.omega, v_body);  // V_0 = Phi nu_b
  // a_0 = -g as a base acceleration, plus the free joint's d/dt(Phi) nu_b = (0, -omega x R^T v).
  a[kBase] = spatial::stack(Eigen::Vector3d::Zero(), -Rt * g_ - x.omega.cross(v_body));
  f[kBase] = I_[kBase] * a[kBase] + spatial::crossForce(V[kBase], I_[kBase] * V[kBase]);

  for (int i = 1; i < kNumBodies; ++i) {
    X[i] = placement(i, x.q[i - 1]);
    Vector6 Sdq = Vector6::Zero();  // S_i dq_i
    Sdq[axis_[i]] = x.dq[i - 1];
    V[i] = spatial::motionToChild(X[i], V[parent_[i]]) + Sdq;
    a[i] = spatial::motionToChild(X[i], a[parent_[i]]) + spatial::crossMotion(V[i], Sdq);
    f[i] = I_[i] * a[i] + spatial::crossForce(V[i], I_[i] * V[i]);
  }

  GeneralizedVector h;
  for (int i = kNumBodies - 1; i >= 1; --i) {
    h[5 + i] = f[i][axis_[i]];  // S_i^T f_i
    f[parent_[i]] += spatial::forceToParent(X[i], f[i]);
  }
  h.head<6>() = baseGeneralizedForce(x.R, f[kBase]);  // Phi^T f_0
  return h;
}

ContactJacobian QuadrupedDynamics::footJacobian(int leg, const FloatingBaseState& x) const {
  if (leg < 0 || leg >= kNumLegs) {
    throw std::invalid_argument("QuadrupedDynamics::footJacobian: leg id " + std::to_string(leg) +
                                " is out of range (expected 0..3: FL, FR, RL, RR)");
  }
  const Eigen::Vector3d q_leg = x.q.segment<3>(Eigen::Index{3} * leg);
  const Eigen::Vector3d B_p_f = kin_.footPosition(leg, q_leg);
  ContactJacobian J = ContactJacobian::Zero();
  J.leftCols<3>().setIdentity();                                        // v
  J.block<3, 3>(0, 3) = -x.R * lie::hat3(B_p_f);                        // R (omega x B_p_f)
  J.block<3, 3>(0, 6 + 3 * leg) = x.R * kin_.footJacobian(leg, q_leg);  // R B_J dq_leg
  return J;
}

}  // namespace legkit::model
