#include "estimation/leg_odometry/observability.hpp"

#include <Eigen/SVD>
#include <lie/so3.hpp>
#include <stdexcept>
#include <string>

#include "estimation/leg_odometry/checks.hpp"
#include "estimation/leg_odometry/position_observation.hpp"

namespace legkit::leg_odometry {
namespace {

int checkFeet(const Eigen::Ref<const Eigen::Matrix3Xd>& d, const char* who) {
  const Eigen::Index k = d.cols();
  if (k < 1 || k > kMaxContacts) {
    throw std::invalid_argument(std::string(who) + ": needs 1 to " + std::to_string(kMaxContacts) +
                                " stance feet, got " + std::to_string(k));
  }
  detail::checkFinite(d, who, "stance foot positions d");
  return static_cast<int>(k);
}

}  // namespace

ObservabilityJacobian legKinematicsJacobian(const Eigen::Vector3d& p, const Eigen::Matrix3d& R,
                                            const Eigen::Vector3d& v,
                                            const Eigen::Ref<const Eigen::Matrix3Xd>& d,
                                            bool with_gravity) {
  constexpr const char* who = "legKinematicsJacobian";
  const int k = checkFeet(d, who);
  detail::checkRotation(R, who);
  detail::checkFinite(p, who, "base position p");
  detail::checkFinite(v, who, "base velocity v");
  const Eigen::Matrix3d Rt = R.transpose();
  ObservabilityJacobian H;
  H.setZero(6 * k + (with_gravity ? 3 : 0), 9 + 3 * k);
  for (int i = 0; i < k; ++i) {
    Eigen::Matrix3d J_p, J_theta, J_d;
    footMeasurement(p, R, d.col(i), &J_p, &J_theta, &J_d);
    H.block<3, 3>(3 * i, 0) = J_p;
    H.block<3, 3>(3 * i, 3) = J_theta;
    H.block<3, 3>(3 * i, 9 + 3 * i) = J_d;
    // u_i = R^T v: same first-order expansion as footMeasurement's attitude column.
    H.block<3, 3>(3 * k + 3 * i, 3) = Rt * lie::hat3(v);
    H.block<3, 3>(3 * k + 3 * i, 6) = Rt;
  }
  if (with_gravity) H.block<3, 3>(6 * k, 3) = Rt * lie::hat3(Eigen::Vector3d::UnitZ());
  return H;
}

NullSpace nullSpace(const ObservabilityJacobian& H) {
  if (H.size() == 0 || !H.allFinite()) {
    throw std::invalid_argument("nullSpace: the Jacobian is empty or not finite");
  }
  const Eigen::JacobiSVD<ObservabilityJacobian> svd(H, Eigen::ComputeFullV);
  const auto& s = svd.singularValues();
  const double threshold = 1e-9 * s.maxCoeff();
  int rank = 0;
  for (Eigen::Index i = 0; i < s.size(); ++i) rank += s[i] > threshold ? 1 : 0;
  NullSpace out;
  out.dimension = static_cast<int>(H.cols()) - rank;
  out.basis = svd.matrixV().rightCols(out.dimension);
  return out;
}

int nullSpaceDimension(const ObservabilityJacobian& H) {
  return nullSpace(H).dimension;
}

StateDirections unobservableDirections(const Eigen::Vector3d& p, const Eigen::Vector3d& v,
                                       const Eigen::Ref<const Eigen::Matrix3Xd>& d) {
  constexpr const char* who = "unobservableDirections";
  const int k = checkFeet(d, who);
  detail::checkFinite(p, who, "base position p");
  detail::checkFinite(v, who, "base velocity v");
  StateDirections N;
  N.setZero(9 + 3 * k, 4);
  const Eigen::Vector3d ez = Eigen::Vector3d::UnitZ();
  for (int a = 0; a < 3; ++a) {
    N(a, a) = 1.0;                                          // dp = e_a
    for (int i = 0; i < k; ++i) N(9 + 3 * i + a, a) = 1.0;  // dd_i = e_a
  }
  N.block<3, 1>(0, 3) = ez.cross(p);
  N.block<3, 1>(3, 3) = ez;
  N.block<3, 1>(6, 3) = ez.cross(v);
  for (int i = 0; i < k; ++i) N.block<3, 1>(9 + 3 * i, 3) = ez.cross(Eigen::Vector3d(d.col(i)));
  return N;
}

}  // namespace legkit::leg_odometry
