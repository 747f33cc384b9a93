// Exercise 57.6.1: the Schmitt trigger's thresholds and hold times for a trot, from what the robot
// and its force sensors are.
#pragma once

namespace ex57_6_1 {

// What the design starts from.
struct DesignInputs {
  double stance_time = 0.3;  // T_stance of the gait: 2 Hz trot, 500 ms period, 300 ms stance [s]
  // Mean normal force on a stance foot: m g over the feet in stance (the kit's Go2-class robot,
  // 15.206 kg, on two feet in a trot) [N].
  double foot_load = 15.206 * 9.81 / 2.0;
  double sensor_bias = 3.0;   // the foot force sensor's constant offset [N]
  double sensor_sigma = 2.0;  // its white noise, per sample [N]
  double saturation = 150.0;  // it never reads more than this [N]
};

// The four numbers of the Schmitt trigger (estimation/contact/schmitt_trigger.hpp).
struct SchmittDesign {
  double f_high = 0.0;  // F_high: contact once the force has stayed above it for T_on [N]
  double f_low = 0.0;   // F_low: no contact once it has stayed below it for T_off [N]
  double t_on = 0.0;    // T_on [s]
  double t_off = 0.0;   // T_off [s]
};

SchmittDesign designSchmitt(const DesignInputs& in);

}  // namespace ex57_6_1
