#include "study_faults.hpp"

#include <cmath>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "estimation/contact/detectors.hpp"
#include "estimation/estimators.hpp"
#include "eval/contact_training.hpp"
#include "eval/fault_injection.hpp"
#include "eval/runner.hpp"
#include "faults_report.hpp"
#include "output.hpp"
#include "shard.hpp"
#include "sim/physics_simulator.hpp"
#include "validators.hpp"

namespace legkit::tools {

namespace {

namespace fs = std::filesystem;

constexpr double kDuration = 3.0;  // stand 0-1 s, trot from 1 s
constexpr double kOnset = 1.5;     // every fault but the drift starts here [s]

struct FaultCase {
  const char* name;
  std::function<io::Log(const io::Log&)> inject;
  bool has_answer;  // the monitor has an answer to compare against the run without it
};

// What the table shows of a monitored run (faults_report.hpp).
FaultRun summarise(const eval::MonitoredRun& r) {
  FaultRun f;
  for (int a = 0; a < engineering::kNumAlarms; ++a) {
    if (r.report.count[a] == 0) continue;
    f.alarms.emplace_back(engineering::alarmName(static_cast<engineering::Alarm>(a)),
                          r.detected_at[a]);
  }
  f.position = r.maxOver(r.position_error, 0, kDuration);
  f.attitude = r.maxOver(r.attitude_error, 0, kDuration);
  f.velocity = r.maxOver(r.velocity_error, 0, kDuration);
  f.position_sigma = r.maxOver(r.position_sigma, 0, kDuration);
  f.finite = r.finite;
  f.health = eval::describe(r.health);
  return f;
}

}  // namespace

StudyFaults::StudyFaults(CLI::App& study)
    : faults_(study.add_subcommand(
          "faults",
          "Section 57.9's faults on a 3 s physics trot: the monitor's alarms and "
          "answers (chapter 57.9's troubleshooting table)")) {
  faults_->add_option("--seed", seed_, "Seed of the physics trot")
      ->check(seedNumber())
      ->capture_default_str();
  faults_->add_option("--filter", filter_, "The estimator run on the recommended contact chain")
      ->check(CLI::IsMember(estimatorNames()))
      ->capture_default_str();
  faults_
      ->add_option("--shard", shard_,
                   "Run shard i of N (a block of the fault cases) into --out; `legkit merge` "
                   "combines the N shards into exactly the single-machine table")
      ->check(shardSpec())
      ->capture_default_str();
  faults_
      ->add_option("--out", out_dir_,
                   "A shard's output folder (default legkit-out/study-faults-shard-<i>-of-<N>); "
                   "the whole study prints its table and writes no files")
      ->check(nonEmptyName());
}

int StudyFaults::run(std::ostream& out) const {
  const Shard shard = parseShard(shard_);
  if (shard.whole() && !out_dir_.empty()) {
    throw UsageError(
        "--out: the whole study faults writes no files (it prints its table); "
        "--out is a shard's folder, with --shard i/N");
  }
  const std::vector<FaultCase> cases = {
      {"none", [](const io::Log& l) { return l; }, false},
      {"IMU rows missing 1.50-1.55 s",
       [](const io::Log& l) { return eval::dropImuRows(l, kOnset, 0.05); }, false},
      {"FR knee encoder frozen from 1.5 s",
       [](const io::Log& l) { return eval::freezeEncoder(l, 5, kOnset); }, true},
      {"FR force sensor +30 N over 1-3 s",
       [](const io::Log& l) { return eval::driftForce(l, 1, 1.0, 2.0, 30.0); }, true},
      {"every force sensor 0 N, 1.5-2.5 s",
       [](const io::Log& l) { return eval::silenceForces(l, kOnset, 1.0); }, true},
      {"accelerometer +10 g z, 1.50-1.51 s",
       [](const io::Log& l) {
         return eval::shockAccelerometer(l, kOnset, 0.01, Eigen::Vector3d(0.0, 0.0, 98.1));
       },
       false},
      {"encoders 20 ms late", [](const io::Log& l) { return eval::delayEncoders(l, 0.02); }, false},
  };
  const int total = static_cast<int>(cases.size());
  const Block block = shardBlock(shard, total, "fault cases");
  const fs::path dir = studyFolder(out_dir_, "faults", shard);
  if (!shard.whole()) makeOutputFolder(dir);  // before the runs: a bad --out fails at once

  sim::PhysicsOptions o = sim::PhysicsOptions::forScenario("physics-trot");
  o.duration = kDuration;
  o.seed = seed_;
  const io::Log log = sim::simulatePhysics(o).log;
  PipelineOptions po;  // what `legkit run` uses on physics
  po.contact = "fallback";
  po.slip = slip::SlipReaction::kInflate;
  po.settle_time = kRecommendedSettleTime;
  contact::DetectorContext context;
  context.gait = eval::plannedGait(o.scenario);
  auto monitored = [&](const io::Log& faulty, bool degrade) {
    ContactPipeline pipeline(faulty.layout, model::QuadrupedKinematics(), FrontendNoise{}, po,
                             context);
    const std::unique_ptr<Estimator> e = makeEstimator(filter_);
    eval::MonitoredRunOptions mo;
    mo.degrade = degrade;
    return eval::runMonitored(*e, faulty, pipeline, eval::initialState(faulty), mo);
  };

  std::vector<FaultCaseResult> rows;
  for (int i = block.begin; i < block.end; ++i) {
    const FaultCase& c = cases[i];
    const io::Log faulty = c.inject(log);
    FaultCaseResult& r = rows.emplace_back();
    r.name = c.name;
    r.answered = summarise(monitored(faulty, true));
    if (c.has_answer) r.without = summarise(monitored(faulty, false));
  }
  if (shard.whole()) {
    reportFaults(out, {filter_, kDuration, seed_}, rows);
    return kExitOk;
  }
  OutputFolder folder(dir, kShardManifest);
  std::vector<std::string> names;
  for (const FaultCase& c : cases) names.push_back(c.name);
  nlohmann::json manifest = shardManifest(
      "study faults",
      {{"seed", seed_}, {"filter", filter_}, {"duration", kDuration}, {"cases", names}}, shard,
      block);
  manifest["rows"] = faultRowsToJson(rows);
  folder.writeManifest(manifest);
  out << "study faults, shard " << shard.text() << ": cases " << block.begin << ".."
      << block.end - 1 << " of " << total << " in " << dir.string()
      << "/; `legkit merge OUT SHARD_DIR...` makes the study's table from all " << shard.count
      << " shards\n";
  return kExitOk;
}

}  // namespace legkit::tools
