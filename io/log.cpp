#include "io/log.hpp"

namespace legkit::io {

bool exactlyEqual(const LogRow& a, const LogRow& b) {
  bool feet_equal = true;
  for (int k = 0; k < kMaxFeet; ++k) {
    feet_equal = feet_equal && a.feet[k].p_body == b.feet[k].p_body &&
                 a.feet[k].cov == b.feet[k].cov && a.feet[k].v_body == b.feet[k].v_body;
    const FootTruth& x = a.gt_feet[k];
    const FootTruth& y = b.gt_feet[k];
    feet_equal = feet_equal && x.contact == y.contact && x.normal_force == y.normal_force &&
                 x.tangential_force == y.tangential_force && x.velocity == y.velocity &&
                 x.slip_speed == y.slip_speed;
  }
  return a.t == b.t && a.gyro == b.gyro && a.acc == b.acc && a.q == b.q && a.dq == b.dq &&
         a.tau == b.tau && a.joint_q == b.joint_q && a.joint_dq == b.joint_dq &&
         a.force == b.force && a.contact == b.contact && feet_equal && a.gt_p == b.gt_p &&
         a.gt_q.coeffs() == b.gt_q.coeffs() && a.gt_v == b.gt_v && a.gt_valid == b.gt_valid;
}

}  // namespace legkit::io
