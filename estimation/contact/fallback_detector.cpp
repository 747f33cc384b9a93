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
  ran_prev_.fill(true);
}

void FallbackDetector::reset() {
  for (const std::unique_ptr<ContactDetector>& d : order_) d->reset();
  reports_ = FallbackReports{};
  source_.fill(-1);
  problems_ = {};
  ran_prev_.fill(true);
}

ContactEstimate FallbackDetector::update(const ContactSignals& signals) {
  checkSignals(signals, "fallback");
  ContactEstimate out;
  out.t = signals.t;
  out.num_feet = signals.num_feet;
  // pending[i]: foot i has no usable answer yet and goes on down the chain.
  std::array<bool, kMaxFeet> pending{};
  for (int i = 0; i < signals.num_feet; ++i) {
    pending[i] = true;
    source_[i] = -1;
    problems_[i].fill(nullptr);
  }
  int num_pending = signals.num_feet;
  const int n = size();
  for (int k = 0; k < n; ++k) {
    const bool run = num_pending > 0;
    if (run) {
      if (!ran_prev_[k]) {
        order_[k]->reset();  // idle since before the previous sample: start clean
        ++reports_.restarts[k];
      }
      ++reports_.ran[k];
      const ContactEstimate answer = order_[k]->update(signals);
      for (int i = 0; i < signals.num_feet; ++i) {
        if (!pending[i]) continue;
        const FootContact& a = answer.feet[i];
        out.feet[i] = a;
        if (a.usable()) {
          source_[i] = k;
          ++reports_.answered[i][k];
          pending[i] = false;
          --num_pending;
          continue;
        }
        ++reports_.failed[i][k];
        problems_[i][k] = a.problem;
        const FallbackReport r{i, signals.t, k, a.problem};
        if (reports_.first.problem == nullptr) reports_.first = r;
        reports_.last = r;
      }
    }
    ran_prev_[k] = run;
  }
  for (int i = 0; i < signals.num_feet; ++i) reports_.undecided[i] += pending[i] ? 1 : 0;
  return out;
}

}  // namespace legkit::contact
