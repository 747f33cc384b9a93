// Reference solution of exercise 57.6.3.
#include <cmath>
#include <stdexcept>

#include "estimation/linear_kf/linear_kf.hpp"
#include "estimation/log_frontend.hpp"
#include "ex57_6_3.hpp"

namespace ex57_6_3 {

// Per foot a small state machine: the flag reported, and how many rows the log's flag has
// disagreed with it. A disagreement that lasts delay + 1 rows (the change row and `delay` more)
// is reported; a shorter one (a phase shorter than the delay) is forgotten.
legkit::io::Log delayContacts(const legkit::io::Log& log, const DetectionDelay& delay) {
  if (delay.touchdown < 0 || delay.liftoff < 0)
    throw std::invalid_argument("delayContacts: negative delay");
  if (!log.layout.contact)
    throw std::invalid_argument("delayContacts: the log has no contact flags");
  legkit::io::Log out = log;
  if (log.rows.empty()) return out;
  for (int foot = 0; foot < log.layout.num_feet; ++foot) {
    bool reported = log.rows.front().contact[foot];
    int disagreeing = 0;
    for (legkit::io::LogRow& row : out.rows) {
      const bool truth = row.contact[foot];
      disagreeing = truth == reported ? 0 : disagreeing + 1;
      if (disagreeing > (truth ? delay.touchdown : delay.liftoff)) {
        reported = truth;
        disagreeing = 0;
      }
      row.contact[foot] = reported;
    }
  }
  return out;
}

double positionRmse(const legkit::io::Log& log) {
  if (!log.layout.ground_truth)
    throw std::invalid_argument("positionRmse: the log has no ground truth");
  if (log.rows.empty()) return 0.0;
  const legkit::LogFrontend frontend(log.layout, legkit::model::QuadrupedKinematics{});
  legkit::linear_kf::LinearKf kf;
  const legkit::io::LogRow& first = log.rows.front();
  legkit::EstimateSample x0;
  x0.t = first.t;
  x0.q = first.gt_q;
  x0.v = first.gt_v;
  x0.p = first.gt_p;
  kf.reset(x0);
  double sum_sq = 0.0;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const legkit::io::LogRow& row = log.rows[k];
    kf.step(frontend.input(row, k == 0 ? 0.0 : row.t - log.rows[k - 1].t));
    sum_sq += (kf.estimate().p - row.gt_p).squaredNorm();
  }
  return std::sqrt(sum_sq / static_cast<double>(log.rows.size()));
}

DelayCost delayCost(const legkit::io::Log& log, const DetectionDelay& delay) {
  DelayCost cost;
  cost.on_time = positionRmse(log);
  cost.delayed = positionRmse(delayContacts(log, delay));
  cost.increase = cost.delayed - cost.on_time;
  return cost;
}

}  // namespace ex57_6_3
