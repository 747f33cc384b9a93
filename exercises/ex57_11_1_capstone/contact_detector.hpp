// Capstone 57.11.1, piece 2: the four-foot Schmitt trigger of section 57.6.
#pragma once

#include <array>

namespace ex57_11 {

struct SchmittConfig {
  double f_high = 25.0, f_low = 10.0;  // F_high, F_low [N]
  double t_on = 0.005, t_off = 0.005;  // T_on, T_off [s]
};

// Per foot, starting in swing:
//   contact = 1          once F > F_high has held for longer than T_on,
//             0          once F < F_low  has held for longer than T_off,
//             unchanged  otherwise.
// "Held" sums the dt of the samples beyond the threshold that would switch the state, from the
// first of them (its own dt included); a sample not beyond it restarts the sum at zero. "Longer
// than T" is sum > T + 1e-9: five 1 ms samples hold for exactly 5 ms, not longer, so a 5 ms hold
// switches on the sixth (the 1 ns absorbs the rounding of the sum).
class SchmittContactDetector {
 public:
  explicit SchmittContactDetector(const SchmittConfig& config = {});
  void reset();  // every foot back to swing, nothing held
  // One sample of the four normal forces [N], dt after the previous one [s].
  const std::array<bool, 4>& update(const std::array<double, 4>& force, double dt);
  const std::array<bool, 4>& contact() const { return contact_; }

 private:
  SchmittConfig config_;
  std::array<bool, 4> contact_{};
  std::array<double, 4> held_{};
};

}  // namespace ex57_11
