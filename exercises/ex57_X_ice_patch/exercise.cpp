// Your solution to exercise 57.X. Replace each throw with your implementation.
#include <legkit/not_implemented.hpp>

#include "ex57_X.hpp"

namespace ex57_X {

PipelineEstimator::PipelineEstimator(const legkit::io::LogLayout& /*layout*/,
                                     const std::string& /*estimator*/,
                                     legkit::slip::SlipReaction /*reaction*/) {
  throw legkit::NotImplemented("PipelineEstimator");
}

bool PipelineEstimator::update(const legkit::io::LogRow& /*row*/,
                               legkit::sim::BaseEstimate& /*out*/) {
  throw legkit::NotImplemented("PipelineEstimator::update");
}

IceRun runOnIce(const legkit::io::Log& /*log*/, const legkit::sim::FrictionPatch& /*ice*/,
                const std::string& /*estimator*/, legkit::slip::SlipReaction /*reaction*/) {
  throw legkit::NotImplemented("runOnIce");
}

}  // namespace ex57_X
