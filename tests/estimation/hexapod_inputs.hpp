// A hexapod at rest, for the tests of robots with more feet than a filter has foot states: exact
// readings of a body 0.3 m above six feet on a circle of 0.4 m, all six feet down for the first
// `standing` samples, then alternating tripods (feet 0 2 4, then 1 3 5) every 250 samples, 1 kHz.
#pragma once

#include <cmath>
#include <vector>

#include "estimation/estimate.hpp"
#include "estimation/step_input.hpp"

namespace legkit::test {

struct Recording {
  EstimateSample x0;  // the true initial state
  std::vector<StepInput> steps;
};

inline Recording hexapodTripods(int standing, int samples) {
  Recording r;
  r.x0 = {0.0, Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 0.3)};
  for (int k = 0; k < samples; ++k) {
    StepInput in;
    in.t = 1e-3 * k;
    in.dt = k == 0 ? 0.0 : 1e-3;
    in.imu.a_m = Eigen::Vector3d(0, 0, 9.81);
    const int phase = k < standing ? -1 : (k / 250) % 2;
    for (int i = 0; i < 6; ++i) {
      if (phase >= 0 && i % 2 != phase) continue;
      const double angle = i * M_PI / 3.0;
      ContactMeasurement& c = in.contacts[in.num_contacts++];
      c.foot = i;
      c.p_body = Eigen::Vector3d(0.4 * std::cos(angle), 0.4 * std::sin(angle), -0.3);
      c.cov = 1e-6 * Eigen::Matrix3d::Identity();
      c.v_body = Eigen::Vector3d::Zero();
    }
    r.steps.push_back(in);
  }
  return r;
}

}  // namespace legkit::test
