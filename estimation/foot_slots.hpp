// Foot slots: how a filter with a fixed number of foot states (the linear KF, the ESKF and the
// TSIF keep four) serves a robot with more feet, a hexapod say.
//
// Each foot in stance holds a slot, one of the filter's foot states, for as long as it stays
// down; the filter sees slot numbers where the log has foot ids. A foot that touches down takes
// the slot of its own id when that one is free, else the first free one; "free" means held by no
// foot now and by no other foot at the previous sample, so that the filter never mistakes a new
// foot for one that stayed down. When every slot is taken, the foot is left out of that sample
// (Fault::kNoFootSlot) until one frees. For a quadruped (ids 0..3, four slots) every foot keeps
// the slot of its own id and map() hands back its input untouched. A filter may use fewer slots
// than it has room for (the ESKF's two flat feet): capacity.
#pragma once

#include <array>
#include <optional>

#include "estimation/health.hpp"
#include "estimation/step_input.hpp"

namespace legkit {

template <int Slots>
class FootSlots {
 public:
  explicit FootSlots(int capacity = Slots) : capacity_(capacity) { reset(); }
  void reset() {
    slot_of_.fill(-1);
    owner_.fill(-1);
  }

  // `in` with foot ids turned into slots (a copy in `storage` when anything changes).
  const StepInput& map(const StepInput& in, std::optional<StepInput>& storage, Health& health) {
    std::array<int, kMaxIds> slot_of;
    slot_of.fill(-1);
    std::array<int, Slots> owner;
    owner.fill(-1);
    bool identity = true;
    // Feet that stay down keep their slot.
    for (const ContactMeasurement& c : in.stance()) {
      const int s = slot_of_[c.foot];
      if (s < 0) continue;
      slot_of[c.foot] = s;
      owner[s] = c.foot;
      identity = identity && s == c.foot;
    }
    // Feet that touch down: their own slot if free, else the first free one.
    const auto isFree = [&](int s) { return owner[s] < 0 && owner_[s] < 0; };
    for (const ContactMeasurement& c : in.stance()) {
      if (slot_of[c.foot] >= 0) continue;
      int s = c.foot < capacity_ && isFree(c.foot) ? c.foot : -1;
      for (int k = 0; s < 0 && k < capacity_; ++k) s = isFree(k) ? k : -1;
      if (s < 0) {
        health.record(Fault::kNoFootSlot, in.t);
        identity = false;
        continue;
      }
      slot_of[c.foot] = s;
      owner[s] = c.foot;
      identity = identity && s == c.foot;
    }
    slot_of_ = slot_of;
    owner_ = owner;
    if (identity) return in;
    StepInput& mapped = storage.emplace(in);
    mapped.num_contacts = 0;
    for (int k = 0; k < in.num_contacts; ++k) {
      const int s = slot_of[in.contacts[k].foot];
      if (s < 0) continue;
      mapped.normal_force[mapped.num_contacts] = in.normal_force[k];
      mapped.contacts[mapped.num_contacts] = in.contacts[k];
      mapped.contacts[mapped.num_contacts++].foot = s;
    }
    return mapped;
  }

 private:
  static constexpr int kMaxIds = leg_odometry::kMaxContacts;
  int capacity_;                      // slots 0..capacity_-1 are used (<= Slots)
  std::array<int, kMaxIds> slot_of_;  // per foot id: its slot while in stance, else -1
  std::array<int, Slots> owner_;      // per slot: the foot id holding it, else -1
};

}  // namespace legkit
