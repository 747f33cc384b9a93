// eval::scoreContacts on constructed flag sequences whose scores are known by hand: a 2 Hz square
// wave of true contact (300 ms stance, 200 ms swing, 1 kHz) and detections shifted by known
// delays, with injected chatter, missed and early events.
#include <rapidcheck/catch.h>
#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "eval/contact_scores.hpp"

using legkit::eval::ContactScores;
using legkit::eval::FootFlags;
using legkit::eval::scoreContacts;

namespace {

constexpr int kSamples = 2000;  // 2 s at 1 kHz: t_k = k ms

std::vector<double> times() {
  std::vector<double> t(kSamples);
  for (int k = 0; k < kSamples; ++k) t[k] = 1e-3 * k;
  return t;
}

// Foot 0 in contact for the first 300 samples of every 500: touchdowns at 500, 1000, 1500 ms,
// lift-offs at 300, 800, 1300, 1800 ms. Other feet as `others`.
std::vector<FootFlags> squareWave(bool others = false) {
  std::vector<FootFlags> f(kSamples);
  for (int k = 0; k < kSamples; ++k) {
    f[k].fill(others);
    f[k][0] = k % 500 < 300;
  }
  return f;
}

void setFoot0(std::vector<FootFlags>& f, int from, int to, bool value) {
  for (int k = from; k < to; ++k) f[k][0] = value;
}

}  // namespace

TEST_CASE("delays, chatter and sample scores of a shifted square wave", "[eval][57.6]") {
  const std::vector<FootFlags> truth = squareWave();
  std::vector<FootFlags> detected = truth;
  setFoot0(detected, 500, 510, false);  // touchdowns late by 10, 20, 30 ms
  setFoot0(detected, 1000, 1020, false);
  setFoot0(detected, 1500, 1530, false);
  for (int fall : {300, 800, 1300, 1800}) setFoot0(detected, fall, fall + 5, true);  // +5 ms
  setFoot0(detected, 400, 402, true);  // chatter in swing: a spurious rise and fall

  const ContactScores s = scoreContacts(times(), detected, truth, 1);
  // 1200 true contact samples; 60 lost at the late touchdowns, 20 + 2 false ones.
  CHECK(s.precision == Approx(1140.0 / 1162.0));
  CHECK(s.recall == Approx(0.95));
  CHECK(s.f1 == Approx(2280.0 / 2362.0));
  CHECK(s.touchdowns == 3);
  CHECK(s.liftoffs == 4);
  CHECK(s.missed_touchdowns == 0);
  CHECK(s.missed_liftoffs == 0);
  CHECK(s.touchdown_delay_mean == Approx(20.0));
  CHECK(s.touchdown_delay_p95 == Approx(30.0));  // ceil(0.95 * 3) = 3rd smallest
  CHECK(s.liftoff_delay_mean == Approx(5.0));
  CHECK(s.liftoff_delay_p95 == Approx(5.0));
  CHECK(s.spurious_toggles == 2);
  CHECK(s.chatter_per_min == Approx(2.0 / (1.999 / 60.0)));
}

TEST_CASE("a detection outside the window is a missed event and a spurious one", "[eval][57.6]") {
  const std::vector<FootFlags> truth = squareWave();
  std::vector<FootFlags> detected = truth;
  setFoot0(detected, 500, 650, false);  // 150 ms late: beyond +-100 ms
  setFoot0(detected, 980, 1000, true);  // 20 ms early
  const ContactScores s = scoreContacts(times(), detected, truth, 1);
  CHECK(s.missed_touchdowns == 1);
  CHECK(s.spurious_toggles == 1);
  CHECK(s.touchdown_delay_mean == Approx(-10.0));  // -20 and 0 ms
  CHECK(s.touchdown_delay_p95 == Approx(0.0));
  CHECK(s.liftoff_delay_mean == Approx(0.0));
  CHECK(s.missed_liftoffs == 0);
}

TEST_CASE("a silent detector misses every event; feet are summed", "[eval][57.6]") {
  const std::vector<FootFlags> truth = squareWave(true);  // foot 1 always in contact
  std::vector<FootFlags> detected = truth;
  setFoot0(detected, 0, kSamples, false);
  const ContactScores s = scoreContacts(times(), detected, truth, 2);
  CHECK(s.precision == 1.0);                   // foot 1's 2000 samples only
  CHECK(s.recall == Approx(2000.0 / 3200.0));  // foot 0's 1200 lost
  CHECK(s.f1 == Approx(4000.0 / 5200.0));
  CHECK(s.missed_touchdowns == 3);
  CHECK(s.missed_liftoffs == 4);
  CHECK(std::isnan(s.touchdown_delay_mean));
  CHECK(std::isnan(s.liftoff_delay_p95));
  CHECK(s.chatter_per_min == 0.0);
}

TEST_CASE("a detector's start-up in the first 100 ms is not chatter", "[eval][57.6]") {
  const std::vector<FootFlags> truth = squareWave();
  std::vector<FootFlags> detected = truth;
  setFoot0(detected, 0, 5, false);      // turns on after 5 ms: a rise no true event explains
  setFoot0(detected, 100, 102, false);  // at 100 ms: counted, a spurious fall and rise
  const ContactScores s = scoreContacts(times(), detected, truth, 1);
  CHECK(s.spurious_toggles == 2);
  CHECK(s.touchdowns == 3);
  CHECK(s.recall == Approx(1193.0 / 1200.0));
}

TEST_CASE("no detected and no true contact leaves precision and F1 undefined", "[eval][57.6]") {
  const std::vector<FootFlags> none(kSamples, FootFlags{});
  const ContactScores s = scoreContacts(times(), none, none, 4);
  CHECK(std::isnan(s.precision));
  CHECK(std::isnan(s.recall));
  CHECK(std::isnan(s.f1));
  CHECK(s.touchdowns == 0);
}

TEST_CASE("a detector equal to the truth scores perfectly", "[eval][57.6]") {
  rc::prop("random flags", [] {
    const int n = *rc::gen::inRange(2, 300);
    const int feet = *rc::gen::inRange(1, 9);
    std::vector<double> t(n);
    std::vector<FootFlags> flags(n);
    for (int k = 0; k < n; ++k) {
      t[k] = 1e-3 * k;
      for (int i = 0; i < feet; ++i) flags[k][i] = *rc::gen::arbitrary<bool>();
    }
    const ContactScores s = scoreContacts(t, flags, flags, feet);
    RC_ASSERT(s.spurious_toggles == 0);
    RC_ASSERT(s.missed_touchdowns + s.missed_liftoffs == 0);
    RC_ASSERT(s.touchdowns == 0 || s.touchdown_delay_p95 == 0.0);
    RC_ASSERT(s.liftoffs == 0 || s.liftoff_delay_mean == 0.0);
    RC_ASSERT(std::isnan(s.f1) || s.f1 == 1.0);
  });
}

TEST_CASE("scoreContacts refuses inputs it cannot score", "[eval][57.6]") {
  const std::vector<FootFlags> f = squareWave();
  std::vector<double> t = times();
  CHECK_THROWS_AS(scoreContacts(t, f, std::vector<FootFlags>(10), 1), std::invalid_argument);
  CHECK_THROWS_AS(scoreContacts(t, f, f, 0), std::invalid_argument);
  CHECK_THROWS_AS(scoreContacts(t, f, f, 9), std::invalid_argument);
  CHECK_THROWS_AS(scoreContacts({0.0}, {FootFlags{}}, {FootFlags{}}, 1), std::invalid_argument);
  t[7] = t[6];
  CHECK_THROWS_AS(scoreContacts(t, f, f, 1), std::invalid_argument);
}
