// Your solution to exercise 57.6.1. Replace the throw with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_6_1.hpp"

namespace ex57_6_1 {

SchmittDesign designSchmitt(const DesignInputs& /*in*/) {
  throw legkit::NotImplemented("designSchmitt");
}

}  // namespace ex57_6_1
