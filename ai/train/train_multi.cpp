// train_multi.cpp — the multi-task baseline (see train_multi.h).
#include "ai/train/train_multi.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "ai/env/multi_task_env.h"
#include "ai/env/skill_env.h"
#include "ai/ppo/checkpoint.h"
#include "ai/ppo/ppo_config.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"
#include "engine/loop/clock.h"

namespace ai {
namespace {

constexpr const char* kPolicyFile = "multitask.policy.bin";
constexpr const char* kSkillsFile = "skills.txt";
constexpr const char* kSkillsLog = "skills.csv";
constexpr const char* kSkillsLogHeader =
    "iteration,env_steps,skill,episodes,mean_episode_return,mean_episode_length,"
    "reward_per_step\n";

// the rows of RUN/skills.csv of iterations before `iteration` (a resumed run writes that one again)
std::string keptRows(const std::string& path, int64_t iteration) {
  std::string kept = kSkillsLogHeader;
  std::istringstream in(std::filesystem::exists(path) ? engine::readFile(path, engine::kMaxDataFileBytes) : "");
  std::string line;
  if (!in || !std::getline(in, line)) return kept;
  while (std::getline(in, line)) {
    const size_t comma = line.find(',');
    if (comma == std::string::npos) break;  // a partial last line
    if (std::atoll(line.substr(0, comma).c_str()) >= iteration) break;
    kept += line + "\n";
  }
  return kept;
}

// a skill's own rollout length: the tree's [ppo] buffer over the root skill's training envs (20480 / 20 = 1024
// steps, 10.24 s)
int rolloutSteps(const TrainingTree& tree, const PpoConfig& config) {
  for (const SkillSpec& s : tree.skills)
    if (s.parent.empty()) return std::max(1, config.bufferSize / std::max(1, s.trainingEnvs));
  return std::max(1, config.bufferSize / 20);
}

}  // namespace

const std::vector<std::string>& paperComparisonSkills() {
  static const std::vector<std::string> skills = {"walk", "run", "squat", "jump", "crawl", "one_leg"};
  return skills;
}

TrainMultiResult trainMultiTask(const TrainMultiOptions& o, const Log& logOnEveryRank,
                                const std::function<void(Trainer*)>& onTrainer) {
  // under mpirun each rank steps a share of every skill's environments; rank 0 prints and writes the run folder
  const dist::Comm& comm = dist::world();
  const Log log = comm.isRoot() ? logOnEveryRank : Log([](const std::string&) {});
  if (o.skills.empty()) throw engine::Error("multitask: no skills given");
  for (size_t i = 0; i < o.skills.size(); ++i)
    if (std::find(o.skills.begin(), o.skills.begin() + long(i), o.skills[i]) != o.skills.begin() + long(i))
      throw engine::Error("multitask: skill '" + o.skills[i] + "' is given twice");
  if (o.envsPerSkill < 1) throw engine::Error("multitask: --envs-per-skill must be at least 1");
  if (o.steps < 1) throw engine::Error("multitask: --steps must be at least 1");
  // each skill as `train SKILL` would train it: its context (tree entry, robot) and its environment
  std::vector<std::unique_ptr<SkillContext>> contexts;
  for (const std::string& name : o.skills) contexts.push_back(std::make_unique<SkillContext>(loadSkillContext(name)));
  const TrainingTree& tree = contexts.front()->tree;
  const std::string modelsDir = o.modelsDir.empty() ? tree.directory : o.modelsDir;
  PpoConfig config = parsePpoConfig(engine::readFile(tree.path), tree.path, "ppo");
  // from fresh weights the paper's linear schedule (Table 2: 3e-4 decaying), as the paper's baseline and the tree's
  // walk from scratch were trained; the tree file's adaptive rate is for branches and fine-tunes (--adaptive-rate)
  if (!o.initFrom.empty()) {
    config.learningRate = config.branchLearningRate;  // the tree's branches' start: adapt what is inherited
  } else if (o.linearRate) {
    config.adaptiveLearningRate = false;
  }
  // every environment steps as often per iteration as in a skill's own run (the tree's buffer over a skill's envs)
  const int stepsPerEnv = rolloutSteps(tree, config);
  const int envs = o.envsPerSkill * int(o.skills.size());
  config.bufferSize = stepsPerEnv * envs;
  if (config.bufferSize < config.batchSize)
    throw engine::Error("multitask: " + std::to_string(envs) + " environments x " + std::to_string(stepsPerEnv) +
                        " steps = " + std::to_string(config.bufferSize) +
                        " samples an iteration, fewer than one minibatch of " + std::to_string(config.batchSize) +
                        ": give more skills or --envs-per-skill");
  std::vector<MultiTaskEnv::Task> tasks;
  for (const auto& l : contexts) {
    log("skill '" + l->skill->name + "' (one-hot " + std::to_string(tasks.size()) +
        "): " + std::to_string(o.envsPerSkill) + " environments\n");
    SkillEnvOptions envOptions = skillEnvOptions(*l, modelsDir, o.envsPerSkill, o.threads, log);
    const dist::EnvShare share = dist::envShare(o.envsPerSkill, comm);
    envOptions.numEnvs = share.count;
    envOptions.firstEnv = share.first;
    envOptions.runEnvs = o.envsPerSkill;
    envOptions.comm = &comm;
    tasks.push_back({l->skill->name, std::make_unique<SkillEnv>(l->model, *l->skill, l->tree.path, envOptions)});
  }
  MultiTaskEnv env(std::move(tasks));

  TrainerOptions options;
  options.runDir = o.runDir;
  options.totalSteps = o.steps;
  options.seed = o.seed;
  options.resume = o.resume;
  options.updateThreads = o.threads;
  options.comm = &comm;
  const std::string skillsLog = o.runDir + "/" + kSkillsLog;
  bool firstIteration = true;
  options.onIteration = [&](const TrainerProgress& p) {
    // a resumed run drops the rows after its checkpoint, as log.csv does
    if (firstIteration && comm.isRoot()) engine::writeFileAtomic(skillsLog, keptRows(skillsLog, p.iteration));
    firstIteration = false;
    std::string rows, line;
    char buf[256];
    std::snprintf(buf, sizeof buf, "iter %lld/%lld  steps %lld  %.0f steps/s  ETA %.0f min  kl %.4f  lr %.2g\n",
                  (long long)p.iteration, (long long)p.totalIterations, (long long)p.envSteps, p.stepsPerSecond,
                  p.etaSeconds / 60.0, p.stats.approxKl, p.stats.learningRate);
    line = buf;
    std::vector<MultiTaskEnv::TaskStats> stats = env.takeTaskStats();
    if (comm.size() > 1) {  // the run's figures: every rank's episodes
      std::vector<double> sums;
      for (const auto& s : stats)
        sums.insert(sums.end(), {double(s.episodes), s.returnSum, s.lengthSum, s.rewardSum, double(s.steps)});
      comm.sum(sums.data(), sums.size());
      for (size_t k = 0; k < stats.size(); ++k) {
        const double* v = &sums[5 * k];
        stats[k] = {int(v[0]), v[1], v[2], v[3], int64_t(v[4])};
      }
    }
    for (int k = 0; k < env.taskCount(); ++k) {
      const MultiTaskEnv::TaskStats& s = stats[size_t(k)];
      const double meanReturn = s.episodes ? s.returnSum / s.episodes : std::nan("");
      const double meanLength = s.episodes ? s.lengthSum / s.episodes : std::nan("");
      const double perStep = s.steps ? s.rewardSum / double(s.steps) : std::nan("");
      std::snprintf(buf, sizeof buf, "%lld,%lld,%s,%d,%.6g,%.6g,%.6g\n", (long long)p.iteration, (long long)p.envSteps,
                    env.taskName(k).c_str(), s.episodes, meanReturn, meanLength, perStep);
      rows += buf;
      std::snprintf(buf, sizeof buf, "  %-8s return %8.1f  length %5.0f  reward/step %.3f\n", env.taskName(k).c_str(),
                    meanReturn, meanLength, perStep);
      line += buf;
    }
    if (comm.isRoot()) {
      std::ofstream out(skillsLog, std::ios::app);
      out << rows;
      if (!out) throw engine::Error(skillsLog + ": cannot append");
    }
    log(line);
  };

  Trainer trainer(env, config, options);
  if (!o.resume && !o.initFrom.empty()) {
    const PolicyState from = loadPolicyState(o.initFrom);
    if (from.observationSize() != robot::kObservationSize || from.actionSize() != robot::kActionSize)
      throw engine::Error(o.initFrom + ": a skill's policy has " + std::to_string(robot::kObservationSize) +
                          " inputs and " + std::to_string(robot::kActionSize) + " actions; this one " +
                          std::to_string(from.observationSize()) + " and " + std::to_string(from.actionSize()));
    trainer.initialiseFrom(widenedForTasks(from, env.taskCount()));
    char rate[32];
    std::snprintf(rate, sizeof rate, "%.2g", config.learningRate);
    log("initialised from " + o.initFrom + " (the one-hot's inputs at zero weight); first learning rate " + rate +
        " ([ppo] branch_learning_rate)\n");
  }
  std::string order;
  for (const std::string& s : o.skills) order += s + "\n";
  if (comm.isRoot()) {
    engine::makeDirectories(o.runDir);
    engine::writeFileAtomic(o.runDir + "/" + kSkillsFile, order);
  }
  {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "training one network on %zu skills: %lld steps in all, %d environments (%d per skill) on %d "
                  "threads%s, %d steps each per iteration, seed %llu, run folder %s\n",
                  o.skills.size(), (long long)o.steps, envs, o.envsPerSkill, o.threads,
                  comm.size() > 1 ? (" in each of " + std::to_string(comm.size()) + " ranks").c_str() : "", stepsPerEnv,
                  (unsigned long long)o.seed, o.runDir.c_str());
    log(buf);
  }
  if (onTrainer) onTrainer(&trainer);
  trainer.run();
  if (onTrainer) onTrainer(nullptr);
  if (trainer.stoppedEarly()) {
    log("stopped at iteration " + std::to_string(trainer.iteration()) + ": checkpoint " + o.runDir +
        "/checkpoint.bin, go on with --resume; nothing exported\n");
    return {o.runDir, trainer.iteration(), trainer.envSteps(), true};
  }
  if (comm.size() > 1)
    log("ranks in step: all " + std::to_string(comm.size()) + " end with policy hash " +
        engine::toHex(trainer.policyHashOnEveryRank()) + "\n");
  if (!comm.isRoot()) return {o.runDir, trainer.iteration(), trainer.envSteps(), false};
  const PolicyInfo info{ppoConfigHash(config), trainer.iteration(), trainer.envSteps(), std::nan("")};
  savePolicyState(o.runDir + "/" + kPolicyFile, trainer.policy(), info);
  log("exported " + o.runDir + "/" + kPolicyFile + " (the final policy; skills in one-hot order in " + o.runDir + "/" +
      kSkillsFile + "); its cards: treelearn eval SKILL --multitask " + o.runDir + "\n");
  return {o.runDir, trainer.iteration(), trainer.envSteps(), false};
}

PolicyState widenedForTasks(const PolicyState& policy, int taskCount) {
  PolicyState p = policy;
  for (MlpWeights* net : {&p.actor, &p.critic}) {
    Eigen::MatrixXf& w = net->W.front();
    const Eigen::Index in = w.cols();
    w.conservativeResize(Eigen::NoChange, in + taskCount);
    w.rightCols(taskCount).setZero();
  }
  p.normalizer.appendFeatures(taskCount);
  return p;
}

RewardFigures measureRewards(const SkillContext& l, const PolicyFn& act, const std::string& modelsDir, int envs,
                             int rollouts, uint64_t seed, int threads, const Log& log) {
  if (envs < 1 || rollouts < 1) throw engine::Error("measureRewards: envs and rollouts must be at least 1");
  // one episode's time limit per rollout: every episode begun at the reset ends in it (a fall, or the time limit)
  const int stepsPerEnv = int(std::lround(l.skill->termination.episodeSeconds / engine::kTickSeconds));
  SkillEnv env(l.model, *l.skill, l.tree.path, skillEnvOptions(l, modelsDir, envs, threads, log));
  RewardFigures f;
  double returns = 0, lengths = 0, rewards = 0;
  int fell = 0;
  Eigen::MatrixXf obs, actions;
  StepResult r;
  for (int k = 0; k < rollouts; ++k) {
    env.reset(seed + uint64_t(k), &obs);
    for (int t = 0; t < stepsPerEnv; ++t) {
      act(obs, &actions);
      env.step(actions, &r);
      obs = r.observations;
      rewards += double(r.rewards.sum());
      for (size_t i = 0; i < r.episodeReturns.size(); ++i) returns += r.episodeReturns[i];
      for (const int n : r.episodeLengths) lengths += n;
      f.episodes += int(r.episodeReturns.size());
      for (const uint8_t down : r.terminated) fell += down;
    }
    env.endRollout();
  }
  f.steps = int64_t(rollouts) * stepsPerEnv * envs;
  f.meanReturn = f.episodes ? returns / f.episodes : std::nan("");
  f.meanLength = f.episodes ? lengths / f.episodes : std::nan("");
  f.rewardPerStep = rewards / double(f.steps);
  f.fellShare = f.episodes ? double(fell) / f.episodes : std::nan("");
  return f;
}

int MultiTaskPolicy::indexOf(const std::string& skill, const std::string& runDir) const {
  for (size_t k = 0; k < skills.size(); ++k)
    if (skills[k] == skill) return int(k);
  std::string names;
  for (const std::string& s : skills) names += (names.empty() ? "" : ", ") + s;
  throw engine::Error(runDir + "/" + kSkillsFile + ": the multi-task run has no skill '" + skill + "' (it has " +
                      names + ")");
}

MultiTaskPolicy loadMultiTaskPolicy(const std::string& runDir) {
  MultiTaskPolicy m;
  const std::string skillsPath = runDir + "/" + kSkillsFile;
  std::istringstream in(engine::readFile(skillsPath));
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) m.skills.push_back(line);
  if (m.skills.empty()) throw engine::Error(skillsPath + ":1: no skills listed");
  const std::string policyPath = runDir + "/" + kPolicyFile;
  m.policy = loadPolicyState(policyPath);
  const int expected = robot::kObservationSize + int(m.skills.size());
  if (m.policy.observationSize() != expected || m.policy.actionSize() != robot::kActionSize)
    throw engine::Error(policyPath + ": the network takes " + std::to_string(m.policy.observationSize()) +
                        " inputs and gives " + std::to_string(m.policy.actionSize()) +
                        " actions; a multi-task run of " + std::to_string(m.skills.size()) + " skills needs " +
                        std::to_string(expected) + " and " + std::to_string(robot::kActionSize));
  return m;
}

}  // namespace ai
