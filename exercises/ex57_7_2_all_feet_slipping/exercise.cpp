// Your solution to exercise 57.7.2. Replace the throw with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_7_2.hpp"

namespace ex57_7_2 {

std::vector<Comparison> legsVersusImu(const legkit::io::Log& /*log*/, double /*t_anchor*/,
                                      const legkit::model::QuadrupedKinematics& /*kin*/) {
  throw legkit::NotImplemented("legsVersusImu");
}

}  // namespace ex57_7_2
