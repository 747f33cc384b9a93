// The heading rule of the ESKF, the InEKF and the TSIF (feet_correct_yaw = false, the default;
// the file comments of estimation/invariant/eskf.hpp, invariant_ekf.hpp and tsif.hpp): a
// stance-foot update moves neither the heading nor the gyro bias about the vertical, and moves
// everything else as the plain filter would. Each filter is stepped twice from the same state over
// the same IMU sample: with the sample's stance feet and with none (a prediction only: the heading
// and the bias there are the prediction's).
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "estimation/invariant/eskf.hpp"
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

// The largest moves over 200 samples of a noisy trot (from sample 500 on, every foot held).
template <typename Filter, typename Params, typename BiasOf>
Moved movedByFeet(const Params& params, const BiasOf& biasOf) {
  const io::Log log = trotLog(1.0, 7, false);
  const std::vector<StepInput> inputs = inputsOf(log);
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

}  // namespace

TEST_CASE("Stance feet correct neither the heading nor the vertical gyro bias", "[57.5][heading]") {
  const auto eskfBias = [](const invariant::Eskf& f) { return f.state().b_g; };
  const auto inekfBias = [](const invariant::InvariantEkf& f) { return f.b_g(); };
  const auto tsifBias = [](const invariant::Tsif& f) { return f.state().b_g; };
  for (const bool correct_yaw : {false, true}) {
    invariant::EskfParams e;
    e.feet_correct_yaw = correct_yaw;
    invariant::InvariantEkfParams i;
    i.feet_correct_yaw = correct_yaw;
    invariant::TsifParams ts;
    ts.feet_correct_yaw = correct_yaw;
    const Moved eskf = movedByFeet<invariant::Eskf>(e, eskfBias);
    const Moved inekf = movedByFeet<invariant::InvariantEkf>(i, inekfBias);
    const Moved tsif = movedByFeet<invariant::Tsif>(ts, tsifBias);
    INFO("feet_correct_yaw " << correct_yaw << ": ESKF heading " << eskf.heading << " rad, bias "
                             << eskf.bias << " rad/s, position " << eskf.position << " m; InEKF "
                             << inekf.heading << ", " << inekf.bias << ", " << inekf.position);
    CHECK(eskf.position > 1e-5);  // the feet do correct the state
    CHECK(inekf.position > 1e-5);
    CHECK(tsif.position > 1e-5);
    if (correct_yaw) {  // the plain filters (2.5e-5 rad, 5.6e-6 rad/s): this check has teeth
      CHECK(eskf.heading > 1e-5);
      CHECK(inekf.heading > 1e-5);
      CHECK(eskf.bias > 1e-6);
      CHECK(inekf.bias > 1e-6);
      CHECK(tsif.heading > 1e-5);
      CHECK(tsif.bias > 1e-6);
    } else {  // second order only: a tilt correction dtheta turns the heading by ~|dtheta|^2
      CHECK(eskf.heading < 3e-8);
      CHECK(inekf.heading < 3e-8);
      CHECK(eskf.bias < 1e-15);
      CHECK(inekf.bias < 1e-15);
      CHECK(tsif.heading < 3e-8);
      CHECK(tsif.bias < 1e-15);
    }
  }
}
