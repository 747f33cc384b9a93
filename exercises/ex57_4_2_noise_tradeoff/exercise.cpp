// Your solution to exercise 57.4.2. Replace each throw with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_4_2.hpp"

namespace ex57_4_2 {

legkit::linear_kf::LinearKfParams filterParams(
    const Scales& /*scales*/, const legkit::linear_kf::LinearKfParams& /*nominal*/) {
  throw legkit::NotImplemented("filterParams");
}

legkit::FrontendNoise frontendNoise(const Scales& /*scales*/,
                                    const legkit::FrontendNoise& /*nominal*/) {
  throw legkit::NotImplemented("frontendNoise");
}

legkit::eval::BiasVariance tradeoffPoint(const legkit::io::Log& /*log*/, const Scales& /*scales*/,
                                         const legkit::FrontendNoise& /*nominal*/,
                                         double /*window*/) {
  throw legkit::NotImplemented("tradeoffPoint");
}

}  // namespace ex57_4_2
