// A read-only view of the stance feet of one instant (a pointer and a count), so that the leg
// odometry takes contacts from any container without copying or allocating.
#pragma once

#include <cstddef>

#include "model/contact_measurement.hpp"

namespace legkit::leg_odometry {

// The most stance contacts one call accepts (a hexapod, or a biped with four points per foot);
// it bounds the fixed-capacity stacked matrices so that per-step code never allocates.
constexpr int kMaxContacts = 8;

class ContactSpan {
 public:
  ContactSpan(const ContactMeasurement* first, std::size_t count) : first_(first), count_(count) {}
  // Any contiguous container of ContactMeasurement: std::vector, std::array, ...
  template <class Container>
  ContactSpan(const Container& c) : first_(c.data()), count_(c.size()) {}  // NOLINT: implicit

  std::size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  const ContactMeasurement& operator[](std::size_t i) const { return first_[i]; }
  const ContactMeasurement* begin() const { return first_; }
  const ContactMeasurement* end() const { return first_ + count_; }

 private:
  const ContactMeasurement* first_;
  std::size_t count_;
};

}  // namespace legkit::leg_odometry
