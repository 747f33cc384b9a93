#include "study_fusion.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "estimation/contact_pipeline.hpp"
#include "estimation/fusion/delayed_filter.hpp"
#include "estimation/fusion/fixed_lag_smoother.hpp"
#include "estimation/fusion/map_odom.hpp"
#include "estimation/fusion/odom_history.hpp"
#include "estimation/fusion/pose_simulator.hpp"
#include "estimation/invariant/invariant_ekf.hpp"
#include "eval/contact_training.hpp"
#include "eval/metrics.hpp"
#include "eval/runner.hpp"
#include "output.hpp"
#include "shard.hpp"
#include "sim/physics_simulator.hpp"
#include "validators.hpp"

namespace legkit::tools {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr double kDefaultDuration = 330.0;  // [s]: about 160 m at 0.5 m/s, over 3 laps
constexpr double kQuickDuration = 30.0;     // [s]: the test's run, 14 m
constexpr double kSpeed = 0.5;              // forward [m/s], the physics trot's
constexpr double kRadius = 8.0;             // of the circle walked [m]: a lap of about 100 s
constexpr double kRpeDistance = 10.0;       // [m]
constexpr double kTraceRate = 10.0;         // rows of fusion-trace.csv per second
constexpr double kJumpWindow = 5.0;         // [s] either side of the loop closure

// A figure of the study's tables: "n/c" when it could not be computed.
std::string fixed(double value, int precision) {
  return std::isfinite(value) ? formatFixed(value, precision) : "n/c";
}

json number(double x) {
  return std::isfinite(x) ? json(x) : json(nullptr);
}

// The value of option `name` of `app`, or `fallback` when it was not given.
template <class T>
T optionOr(const CLI::App& app, const std::string& name, T fallback) {
  const CLI::Option* o = app.get_option(name);
  return o->count() > 0 ? o->as<T>() : fallback;
}

double yawOf(const Eigen::Quaterniond& q) {
  const Eigen::Matrix3d R = q.toRotationMatrix();
  return std::atan2(R(1, 0), R(0, 0));
}

// One way of estimating the base pose in the map frame: its name, one estimate per log row, and
// what it did with the poses.
struct Track {
  std::string name;
  std::string what;  // in words, for the table's legend
  eval::Trajectory x;
  int poses_used = 0, poses_rejected = 0;
};

// The scores of one track against the truth.
struct Scores {
  eval::Metrics m;
  double final_yaw_deg = NAN;  // yaw error at the last row [deg]
  double corridor_rmse = NAN;  // position RMSE inside the corridor stretch [m]
  double jump_max = NAN;       // largest position error within kJumpWindow of the jump [m]
  double jump_step = NAN;      // largest change of the estimate from one row to the next
                               // within kJumpWindow of the jump, beyond the truth's [m]
};

// When the exteroceptive poses misbehave (fusion::simulatePoses' events), [s].
struct Events {
  double corridor_start = NAN, corridor_end = NAN;
  double loop_closure = NAN;
};

Scores score(const io::Log& log, const Track& track, const Events& events, double rpe_distance) {
  Scores s;
  s.m = eval::compare(log, track.x, {rpe_distance});
  const io::LogRow& last = log.rows.back();
  s.final_yaw_deg =
      kRadToDeg * eval::yawError(track.x.back().q.toRotationMatrix(), last.gt_q.toRotationMatrix());
  double sum = 0.0, jump_max = 0.0, jump_step = 0.0;
  int n = 0;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const double t = log.rows[k].t;
    const double e = (track.x[k].p - log.rows[k].gt_p).norm();
    if (t >= events.corridor_start && t <= events.corridor_end) {
      sum += e * e;
      ++n;
    }
    if (std::abs(t - events.loop_closure) <= kJumpWindow) {
      jump_max = std::max(jump_max, e);
      if (k > 0) {
        const Eigen::Vector3d step = track.x[k].p - track.x[k - 1].p;
        const Eigen::Vector3d truth = log.rows[k].gt_p - log.rows[k - 1].gt_p;
        jump_step = std::max(jump_step, (step - truth).norm());
      }
    }
  }
  if (n > 0) s.corridor_rmse = std::sqrt(sum / n);
  if (std::isfinite(events.loop_closure)) {
    s.jump_max = jump_max;
    s.jump_step = jump_step;
  }
  return s;
}

// The physics trot on a circle of radius kRadius, left turn.
sim::PhysicsOptions circleTrot(double duration, unsigned seed) {
  sim::PhysicsOptions o = sim::PhysicsOptions::forScenario("physics-trot");
  o.scenario.name = "physics-trot-circle";
  o.scenario.velocity = {kSpeed, 0.0};
  o.scenario.yaw_rate = kSpeed / kRadius;
  o.duration = duration;
  o.seed = seed;
  return o;
}

// The simulated SLAM's events: the corridor over [0.35, 0.5] of the run, the loop closure when
// the robot is back at its start after the last whole lap before 0.8 of the run (0.7 of a run
// shorter than a lap).
fusion::PoseSimulatorOptions poseOptions(double duration) {
  fusion::PoseSimulatorOptions o;
  o.corridor_start = 0.35 * duration;
  o.corridor_end = 0.5 * duration;
  const double start = 1.5;  // stand 1 s, then the ramp to full speed over 1 s: half of it
  const double lap = 2.0 * M_PI * kRadius / kSpeed;
  const double laps = std::floor((0.8 * duration - start) / lap);
  o.loop_closure_time = laps >= 1.0 ? start + laps * lap : 0.7 * duration;
  return o;
}

// The (dtheta, dp) block of a filter's (dtheta, dv, dp) covariance: the odometry pose's.
fusion::Matrix6d poseCovariance(const BaseCovariance& P) {
  fusion::Matrix6d C;
  C << P.P.block<3, 3>(0, 0), P.P.block<3, 3>(0, 6), P.P.block<3, 3>(6, 0), P.P.block<3, 3>(6, 6);
  return C;
}

// fusion-poses.csv: the simulated poses as they were stamped, with their reported sigmas and the
// map's drift at each.
std::string posesCsv(const fusion::SimulatedPoses& simulated) {
  std::ostringstream csv;
  csv << std::setprecision(7)
      << "t,t_arrival,x,y,z,yaw,sigma_x,sigma_y,valid,drift_x,drift_y,drift_yaw,in_corridor\n";
  for (std::size_t i = 0; i < simulated.poses.size(); ++i) {
    const fusion::PoseMeasurement& z = simulated.poses[i];
    const fusion::MapDrift& d = simulated.drift[i];
    csv << z.t << ',' << z.t_arrival << ',' << z.p_MB.x() << ',' << z.p_MB.y() << ',' << z.p_MB.z()
        << ',' << yawOf(z.R_MB.quaternion()) << ',' << std::sqrt(z.cov(3, 3)) << ','
        << std::sqrt(z.cov(4, 4)) << ',' << z.valid << ',' << d.p.x() << ',' << d.p.y() << ','
        << d.yaw << ',' << d.in_corridor << '\n';
  }
  return csv.str();
}

// fusion-trace.csv: the truth and every track at kTraceRate.
std::string traceCsv(const io::Log& log, const std::vector<Track>& tracks) {
  std::ostringstream csv;
  csv << std::setprecision(7) << "t,gt_x,gt_y,gt_yaw";
  for (const Track& tr : tracks) {
    csv << ',' << tr.name << "_x," << tr.name << "_y," << tr.name << "_err," << tr.name
        << "_yaw_err_deg";
  }
  csv << '\n';
  double next = log.rows.front().t;
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const io::LogRow& row = log.rows[k];
    if (row.t < next) continue;
    next += 1.0 / kTraceRate;
    csv << row.t << ',' << row.gt_p.x() << ',' << row.gt_p.y() << ',' << yawOf(row.gt_q);
    for (const Track& tr : tracks) {
      const EstimateSample& x = tr.x[k];
      csv << ',' << x.p.x() << ',' << x.p.y() << ',' << (x.p - row.gt_p).norm() << ','
          << kRadToDeg * eval::yawError(x.q.toRotationMatrix(), row.gt_q.toRotationMatrix());
    }
    csv << '\n';
  }
  return csv.str();
}

}  // namespace

CLI::App* addStudyFusion(CLI::App& study) {
  CLI::App* c = study.add_subcommand(
      "fusion",
      "Proprioception alone against exteroceptive fusion on a long physics trot around a circle "
      "with simulated SLAM poses (section 57.8)");
  c->add_option("--duration", "Simulated time [s] (default 330: about 160 m; --quick: 30)")
      ->check(finiteRange(5.0, kMaxSimulatedSeconds));
  c->add_option("--seed", "Seed of the physics run and of the poses (default 1)")
      ->check(seedNumber());
  c->add_option("--out", "Output folder (default legkit-out/study-fusion)")->check(nonEmptyName());
  c->add_flag("--quick", "A 30 s run (the test's)");
  c->add_flag("--no-plots", "Do not draw the figures");
  // Accepted so that every study has the option, refused past 1/1 (runStudyFusion says why).
  c->add_option("--shard", "Not shardable: one physics run that every coupling rides on (only 1/1)")
      ->check(shardSpec());
  return c;
}

int runStudyFusion(const CLI::App& fusion, std::ostream& out) {
  const bool quick = fusion.get_option("--quick")->count() > 0;
  const double duration = optionOr(fusion, "--duration", quick ? kQuickDuration : kDefaultDuration);
  const unsigned seed = optionOr(fusion, "--seed", 1u);
  const fs::path dir = optionOr<std::string>(fusion, "--out", "legkit-out/study-fusion");
  const bool plots = fusion.get_option("--no-plots")->count() == 0;
  // One run, no items to split: the four couplings ride on the same simulation and on the
  // proprioceptive InEKF, whose estimate feeds the contact chain every coupling's inputs come
  // from. A shard per coupling would repeat the simulation (about half the study's time: 2.0 of
  // 3.8 s for --quick) and that filter in every shard; seeds are not the study's items (it is
  // one seed's run).
  if (const Shard shard = parseShard(optionOr<std::string>(fusion, "--shard", "1/1"));
      !shard.whole()) {
    throw UsageError("--shard " + shard.text() +
                     ": study fusion is one physics run, not a set of runs: its four couplings "
                     "all ride on the same simulation and the same InEKF's contact chain, so "
                     "there is nothing to split (run it whole; --shard 1/1 is the whole study)");
  }
  makeOutputFolder(dir);  // before the run: a bad --out fails at once

  const auto wall_start = std::chrono::steady_clock::now();
  const sim::PhysicsOptions physics = circleTrot(duration, seed);
  const sim::PhysicsResult sim = sim::simulatePhysics(physics);
  if (sim.status.fell) {
    std::cerr << "legkit study fusion: the physics run failed at t = " << sim.status.time
              << " s: " << sim.status.reason << "\n";
    return kExitUnhealthy;
  }
  const io::Log& log = sim.log;
  const double sim_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  // The contact chain `legkit run` uses on physics (study faults does the same).
  PipelineOptions po;
  po.contact = "fallback";
  po.slip = slip::SlipReaction::kInflate;
  po.settle_time = kRecommendedSettleTime;
  contact::DetectorContext context;
  context.gait = eval::plannedGait(physics.scenario);
  ContactPipeline pipeline(log.layout, model::QuadrupedKinematics(), FrontendNoise{}, po, context);

  const fusion::PoseSimulatorOptions pose_options = poseOptions(duration);
  const fusion::SimulatedPoses simulated = fusion::simulatePoses(log, pose_options, seed);
  const std::vector<fusion::PoseMeasurement>& poses = simulated.poses;

  const EstimateSample x0 = eval::initialState(log);
  invariant::InvariantEkf proprio;
  proprio.reset(x0);
  // Loose coupling: the odometry's poses by time (1.0 s at 1 kHz, the poses are 80 ms late) and
  // T_MO with the alignment's default options.
  fusion::OdomHistory history(1024);
  fusion::MapOdomAlignment alignment;
  std::size_t next_loose = 0;  // the next pose to reach the loose coupling
  // Pose injection: a second InEKF whose world is the map, each pose applied at its stamp and the
  // inputs since re-run (DelayedFilter, 0.5 s of history).
  fusion::DelayedFilter<invariant::InvariantEkf> injection{invariant::InvariantEkf{}};
  injection.reset(x0);
  std::size_t next_injected = 0;
  // The fixed-lag smoother (default options: keyframes every 0.1 s, 2 s window, leg-velocity
  // bias), its poses attached at their stamps.
  fusion::FixedLagSmoother smoother;
  smoother.initialise(InitialState{x0});
  std::size_t next_smoothed = 0;
  std::vector<Track> tracks = {
      {"proprio", "the InEKF alone (default parameters, fallback contacts)", {}, 0, 0},
      {"loose",
       "T_MO T_OB, T_MO from MapOdomAlignment (default options) on the InEKF's odometry",
       {},
       0,
       0},
      {"injection",
       "the poses as updates of a second InEKF, applied at their stamps (DelayedFilter)",
       {},
       0,
       0},
      {"smoother",
       "the fixed-lag smoother (2 s window, keyframes every 0.1 s, leg-velocity bias)",
       {},
       0,
       0}};
  for (Track& tr : tracks) tr.x.reserve(log.rows.size());

  const auto run_start = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    const io::LogRow& row = log.rows[k];
    const double dt = k == 0 ? 0.0 : row.t - log.rows[k - 1].t;
    const StepInput& in = pipeline.step(row, dt, proprio.estimate(), proprio.covariance());
    proprio.step(in);
    const EstimateSample odom = proprio.estimate();
    tracks[0].x.push_back(odom);

    const lie::SO3d R_OB = lie::SO3d::fromQuaternion(odom.q);
    history.push({row.t, R_OB, odom.p, poseCovariance(*proprio.covariance())});
    for (; next_loose < poses.size() && poses[next_loose].t_arrival <= row.t; ++next_loose) {
      alignment.update(poses[next_loose], history);
    }
    const fusion::MapPose map = alignment.mapPose(R_OB, odom.p);
    tracks[1].x.push_back(
        {row.t, map.R_MB.quaternion(), alignment.R_MO().matrix() * odom.v, map.p_MB});

    injection.step(in);
    for (; next_injected < poses.size() && poses[next_injected].t_arrival <= row.t;
         ++next_injected) {
      injection.updatePose(poses[next_injected]);
    }
    tracks[2].x.push_back(injection.estimate());

    smoother.addStep(in);
    for (; next_smoothed < poses.size() && poses[next_smoothed].t_arrival <= row.t;
         ++next_smoothed) {
      smoother.addPose(poses[next_smoothed]);
    }
    tracks[3].x.push_back(smoother.estimate());
  }
  const double run_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start).count();

  const fusion::MapOdomAlignment::Counts& loose_counts = alignment.counts();
  tracks[1].poses_used = loose_counts.initialised + loose_counts.used + loose_counts.jump_updates;
  tracks[1].poses_rejected = loose_counts.rejected();
  tracks[2].poses_used = static_cast<int>(injection.stats().used);
  tracks[2].poses_rejected = static_cast<int>(injection.stats().rejections());
  tracks[3].poses_used = smoother.stats().poses_used;
  tracks[3].poses_rejected = smoother.stats().poses_rejected + smoother.stats().poses_invalid;

  const Events events{pose_options.corridor_start, pose_options.corridor_end,
                      pose_options.loop_closure_time};
  std::vector<Scores> scores;
  scores.reserve(tracks.size());
  for (const Track& tr : tracks) scores.push_back(score(log, tr, events, kRpeDistance));

  const eval::Metrics& m0 = scores.front().m;
  out << "Exteroceptive fusion on the physics trot around a circle of " << kRadius << " m ("
      << kSpeed << " m/s, " << duration << " s, " << fixed(m0.distance, 1) << " m walked, seed "
      << seed << "); simulated in " << fixed(sim_seconds, 1) << " s, estimated in "
      << fixed(run_seconds, 1) << " s\n\n";
  std::vector<std::vector<std::string>> table = {
      {"coupling", "ATE [m]", "RPE 10 m [%]", "RPE 10 m [deg]", "yaw at end [deg]",
       "yaw RMSE [deg]", "corridor RMSE [m]", "max err near jump [m]", "poses used/rejected"}};
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    const Scores& s = scores[i];
    const eval::RelativeError& rpe = s.m.rpe.front();
    table.push_back(
        {tracks[i].name, fixed(s.m.ate_rmse, 3), fixed(rpe.translation_percent, 2),
         fixed(rpe.rotation_rmse_deg, 2), fixed(s.final_yaw_deg, 2), fixed(s.m.yaw_rmse_deg, 2),
         fixed(s.corridor_rmse, 3), fixed(s.jump_max, 3),
         std::to_string(tracks[i].poses_used) + "/" + std::to_string(tracks[i].poses_rejected)});
  }
  printTable(out, table);
  out << '\n';
  for (const Track& tr : tracks) out << tr.name << ": " << tr.what << '\n';

  json summary = {{"duration_s", duration},
                  {"seed", seed},
                  {"radius_m", kRadius},
                  {"speed_mps", kSpeed},
                  {"distance_m", number(m0.distance)},
                  {"rpe_distance_m", kRpeDistance},
                  {"loop_closure_s", number(events.loop_closure)},
                  {"corridor_s", {number(events.corridor_start), number(events.corridor_end)}}};
  json all = json::array();
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    const Scores& s = scores[i];
    const eval::RelativeError& rpe = s.m.rpe.front();
    all.push_back({{"name", tracks[i].name},
                   {"what", tracks[i].what},
                   {"ate_m", number(s.m.ate_rmse)},
                   {"position_rmse_m", number(s.m.position_rmse)},
                   {"rpe_percent", number(rpe.translation_percent)},
                   {"rpe_deg", number(rpe.rotation_rmse_deg)},
                   {"final_yaw_error_deg", number(s.final_yaw_deg)},
                   {"yaw_rmse_deg", number(s.m.yaw_rmse_deg)},
                   {"corridor_rmse_m", number(s.corridor_rmse)},
                   {"jump_max_error_m", number(s.jump_max)},
                   {"jump_max_step_m", number(s.jump_step)},
                   {"poses_used", tracks[i].poses_used},
                   {"poses_rejected", tracks[i].poses_rejected}});
  }
  summary["couplings"] = all;
  writeAtomically(dir / "fusion-poses.csv", [&](std::ostream& f) { f << posesCsv(simulated); });
  writeAtomically(dir / "fusion-trace.csv", [&](std::ostream& f) { f << traceCsv(log, tracks); });
  writeAtomically(dir / "summary.json", [&](std::ostream& f) { f << summary.dump(2) << '\n'; });
  out << "tables: " << (dir / "fusion-trace.csv").string() << ", "
      << (dir / "fusion-poses.csv").string() << ", " << (dir / "summary.json").string() << '\n';
  if (plots) {
    const std::string failed = plot("57.8-fusion.py", {dir.string()});
    out << (failed.empty() ? "figures: " + (dir / "57.8-fusion-path.png").string() + ", " +
                                 (dir / "57.8-fusion-error.png").string()
                           : failed)
        << '\n';
    if (plotFailed(failed)) return kExitInput;
  }
  return 0;
}

}  // namespace legkit::tools
