// Reference solution of exercise 57.6.1 (the reasoning: answer.md in this folder).
#include <algorithm>

#include "ex57_6_1.hpp"

namespace ex57_6_1 {

SchmittDesign designSchmitt(const DesignInputs& in) {
  SchmittDesign d;
  // F_low: a foot that has lifted off must read below it, so it sits above what an unloaded
  // sensor reads, the offset plus four standard deviations of the noise (exceeded once in about
  // 30 000 samples, never for a whole T_off).
  d.f_low = in.sensor_bias + 4.0 * in.sensor_sigma;
  // F_high: reached early in the loading of every stance, also when four feet share the weight
  // (half the trot's load each): 40 % of the trot's mean stance load; and at least six noise
  // deviations above F_low, so that noise alone never spans the band.
  d.f_high = std::max(0.4 * in.foot_load, d.f_low + 6.0 * in.sensor_sigma);
  // Hold times: 2 % of the stance (6 ms in the 2 Hz trot), well under the rule of thumb
  // T < 0.1 T_stance, long enough to ride out the bounce of an impact.
  d.t_on = 0.02 * in.stance_time;
  d.t_off = 0.02 * in.stance_time;
  return d;
}

}  // namespace ex57_6_1
