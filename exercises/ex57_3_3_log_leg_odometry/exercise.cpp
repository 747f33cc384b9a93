// Your solution to exercise 57.3.3. Replace each throw with your implementation.
#include "ex57_3_3.hpp"

#include <legkit/not_implemented.hpp>

namespace ex57_3_3 {

std::optional<Eigen::Vector3d> rowVelocity(const legkit::io::LogRow& /*row*/,
                                           const legkit::model::QuadrupedKinematics& /*kin*/) {
  throw legkit::NotImplemented("rowVelocity");
}

Comparison compareWithTruth(const legkit::io::Log& /*log*/,
                            const legkit::model::QuadrupedKinematics& /*kin*/) {
  throw legkit::NotImplemented("compareWithTruth");
}

Comparison compareLogFile(const std::string& /*path*/,
                          const legkit::model::QuadrupedKinematics& /*kin*/) {
  throw legkit::NotImplemented("compareLogFile");
}

}  // namespace ex57_3_3
