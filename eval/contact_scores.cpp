#include "eval/contact_scores.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace legkit::eval {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Times of the rises (rising = true) or falls of one foot's flag, from kEventWindow after the
// first sample on (a detector's start-up, which no true event can explain, is not chatter).
std::vector<double> events(const std::vector<double>& t, const std::vector<FootFlags>& flags,
                           int foot, bool rising) {
  std::vector<double> at;
  for (std::size_t k = 1; k < t.size(); ++k) {
    if (t[k] - t.front() < kEventWindow) continue;
    if (flags[k][foot] != flags[k - 1][foot] && flags[k][foot] == rising) at.push_back(t[k]);
  }
  return at;
}

struct Matching {
  std::vector<double> delays;  // t_detected - t_true of the matched true events [s]
  int missed = 0;              // true events without a detected one
  int spurious = 0;            // detected events without a true one
};

// Each true event in time order takes the nearest detected event within the window that no
// earlier true event took.
void match(const std::vector<double>& truth, const std::vector<double>& detected, Matching& m) {
  std::vector<bool> taken(detected.size(), false);
  for (const double t_true : truth) {
    int best = -1;
    for (std::size_t j = 0; j < detected.size(); ++j) {
      const double gap = std::abs(detected[j] - t_true);
      if (taken[j] || gap > kEventWindow) continue;
      if (best < 0 || gap < std::abs(detected[best] - t_true)) best = static_cast<int>(j);
    }
    if (best < 0) {
      ++m.missed;
      continue;
    }
    taken[best] = true;
    m.delays.push_back(detected[best] - t_true);
  }
  m.spurious += static_cast<int>(std::count(taken.begin(), taken.end(), false));
}

double meanMs(const std::vector<double>& d) {
  if (d.empty()) return kNaN;
  double sum = 0.0;
  for (const double x : d) sum += x;
  return 1e3 * sum / static_cast<double>(d.size());
}

// Nearest-rank 95th percentile: the ceil(0.95 n)-th smallest.
double p95Ms(std::vector<double> d) {
  if (d.empty()) return kNaN;
  std::sort(d.begin(), d.end());
  const auto rank = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(d.size())));
  return 1e3 * d[std::max<std::size_t>(rank, 1) - 1];
}

double ratio(double num, double den) {
  return den > 0.0 ? num / den : kNaN;
}

}  // namespace

ContactScores scoreContacts(const std::vector<double>& t, const std::vector<FootFlags>& detected,
                            const std::vector<FootFlags>& truth, int num_feet) {
  if (detected.size() != t.size() || truth.size() != t.size()) {
    throw std::invalid_argument("scoreContacts: " + std::to_string(t.size()) + " times, " +
                                std::to_string(detected.size()) + " detected and " +
                                std::to_string(truth.size()) + " true samples");
  }
  if (t.size() < 2) throw std::invalid_argument("scoreContacts: fewer than two samples");
  if (num_feet < 1 || num_feet > kScoredFeet) {
    throw std::invalid_argument("scoreContacts: num_feet " + std::to_string(num_feet) +
                                " outside [1, " + std::to_string(kScoredFeet) + "]");
  }
  for (std::size_t k = 1; k < t.size(); ++k) {
    if (!(t[k] > t[k - 1])) {
      throw std::invalid_argument("scoreContacts: time does not increase at sample " +
                                  std::to_string(k));
    }
  }

  double tp = 0.0, fp = 0.0, fn = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    for (int i = 0; i < num_feet; ++i) {
      tp += detected[k][i] && truth[k][i];
      fp += detected[k][i] && !truth[k][i];
      fn += !detected[k][i] && truth[k][i];
    }
  }
  Matching down, up;
  ContactScores s;
  for (int i = 0; i < num_feet; ++i) {
    const std::vector<double> true_down = events(t, truth, i, true);
    const std::vector<double> true_up = events(t, truth, i, false);
    s.touchdowns += static_cast<int>(true_down.size());
    s.liftoffs += static_cast<int>(true_up.size());
    match(true_down, events(t, detected, i, true), down);
    match(true_up, events(t, detected, i, false), up);
  }
  s.precision = ratio(tp, tp + fp);
  s.recall = ratio(tp, tp + fn);
  s.f1 = ratio(2.0 * tp, 2.0 * tp + fp + fn);
  s.touchdown_delay_mean = meanMs(down.delays);
  s.touchdown_delay_p95 = p95Ms(down.delays);
  s.liftoff_delay_mean = meanMs(up.delays);
  s.liftoff_delay_p95 = p95Ms(up.delays);
  s.missed_touchdowns = down.missed;
  s.missed_liftoffs = up.missed;
  s.spurious_toggles = down.spurious + up.spurious;
  s.chatter_per_min = s.spurious_toggles / ((t.back() - t.front()) / 60.0);
  return s;
}

}  // namespace legkit::eval
