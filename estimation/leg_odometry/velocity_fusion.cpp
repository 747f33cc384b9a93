#include "estimation/leg_odometry/velocity_fusion.hpp"

#include <Eigen/Dense>
#include <stdexcept>
#include <string>

#include "estimation/leg_odometry/checks.hpp"

namespace legkit::leg_odometry {
namespace {

void checkContacts(ContactSpan contacts, const char* who) {
  if (contacts.empty()) {
    throw std::invalid_argument(std::string(who) +
                                ": the contact set is empty (no stance foot, so the legs give no "
                                "velocity; propagate with the IMU alone)");
  }
  if (contacts.size() > static_cast<std::size_t>(kMaxContacts)) {
    throw std::invalid_argument(std::string(who) + ": " + std::to_string(contacts.size()) +
                                " contacts exceed kMaxContacts = " + std::to_string(kMaxContacts));
  }
}

}  // namespace

Eigen::Vector3d meanVelocity(const Eigen::Matrix3d& R, const Eigen::Vector3d& w_b,
                             ContactSpan contacts) {
  checkContacts(contacts, "meanVelocity");
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const ContactMeasurement& c : contacts) sum += baseVelocityFromFoot(R, w_b, c);
  return sum / static_cast<double>(contacts.size());
}

Eigen::Vector3d forceWeightedVelocity(const Eigen::Matrix3d& R, const Eigen::Vector3d& w_b,
                                      ContactSpan contacts,
                                      const Eigen::Ref<const Eigen::VectorXd>& normal_forces) {
  constexpr const char* who = "forceWeightedVelocity";
  checkContacts(contacts, who);
  if (normal_forces.size() != static_cast<Eigen::Index>(contacts.size())) {
    throw std::invalid_argument(std::string(who) + ": " + std::to_string(normal_forces.size()) +
                                " normal forces for " + std::to_string(contacts.size()) +
                                " contacts");
  }
  detail::checkFinite(normal_forces, who, "normal force");
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double total = 0.0;
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const double f = std::max(normal_forces[static_cast<Eigen::Index>(i)], 0.0);
    sum += f * baseVelocityFromFoot(R, w_b, contacts[i]);
    total += f;
  }
  if (!(total > 0.0)) {
    throw std::invalid_argument(std::string(who) + ": no stance foot carries a positive load");
  }
  return sum / total;
}

StackedVelocityMeasurement stackVelocityMeasurements(const Eigen::Matrix3d& R,
                                                     const Eigen::Vector3d& w_b,
                                                     ContactSpan contacts,
                                                     const FootVelocityNoise& noise) {
  checkContacts(contacts, "stackVelocityMeasurements");
  const int rows = 3 * static_cast<int>(contacts.size());
  StackedVelocityMeasurement m;
  m.z.resize(rows);
  m.H_v.resize(rows, 3);
  m.Rn.setZero(rows, rows);
  for (int i = 0; i < rows / 3; ++i) {
    const ContactMeasurement& c = contacts[static_cast<std::size_t>(i)];
    m.z.segment<3>(3 * i) = baseVelocityFromFoot(R, w_b, c);
    m.H_v.block<3, 3>(3 * i, 0).setIdentity();
    m.Rn.block<3, 3>(3 * i, 3 * i) = baseVelocityCovariance(R, w_b, c.p_body, c.cov, noise);
  }
  return m;
}

FusedVelocity fuseStacked(const StackedVelocityMeasurement& m) {
  if (m.feet() == 0 || m.H_v.rows() != m.z.size() || m.Rn.rows() != m.z.size()) {
    throw std::invalid_argument("fuseStacked: empty or inconsistent stacked measurement");
  }
  // Rn is block diagonal, so the information sum runs foot by foot.
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  Eigen::Vector3d information_vector = Eigen::Vector3d::Zero();
  for (int i = 0; i < m.feet(); ++i) {
    const Eigen::LLT<Eigen::Matrix3d> llt(m.Rn.block<3, 3>(3 * i, 3 * i));
    if (llt.info() != Eigen::Success) {
      throw std::invalid_argument("fuseStacked: the covariance of foot measurement " +
                                  std::to_string(i) + " is not positive definite");
    }
    const Eigen::Matrix3d H_i = m.H_v.block<3, 3>(3 * i, 0);
    information += H_i.transpose() * llt.solve(H_i);
    information_vector += H_i.transpose() * llt.solve(m.z.segment<3>(3 * i));
  }
  FusedVelocity out;
  out.P = information.inverse();
  out.v = out.P * information_vector;
  return out;
}

}  // namespace legkit::leg_odometry
