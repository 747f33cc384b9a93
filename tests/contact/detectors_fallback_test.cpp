// The fallback chain (estimation/contact/fallback_detector.hpp) is lazy: a detector runs at a
// sample only when some foot reached it, and one that sat out the sample before is reset() before
// it runs again. Checked by counting the calls of a test detector, not by timing.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "allocation_counter.hpp"
#include "estimation/contact/fallback_detector.hpp"

using namespace legkit::contact;

namespace {

// What a test detector needs to decide a foot.
enum class Needs { kForce, kKinematics, kNothing };

// Counts its calls; per foot it answers "contact" when it has what it needs (else a problem). Its
// answer's probability is 1 / (samples run since its last reset), so a test can tell a clean
// start from a detector that kept its state.
class CountingDetector : public ContactDetector {
 public:
  CountingDetector(std::string name, Needs needs, long* updates, long* resets)
      : name_(std::move(name)), needs_(needs), updates_(updates), resets_(resets) {}
  std::string name() const override { return name_; }
  void reset() override {
    ++*resets_;
    since_reset_ = 0;
  }
  ContactEstimate update(const ContactSignals& s) override {
    ++*updates_;
    ++since_reset_;
    ContactEstimate e;
    e.t = s.t;
    e.num_feet = s.num_feet;
    for (int i = 0; i < s.num_feet; ++i) {
      e.feet[i].contact = true;
      e.feet[i].probability = 1.0 / static_cast<double>(since_reset_);
      if (needs_ == Needs::kForce && std::isnan(s.feet[i].force))
        e.feet[i].problem = "no force reading";
      if (needs_ == Needs::kKinematics && !s.feet[i].has_kinematics)
        e.feet[i].problem = "no leg kinematics";
    }
    return e;
  }

 private:
  std::string name_;
  Needs needs_;
  long* updates_;
  long* resets_;
  long since_reset_ = 0;
};

}  // namespace

TEST_CASE("fallback: a detector runs only when a foot reaches it, and restarts clean", "[57.6]") {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::array<long, 3> updates{}, resets{};
  std::vector<std::unique_ptr<ContactDetector>> c;
  c.push_back(std::make_unique<CountingDetector>("sensor", Needs::kForce, &updates[0], &resets[0]));
  c.push_back(
      std::make_unique<CountingDetector>("second", Needs::kKinematics, &updates[1], &resets[1]));
  c.push_back(std::make_unique<CountingDetector>("last", Needs::kNothing, &updates[2], &resets[2]));
  FallbackDetector d(std::move(c));
  CHECK(d.name() == "sensor>second>last");
  ContactSignals s;
  s.num_feet = 4;
  for (int i = 0; i < 4; ++i) {
    s.feet[i].force = 30.0;
    s.feet[i].has_kinematics = true;
  }
  long k = 0;
  auto step = [&] {
    s.t = 0.001 * k;
    s.dt = k == 0 ? 0.0 : 0.001;
    ++k;
    return d.update(s);
  };
  // Healthy: only the first detector runs, 100 samples.
  for (int j = 0; j < 100; ++j) CHECK(step().feet[0].usable());
  CHECK(updates == std::array<long, 3>{100, 0, 0});
  CHECK(resets == std::array<long, 3>{0, 0, 0});

  // Foot 2 loses its sensor for 10 samples: the second detector runs on those, once reset first
  // (it sat out the sample before); the last never runs.
  s.feet[2].force = kNaN;
  for (int j = 0; j < 10; ++j) {
    const ContactEstimate e = step();
    CHECK(d.source()[2] == 1);
    CHECK(d.source()[0] == 0);
    CHECK(e.feet[2].probability == Approx(1.0 / (j + 1)));  // counted from the restart
  }
  CHECK(updates == std::array<long, 3>{110, 10, 0});
  CHECK(resets == std::array<long, 3>{0, 1, 0});
  CHECK(d.reports().ran[1] == 10);
  CHECK(d.reports().restarts[1] == 1);

  // Foot 2 also loses its kinematics for 5 samples: the third detector runs too.
  s.feet[2].has_kinematics = false;
  for (int j = 0; j < 5; ++j) {
    step();
    CHECK(d.source()[2] == 2);
  }
  CHECK(updates == std::array<long, 3>{115, 15, 5});
  CHECK(resets == std::array<long, 3>{0, 1, 1});
  // The kinematics come back: the second stage kept running, so it is not reset, and the last
  // stage stops.
  s.feet[2].has_kinematics = true;
  const ContactEstimate e = step();
  CHECK(d.source()[2] == 1);
  CHECK(e.feet[2].probability == Approx(1.0 / 16));
  CHECK(resets == std::array<long, 3>{0, 1, 1});
  // The sensor comes back for 3 samples, then fails again: the second stage restarts clean.
  s.feet[2].force = 30.0;
  for (int j = 0; j < 3; ++j) step();
  CHECK(updates == std::array<long, 3>{119, 16, 5});
  s.feet[2].force = kNaN;
  CHECK(step().feet[2].probability == Approx(1.0));
  CHECK(resets == std::array<long, 3>{0, 2, 1});
  for (int i = 0; i < 4; ++i) CHECK(d.reports().undecided[i] == 0);

  // reset() resets every stage once and the next update is a first one for all: no second reset.
  d.reset();
  CHECK(resets == std::array<long, 3>{1, 3, 2});
  step();
  CHECK(resets == std::array<long, 3>{1, 3, 2});
  CHECK(d.reports().ran == std::array<long, kMaxChain>{1, 1, 0, 0, 0, 0, 0, 0});

  // A restart allocates nothing.
  s.feet[2].force = 30.0;
  step();
  const long before = legkit::test::allocationCount();
  s.feet[2].force = kNaN;
  step();
  CHECK(legkit::test::allocationCount() == before);
}
