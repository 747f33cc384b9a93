// Your solution to exercise 57.X. Replace the throw with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_X.hpp"

namespace ex57_X {

IceRun runOnIce(const legkit::io::Log& /*log*/, const legkit::sim::FrictionPatch& /*ice*/,
                const std::string& /*estimator*/, legkit::slip::SlipReaction /*reaction*/) {
  throw legkit::NotImplemented("runOnIce");
}

}  // namespace ex57_X
