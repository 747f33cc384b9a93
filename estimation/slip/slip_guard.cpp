#include "estimation/slip/slip_guard.hpp"

namespace legkit::slip {

std::optional<SlipReaction> slipReactionByName(const std::string& name) {
  for (const SlipReaction r :
       {SlipReaction::kNone, SlipReaction::kInflate, SlipReaction::kDrop, SlipReaction::kImuOnly}) {
    if (name == slipReactionName(r)) return r;
  }
  return std::nullopt;
}

const char* slipReactionName(SlipReaction reaction) {
  switch (reaction) {
    case SlipReaction::kNone:
      return "none";
    case SlipReaction::kInflate:
      return "inflate";
    case SlipReaction::kDrop:
      return "drop";
    case SlipReaction::kImuOnly:
      return "imu-only";
  }
  return "none";
}

SlipGuard::SlipGuard(const SlipParams& params, SlipReaction reaction)
    : detector_(params), reaction_(reaction) {}

const StepInput& SlipGuard::apply(const StepInput& in, const EstimateSample& x,
                                  const std::optional<BaseCovariance>& P,
                                  std::optional<StepInput>& storage, SlipReport* report) {
  const SlipReport r = P ? detector_.check(in, x, *P) : detector_.check(in, x);
  if (report != nullptr) *report = r;
  if (reaction_ == SlipReaction::kNone) return in;

  // Which contacts the reaction touches.
  const bool every_foot = r.all_slipping && reaction_ != SlipReaction::kDrop;
  std::array<bool, leg_odometry::kMaxContacts> hit{};
  bool any = false;
  for (int k = 0; k < in.num_contacts; ++k) {
    hit[k] = every_foot || r.slipping(in.contacts[k].foot);
    any = any || hit[k];
  }
  if (!any) return in;

  storage = in;
  StepInput& out = *storage;
  out.slip = true;
  if (reaction_ == SlipReaction::kInflate) {
    for (int k = 0; k < in.num_contacts; ++k) {
      if (hit[k]) out.contacts[k].cov *= detector_.params().inflate;  // R_i <- R_i alpha_inflate
    }
    return out;
  }
  int kept = 0;  // kDrop, kImuOnly: the contacts not hit, in their order
  for (int k = 0; k < in.num_contacts; ++k) {
    if (hit[k]) continue;
    out.contacts[kept] = in.contacts[k];
    out.normal_force[kept] = in.normal_force[k];
    ++kept;
  }
  out.num_contacts = kept;
  return out;
}

}  // namespace legkit::slip
