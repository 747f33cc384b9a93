#include "estimation/contact/fallback_detector.hpp"

#include <stdexcept>
#include <utility>

#include "estimation/contact/gait_clock.hpp"

namespace legkit::contact {

FallbackDetector::FallbackDetector(std::vector<std::unique_ptr<ContactDetector>> order)
    : order_(std::move(order)) {
  if (order_.empty()) throw std::invalid_argument("fallback: the chain is empty");
  if (order_.size() > static_cast<std::size_t>(kMaxChain))
    throw std::invalid_argument("fallback: more than " + std::to_string(kMaxChain) + " detectors");
  for (std::size_t k = 0; k < order_.size(); ++k) {
    if (!order_[k])
      throw std::invalid_argument("fallback: detector " + std::to_string(k) + " is null");
    name_ += (k == 0 ? "" : ">") + order_[k]->name();
  }
  source_.fill(-1);
}

void FallbackDetector::reset() {
  for (const std::unique_ptr<ContactDetector>& d : order_) d->reset();
  reports_ = FallbackReports{};
  source_.fill(-1);
}

ContactEstimate FallbackDetector::update(const ContactSignals& signals) {
  checkSignals(signals, "fallback");
  // Every detector sees every sample; only the first usable answer per foot is kept.
  std::array<ContactEstimate, kMaxChain> answers;
  const int n = size();
  for (int k = 0; k < n; ++k) answers[k] = order_[k]->update(signals);

  ContactEstimate out;
  out.t = signals.t;
  out.num_feet = signals.num_feet;
  for (int i = 0; i < signals.num_feet; ++i) {
    source_[i] = -1;
    for (int k = 0; k < n; ++k) {
      const FootContact& a = answers[k].feet[i];
      out.feet[i] = a;
      if (a.usable()) {
        source_[i] = k;
        ++reports_.answered[i][k];
        break;
      }
      ++reports_.failed[i][k];
      const FallbackReport r{i, signals.t, k, a.problem};
      if (reports_.first.problem == nullptr) reports_.first = r;
      reports_.last = r;
    }
    if (source_[i] < 0) ++reports_.undecided[i];
  }
  return out;
}

}  // namespace legkit::contact
