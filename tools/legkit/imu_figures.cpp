// legkit-imu-figures: the data behind the figures of chapters 57.1 and 57.2, as CSV.
//   legkit-imu-figures [OUT_DIR]      (default: the current directory)
// writes
//   57.1-drift.csv               dead-reckoning error of a standing robot vs time, per bias case
//                                (a still IMU, and the simulator's swaying stand scenario)
//   57.2-gyro-step-error.csv     one-step error of R_{k+1} = R_k Exp(w_k dt) vs dt, per profile
//   57.2-gyro-impact.csv         one-step error vs impact severity at 400 Hz and 1 kHz
//   57.2-bias-correction.csv     preintegration bias correction error vs bias change
// and prints the drift table. Plot with tools/plots/57.1-drift.py and tools/plots/57.2-imu.py.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "estimation/imu/drift_study.hpp"
#include "estimation/imu/gyro_integration.hpp"
#include "estimation/imu/log_drift.hpp"
#include "estimation/imu/preintegration.hpp"
#include "sim/simulator.hpp"

namespace {

using Eigen::Vector3d;
using legkit::imu::RateSample;

std::ofstream openCsv(const std::string& dir, const std::string& name) {
  std::ofstream f(dir + "/" + name);
  if (!f) throw std::runtime_error("cannot write " + dir + "/" + name);
  f.precision(10);
  return f;
}

// Dead reckoning on a noiseless simulated log of the "stand" scenario (legkit::sim), whose IMU
// carries the constant bias b.
std::vector<legkit::imu::DriftSample> simulatedStandDrift(const legkit::model::ImuBias& b) {
  legkit::sim::SimOptions o;
  o.scenario = legkit::sim::scenarioByName("stand");
  o.duration = 60.001;
  o.noiseless();
  o.initial_bias = b;
  return legkit::imu::deadReckoningDriftOnLog(legkit::sim::simulate(o).log, {}, 0.1);
}

// Section 57.1: a standing robot, one bias at a time, dead reckoning that ignores the bias.
void driftFigure(const std::string& dir) {
  struct Case {
    const char* name;
    legkit::model::ImuBias bias;
    bool go2_noise;
    bool simulator = false;  // the simulator's swaying "stand" scenario instead of a still IMU
  };
  const Vector3d z = Vector3d::Zero();
  const std::vector<Case> cases = {
      {"accel_bias_0.01", {z, Vector3d(0.01, 0, 0)}, false},
      {"gyro_bias_roll_0.01", {Vector3d(0.01, 0, 0), z}, false},
      {"gyro_bias_yaw_0.01", {Vector3d(0, 0, 0.01), z}, false},
      {"accel_bias_0.01_go2_noise", {z, Vector3d(0.01, 0, 0)}, true},
      {"go2_noise_only", {z, z}, true},
      {"sim_stand_accel_bias_0.01", {z, Vector3d(0.01, 0, 0)}, false, true},
      {"sim_stand_gyro_bias_roll_0.01", {Vector3d(0.01, 0, 0), z}, false, true},
  };
  std::ofstream f = openCsv(dir, "57.1-drift.csv");
  f << "case,t,position_error,velocity_error,attitude_error_deg\n";
  std::printf("57.1 drift of a standing robot, dead reckoning at 1 kHz (measured)\n");
  std::printf("%-28s %10s %10s %10s %12s\n", "case", "t [s]", "|dp| [m]", "|dv| [m/s]",
              "dtheta [deg]");
  for (const Case& c : cases) {
    legkit::imu::StationaryDriftStudy study;
    study.bias = c.bias;
    if (c.go2_noise) study.noise = legkit::model::ImuNoise::go2();
    study.seed = 57;
    const auto drift =
        c.simulator ? simulatedStandDrift(c.bias) : legkit::imu::runStationaryDrift(study);
    for (const auto& s : drift)
      f << c.name << ',' << s.t << ',' << s.position_error << ',' << s.velocity_error << ','
        << s.attitude_error_deg << '\n';
    for (double t : {1.0, 10.0, 30.0, 60.0}) {
      const auto s = legkit::imu::driftAt(drift, t);
      std::printf("%-28s %10.0f %10.4g %10.4g %12.4g\n", c.name, s.t, s.position_error,
                  s.velocity_error, s.attitude_error_deg);
    }
  }
}

// Rate profiles of section 57.2 / exercise 57.2.3.
Vector3d impactRamp(double t) {
  return Vector3d(2.0, 5000.0 * t, 0.0);
}  // +5 rad/s per ms
Vector3d gait20Hz(double t) {
  return Vector3d(0.5, 4.0 * std::sin(2.0 * M_PI * 20.0 * t), 0.3);
}
Vector3d ring100Hz(double t) {
  return Vector3d(1.0, 0.0, 0.0) + 6.0 * std::sin(2.0 * M_PI * 100.0 * t) * Vector3d(0.0, 1.0, 1.0);
}

void gyroStepFigure(const std::string& dir) {
  std::ofstream f = openCsv(dir, "57.2-gyro-step-error.csv");
  f << "profile,dt,error_start,error_midpoint\n";
  const std::vector<std::pair<const char*, legkit::imu::RateProfile>> profiles = {
      {"impact_ramp", impactRamp}, {"gait_20Hz", gait20Hz}, {"ring_100Hz", ring100Hz}};
  std::printf("\n57.2 one-step error of R_k Exp(w_k dt) [rad]\n");
  for (const auto& [name, w] : profiles) {
    for (int i = 0; i <= 32; ++i) {
      const double dt = 1e-4 * std::pow(10.0, i / 20.0);  // 0.1 ms .. 4 ms
      // Start the step where the rate changes fastest: t0 = 0 for all three profiles.
      const double e0 = legkit::imu::gyroStepError(w, 0.0, dt, RateSample::kStart);
      const double e1 = legkit::imu::gyroStepError(w, 0.0, dt, RateSample::kMidpoint);
      f << name << ',' << dt << ',' << e0 << ',' << e1 << '\n';
    }
    for (double dt : {1e-3, 2.5e-3}) {
      std::printf("%-12s dt = %6.4f s: start sample %.3e, midpoint %.3e\n", name, dt,
                  legkit::imu::gyroStepError(w, 0.0, dt, RateSample::kStart),
                  legkit::imu::gyroStepError(w, 0.0, dt, RateSample::kMidpoint));
    }
  }
}

void gyroImpactFigure(const std::string& dir) {
  std::ofstream f = openCsv(dir, "57.2-gyro-impact.csv");
  f << "alpha,error_400Hz,error_1kHz\n";
  for (int i = 0; i <= 40; ++i) {
    const double alpha = 10.0 * std::pow(10.0, i / 10.0);  // 10 .. 1e5 rad/s^2
    const auto w = [alpha](double t) { return Vector3d(2.0, alpha * t, 0.0); };
    f << alpha << ',' << legkit::imu::gyroStepError(w, 0.0, 2.5e-3, RateSample::kStart) << ','
      << legkit::imu::gyroStepError(w, 0.0, 1e-3, RateSample::kStart) << '\n';
  }
}

// Preintegration over 0.3 s of a lively motion: first-order bias correction against
// re-integration, as the bias change shrinks.
void biasCorrectionFigure(const std::string& dir) {
  const double dt = 1e-3;
  std::vector<legkit::model::ImuReading> m(300);
  for (int k = 0; k < 300; ++k) {
    const double t = k * dt;
    m[k].w_m = Vector3d(0.3 + 1.5 * std::sin(5 * t), -0.2 + std::cos(4 * t), 0.8 * std::sin(2 * t));
    m[k].a_m = Vector3d(0.5 + 3 * std::cos(4 * t), 3 * std::sin(2 * t), 9.81 + 3 * std::sin(5 * t));
  }
  const auto integrate = [&](const legkit::model::ImuBias& b) {
    legkit::imu::Preintegrator p(b);
    for (const auto& r : m) p.integrate(r, dt);
    return p;
  };
  const auto distance = [](const legkit::imu::PreintegratedDelta& a,
                           const legkit::imu::PreintegratedDelta& b) {
    Eigen::Matrix<double, 9, 1> e;
    e << a.dR.rminus(b.dR), a.dv - b.dv, a.dp - b.dp;
    return e.norm();
  };
  const legkit::model::ImuBias b0;
  const legkit::imu::Preintegrator pre = integrate(b0);
  std::ofstream f = openCsv(dir, "57.2-bias-correction.csv");
  f << "db_norm,error_corrected,error_uncorrected\n";
  std::printf("\n57.2 bias correction over %.1f s: |db| error(corrected) error(stale)\n",
              pre.dt_ij());
  for (int i = 0; i <= 24; ++i) {
    const double s = std::pow(2.0, -i / 2.0);
    const legkit::model::ImuBias b{s * Vector3d(0.3, -0.2, 0.25), s * Vector3d(0.5, 0.4, -0.6)};
    const auto truth = integrate(b).delta();
    const double db = std::sqrt(b.b_g.squaredNorm() + b.b_a.squaredNorm());
    const double ec = distance(pre.corrected(b), truth), eu = distance(pre.delta(), truth);
    f << db << ',' << ec << ',' << eu << '\n';
    if (i % 4 == 0) std::printf("  %.4g  %.3e  %.3e\n", db, ec, eu);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : ".";
  try {
    driftFigure(dir);
    gyroStepFigure(dir);
    gyroImpactFigure(dir);
    biasCorrectionFigure(dir);
  } catch (const std::exception& e) {
    std::cerr << "legkit-imu-figures: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
