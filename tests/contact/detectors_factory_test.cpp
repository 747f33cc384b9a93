// makeDetector (estimation/contact/detectors.hpp): every name builds its detector, the context a
// detector needs is asked for by name, the fallback chain's order.
#include <catch2/catch.hpp>
#include <string>

#include "estimation/contact/detectors.hpp"
#include "estimation/contact/fallback_detector.hpp"

using namespace legkit::contact;

TEST_CASE("makeDetector builds every detector by its name", "[57.6]") {
  DetectorContext c;
  c.gait = GaitSchedule{};
  LogisticModel m;
  m.w << 0.0, 1.0, -1.0, 0.0;  // force and foot speed: no phase needed
  c.logistic = m;
  const std::vector<std::string> names = detectorNames();
  CHECK(names.size() == 9);
  for (const std::string& n : names) {
    INFO(n);
    const auto d = makeDetector(n, c);
    REQUIRE(d);
    if (n == "fallback")
      CHECK(d->name() == "schmitt>momentum-observer>kinematic>gait-clock");
    else
      CHECK(d->name() == n);
  }
  // Without a gait the chain ends at the kinematic detector.
  c.gait.reset();
  CHECK(makeDetector("fallback", c)->name() == "schmitt>momentum-observer>kinematic");
}

TEST_CASE("makeDetector: missing context and unknown names are errors that say so", "[57.6]") {
  const DetectorContext c;
  CHECK_THROWS_WITH(makeDetector("gait-clock", c), Catch::Contains("gait schedule"));
  CHECK_THROWS_WITH(makeDetector("probabilistic", c), Catch::Contains("logistic model"));
  CHECK_THROWS_WITH(makeDetector("schmit", c), Catch::Contains("known: gait-clock"));
  DetectorContext bad;
  bad.schmitt.f_low = 100.0;  // above f_high
  CHECK_THROWS_AS(makeDetector("schmitt", bad), std::invalid_argument);
}

TEST_CASE("makeDetector: the sensor Schmitt uses the kit's Go2 thresholds", "[57.6]") {
  // 30 N on a standing Go2's foot (37 N load) is a contact for the Go2 design (F_high 25 N), not
  // for the chapter's 50 N.
  auto d = makeDetector("schmitt", DetectorContext{});
  ContactSignals s;
  s.num_feet = 1;
  s.feet[0].force = 30.0;
  bool on = false;
  for (int k = 0; k < 10; ++k) {
    s.t = 0.001 * k;
    s.dt = k == 0 ? 0.0 : 0.001;
    on = d->update(s).feet[0].contact;
  }
  CHECK(on);
  DetectorContext chapter;
  chapter.schmitt = SchmittParams{};
  auto e = makeDetector("schmitt", chapter);
  for (int k = 0; k < 10; ++k) {
    s.t = 0.001 * k;
    s.dt = k == 0 ? 0.0 : 0.001;
    on = e->update(s).feet[0].contact;
  }
  CHECK_FALSE(on);
}
