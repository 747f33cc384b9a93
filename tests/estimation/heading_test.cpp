// The heading rule of the ESKF, the InEKF and the TSIF (feet_correct_yaw = false, the default;
// the file comments of estimation/invariant/eskf.hpp, invariant_ekf.hpp and tsif.hpp): with the
// whole rule a stance-foot update moves neither the heading nor the gyro bias about the vertical,
// and moves everything else as the plain filter would; its share alpha follows the turn rate and
// a slip (estimation/invariant/heading_rule.hpp). Each filter is stepped twice from the same state
// over the same IMU sample: with the sample's stance feet and with none (a prediction only: the
// heading and the bias there are the prediction's).
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "estimation/invariant/eskf.hpp"
#include "estimation/invariant/heading_rule.hpp"
#include "estimation/invariant/invariant_ekf.hpp"
#include "estimation/invariant/tsif.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "trot_log.hpp"

using namespace legkit;
using legkit::test::inputsOf;
using legkit::test::trotLog;

namespace {

struct Moved {
  double heading = 0.0;   // |yaw(updated) - yaw(predicted)| [rad]
  double bias = 0.0;      // |up^T (b_g updated - b_g predicted)| [rad/s]
  double position = 0.0;  // |p updated - p predicted| [m]: the update does something
};

// The largest moves over 200 samples of a noisy trot (from sample 500 on, every foot held); with
// `slip`, every sample says the slip detector accused a foot (StepInput::slip).
template <typename Filter, typename Params, typename BiasOf>
Moved movedByFeet(const Params& params, const BiasOf& biasOf, bool slip = false) {
  const io::Log log = trotLog(1.0, 7, false);
  std::vector<StepInput> inputs = inputsOf(log);
  for (StepInput& in : inputs) in.slip = slip;
  Filter filter(params);
  filter.reset(eval::initialState(log));
  Moved worst;
  for (std::size_t k = 0; k < 700; ++k) {
    if (k >= 500 && inputs[k].num_contacts > 0) {
      Filter predicted = filter;
      StepInput none = inputs[k];
      none.num_contacts = 0;
      predicted.step(none);
      Filter updated = filter;
      updated.step(inputs[k]);
      const EstimateSample a = updated.estimate(), b = predicted.estimate();
      const Eigen::Vector3d up = b.q.toRotationMatrix().row(2).transpose();
      worst.heading =
          std::max(worst.heading, eval::yawError(a.q.toRotationMatrix(), b.q.toRotationMatrix()));
      worst.bias = std::max(worst.bias, std::abs(up.dot(biasOf(updated) - biasOf(predicted))));
      worst.position = std::max(worst.position, (a.p - b.p).norm());
    }
    filter.step(inputs[k]);
  }
  return worst;
}

// Whether the three filters' feet move the heading and the vertical gyro bias: the plain filters
// and the rule at alpha near 0 do, the whole rule (alpha = 1) does not (to second order).
struct Case {
  const char* what;
  bool correct_yaw;
  double turn_rate;  // FilterParams::heading_turn_rate
  bool slip;
  bool moved;  // the heading and the bias move as the plain filter's
};

void checkHeading(const Case& c) {
  const auto eskfBias = [](const invariant::Eskf& f) { return f.state().b_g; };
  const auto inekfBias = [](const invariant::InvariantEkf& f) { return f.b_g(); };
  const auto tsifBias = [](const invariant::Tsif& f) { return f.state().b_g; };
  invariant::EskfParams e;
  invariant::InvariantEkfParams i;
  invariant::TsifParams ts;
  for (invariant::FilterParams* p :
       {static_cast<invariant::FilterParams*>(&e), static_cast<invariant::FilterParams*>(&i),
        static_cast<invariant::FilterParams*>(&ts)}) {
    p->feet_correct_yaw = c.correct_yaw;
    p->heading_turn_rate = c.turn_rate;
  }
  const Moved eskf = movedByFeet<invariant::Eskf>(e, eskfBias, c.slip);
  const Moved inekf = movedByFeet<invariant::InvariantEkf>(i, inekfBias, c.slip);
  const Moved tsif = movedByFeet<invariant::Tsif>(ts, tsifBias, c.slip);
  INFO(c.what << ": ESKF heading " << eskf.heading << " rad, bias " << eskf.bias
              << " rad/s, position " << eskf.position << " m; InEKF " << inekf.heading << ", "
              << inekf.bias << ", " << inekf.position << "; TSIF " << tsif.heading << ", "
              << tsif.bias << ", " << tsif.position);
  CHECK(eskf.position > 1e-5);  // the feet do correct the state
  CHECK(inekf.position > 1e-5);
  CHECK(tsif.position > 1e-5);
  if (c.moved) {  // as the plain filters (2.5e-5 rad, 5.6e-6 rad/s): this check has teeth
    CHECK(eskf.heading > 1e-5);
    CHECK(inekf.heading > 1e-5);
    CHECK(tsif.heading > 1e-5);
    CHECK(eskf.bias > 1e-6);
    CHECK(inekf.bias > 1e-6);
    CHECK(tsif.bias > 1e-6);
  } else {  // second order only: a tilt correction dtheta turns the heading by ~|dtheta|^2
    CHECK(eskf.heading < 3e-8);
    CHECK(inekf.heading < 3e-8);
    CHECK(tsif.heading < 3e-8);
    CHECK(eskf.bias < 1e-15);
    CHECK(inekf.bias < 1e-15);
    CHECK(tsif.bias < 1e-15);
  }
}

}  // namespace

TEST_CASE("Stance feet and the heading: the whole rule, its share by the turn rate, a slip",
          "[57.5][heading]") {
  // The trot's low-passed yaw rate stays far above 1e-9 rad/s and far below 1e9.
  for (const Case& c :
       {Case{"the whole rule (heading_turn_rate 0)", false, 0.0, false, false},
        Case{"the plain filters", true, 0.05, false, true},
        Case{"the rule at a yaw rate far below turn_rate", false, 1e9, false, true},
        Case{"the rule at a yaw rate far above turn_rate", false, 1e-9, false, false},
        Case{"a slipping foot holds the whole rule", false, 1e9, true, false}}) {
    checkHeading(c);
  }
}

TEST_CASE("The heading rule's share follows the low-passed turn rate and a slip",
          "[57.5][heading]") {
  const double dt = 1e-3, tau = 1.0, turn_rate = 0.05;
  invariant::HeadingRule rule(turn_rate, tau);
  rule.reset();
  rule.add(0.0, dt, false);  // the first sample is the mean: straight ahead
  CHECK(rule.alpha() == 0.0);
  // A step to 0.02 rad/s: the first-order low-pass reaches 1 - 1/e of it after tau.
  for (int k = 0; k < 1000; ++k) rule.add(0.02, dt, false);
  CHECK(rule.turnRate() == Approx(0.02 * (1.0 - std::exp(-1.0))).epsilon(1e-3));
  for (int k = 0; k < 20000; ++k) rule.add(0.02, dt, false);
  CHECK(rule.alpha() == Approx(0.02 / turn_rate).epsilon(1e-6));
  for (int k = 0; k < 20000; ++k) rule.add(-0.2, dt, false);  // turning right, faster
  CHECK(rule.alpha() == 1.0);
  // Straight again, then one slipping sample: whole for tau, then the turn rate's share again.
  for (int k = 0; k < 20000; ++k) rule.add(0.0, dt, false);
  CHECK(rule.alpha() < 1e-6);
  rule.add(0.0, dt, true);
  for (int k = 0; k < 990; ++k) rule.add(0.0, dt, false);
  CHECK(rule.alpha() == 1.0);
  for (int k = 0; k < 20; ++k) rule.add(0.0, dt, false);
  CHECK(rule.alpha() < 1e-6);
  // turn_rate 0: the whole rule always; reset forgets the turn.
  invariant::HeadingRule whole(0.0, tau);
  whole.reset();
  whole.add(0.0, dt, false);
  CHECK(whole.alpha() == 1.0);
  rule.reset();
  rule.add(0.0, dt, false);
  CHECK(rule.alpha() == 0.0);
}
