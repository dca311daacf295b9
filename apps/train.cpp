// train.cpp — `treelearn train SKILL` and `treelearn eval SKILL`: wires the skill tree, the training
// environment, the PPO trainer, the report card and the ONNX export together. Prints progress; files
// are written atomically by the layers below.
#include <csignal>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "ai/env/skill_env.h"
#include "ai/eval/walk_card.h"
#include "ai/onnx/policy_onnx.h"
#include "ai/ppo/checkpoint.h"
#include "ai/ppo/ppo_config.h"
#include "ai/ppo/trainer.h"
#include "apps/commands.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"
#include "engine/loop/clock.h"
#include "robot/skill_layout.h"

namespace apps {
namespace {

ai::Trainer* gTrainer = nullptr;  // apps/ only: lets Ctrl-C stop training cleanly with a checkpoint

void onSigint(int) {
  if (gTrainer) gTrainer->requestStop();
}

std::string joinNumbers(const double* v, size_t n) {
  std::ostringstream s;
  s.precision(9);
  for (size_t i = 0; i < n; ++i) s << (i ? "," : "") << v[i];
  return s.str();
}

// DESIGN.md §3: the metadata every skill file carries
std::vector<std::pair<std::string, std::string>> skillMetadata(const robot::RobotModel& model,
                                                                const robot::SkillDef& skill, int64_t envSteps,
                                                                uint64_t seed) {
  std::string joints;
  robot::JointArray defaults{};
  for (size_t j = 0; j < size_t(robot::kNumJoints); ++j) {
    joints += (j ? "," : "") + model.joints[j].name;
    defaults[j] = model.joints[j].defaultPosition;
  }
  const char* prior = skill.prior.kind == robot::PriorDef::Kind::Phase ? "phase" : "none";
  return {
      {"treelearn.skill", skill.name},
      {"treelearn.parent", skill.parent},
      {"treelearn.key", std::to_string(skill.key)},
      {"treelearn.layout_version", std::to_string(robot::kLayoutVersion)},
      {"treelearn.observation_size", std::to_string(robot::kObservationSize)},
      {"treelearn.action_size", std::to_string(robot::kActionSize)},
      {"treelearn.joint_order", joints},
      {"treelearn.default_pose", joinNumbers(defaults.data(), defaults.size())},
      {"treelearn.action_scale", joinNumbers(skill.actionScale.data(), skill.actionScale.size())},
      {"treelearn.action_clip", std::to_string(robot::kActionClip)},
      {"treelearn.kp", joinNumbers(skill.kp.data(), skill.kp.size())},
      {"treelearn.kd", joinNumbers(skill.kd.data(), skill.kd.size())},
      {"treelearn.control_rate_hz", "100"},
      {"treelearn.physics_substep_s", "0.002"},
      {"treelearn.prior", std::string(prior) + " T1=" + std::to_string(skill.prior.halfPeriodTicks) +
                              " dh=" + std::to_string(skill.prior.dh) + " d0=" + std::to_string(skill.prior.d0) +
                              " stand_still=" + (skill.prior.standStill ? "true" : "false")},
      {"treelearn.robot_hash", engine::toHex(model.hash)},
      {"treelearn.env_steps", std::to_string(envSteps)},
      {"treelearn.seed", std::to_string(seed)},
  };
}

struct Loaded {
  robot::RobotModel model;
  robot::SkillTree tree;
  const robot::SkillDef* skill = nullptr;
};

Loaded loadSkill(const std::string& name) {
  Loaded l;
  l.model = robot::loadRobotModel(robot::defaultRobotConfigPath());
  l.tree = robot::loadSkillTree(robot::defaultSkillTreePath(), l.model);
  l.skill = l.tree.find(name);
  if (!l.skill) {
    std::string names;
    for (const auto& s : l.tree.skills) names += (names.empty() ? "" : ", ") + s.name;
    throw engine::Error("unknown skill '" + name + "' (the tree at " + l.tree.path + " has: " + names + ")");
  }
  return l;
}

void printCard(const ai::CardResult& card) {
  for (const ai::CardFigure& f : card.figures)
    if (f.bar[0] == '(')
      std::printf("  %-36s %10.3f   %s\n", f.name.c_str(), f.value, f.bar.c_str());
    else
      std::printf("  %-36s %10.3f   bar %-14s %s\n", f.name.c_str(), f.value, f.bar.c_str(), f.pass ? "PASS" : "FAIL");
  std::printf("  %s\n", card.pass ? "CARD PASSED" : "CARD FAILED");
}

}  // namespace

int runTrain(const TrainOptions& o) {
  const Loaded l = loadSkill(o.skill);
  const robot::SkillDef& skill = *l.skill;
  ai::PpoConfig config = ai::parsePpoConfig(engine::readFile(l.tree.path), l.tree.path, "ppo");
  const int64_t steps = o.steps > 0 ? o.steps : skill.trainingSteps;
  const int envs = o.envs > 0 ? o.envs : skill.trainingEnvs;
  const std::string runDir = o.runDir.empty() ? "runs/" + skill.name : o.runDir;
  const std::string modelsDir = o.modelsDir.empty() ? l.tree.directory : o.modelsDir;
  const std::string onnxPath = modelsDir + "/" + skill.model;
  const std::string policyPath = modelsDir + "/" + skill.name + ".policy.bin";
  if (config.bufferSize % envs != 0)
    throw engine::Error("--envs " + std::to_string(envs) + " must divide the PPO buffer size " + std::to_string(config.bufferSize));

  ai::SkillEnv env(l.model, skill, l.tree.path, {envs, o.threads, true});
  ai::TrainerOptions options;
  options.runDir = runDir;
  options.totalSteps = steps;
  options.seed = o.seed;
  options.resume = o.resume;
  options.evalEvery = std::max(1, o.evalEvery);
  if (skill.name == "walk" && o.evalEvery > 0) {
    options.evaluate = [&](const ai::PolicyState& p) {
      ai::WalkCardOptions card;
      card.episodes = 10;
      card.standEpisodes = 4;
      card.seed = 1000 + o.seed;  // fixed, so resumed runs score identically
      card.threads = o.threads;
      const ai::CardResult r = ai::runWalkCard(
          l.model, skill, [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) { ai::actDeterministic(p, obs, act); },
          card);
      std::printf("  eval: ");
      for (const auto& f : r.figures) std::printf("%s %.3f  ", f.name.c_str(), f.value);
      std::printf("-> score %.3f\n", r.score);
      return r.score;
    };
  }
  options.onIteration = [&](const ai::TrainerProgress& p) {
    std::printf("iter %lld/%lld  steps %lld  %.0f steps/s  ETA %.0f min  reward/step %.3f  episode return %.1f  length %.0f"
                "  kl %.4f  clip %.3f  ev %.2f\n",
                (long long)p.iteration, (long long)p.totalIterations, (long long)p.envSteps, p.stepsPerSecond,
                p.etaSeconds / 60.0, p.meanReward, p.meanEpisodeReturn, p.meanEpisodeLength, p.stats.approxKl,
                p.stats.clipFraction, p.stats.explainedVariance);
    std::fflush(stdout);
  };

  ai::Trainer trainer(env, config, options);
  if (!o.resume && !o.initFrom.empty()) {
    trainer.initialiseFrom(ai::loadPolicyState(o.initFrom), float(o.reinflateLogStd));
    std::printf("initialised from %s (fine-tuning: fresh optimiser and schedules)\n", o.initFrom.c_str());
  } else if (!o.resume && !skill.parent.empty()) {
    const robot::SkillDef* parent = l.tree.find(skill.parent);
    const std::string parentPolicy = l.tree.directory + "/" + parent->name + ".policy.bin";
    trainer.initialiseFrom(ai::loadPolicyState(parentPolicy), float(o.reinflateLogStd));
    std::printf("initialised from parent '%s' (%s)\n", parent->name.c_str(), parentPolicy.c_str());
  }
  std::printf("training %s: %lld steps, %d envs on %d threads, seed %llu, run folder %s\n", skill.name.c_str(),
              (long long)steps, envs, o.threads, (unsigned long long)o.seed, runDir.c_str());
  gTrainer = &trainer;
  std::signal(SIGINT, onSigint);
  trainer.run();
  gTrainer = nullptr;

  // export the best-by-evaluation policy if there is one, else the final one
  ai::PolicyInfo info;
  ai::PolicyState chosen = trainer.policy();
  const std::string best = runDir + "/best.bin";
  if (std::filesystem::exists(best)) chosen = ai::loadPolicyState(best, &info);
  exportSkill(l.model, skill, chosen, onnxPath, policyPath, trainer.envSteps(), o.seed);
  std::printf("exported %s and %s (%s policy)\n", onnxPath.c_str(), policyPath.c_str(),
              std::filesystem::exists(best) ? "best-by-evaluation" : "final");
  return 0;
}

void exportSkill(const robot::RobotModel& model, const robot::SkillDef& skill, const ai::PolicyState& policy,
                 const std::string& onnxPath, const std::string& policyPath, int64_t envSteps, uint64_t seed) {
  ai::PolicyExport e;
  e.actor = policy.actor;
  e.obsMean = policy.normalizer.mean();
  e.obsStd = policy.normalizer.stddev();
  e.obsClip = policy.normalizer.clip();
  e.metadata = skillMetadata(model, skill, envSteps, seed);
  ai::savePolicyOnnx(onnxPath, e);
  ai::savePolicyState(policyPath, policy);
}

int runExport(const TrainOptions& o) {
  const Loaded l = loadSkill(o.skill);
  const std::string runDir = o.runDir.empty() ? "runs/" + o.skill : o.runDir;
  ai::PolicyState p;
  ai::PolicyInfo info;
  std::string source;
  if (o.exportFrom == "last") {
    source = runDir + "/checkpoint.bin";
    const ai::TrainerCheckpoint c = ai::loadCheckpoint(source);
    p = c.policy;
    info.iteration = c.iteration;
    info.envSteps = c.envSteps;
  } else {
    source = runDir + "/best.bin";
    if (!std::filesystem::exists(source)) throw engine::Error(source + ": no evaluated policy to export yet");
    p = ai::loadPolicyState(source, &info);
  }
  const std::string modelsDir = o.modelsDir.empty() ? l.tree.directory : o.modelsDir;
  exportSkill(l.model, *l.skill, p, modelsDir + "/" + l.skill->model, modelsDir + "/" + l.skill->name + ".policy.bin",
              info.envSteps, o.seed);
  std::printf("exported %s from %s (iteration %lld, %lld env steps)\n", l.skill->model.c_str(), source.c_str(),
              (long long)info.iteration, (long long)info.envSteps);
  return 0;
}

int runEval(const EvalOptions& o) {
  const Loaded l = loadSkill(o.skill);
  if (o.skill != "walk") throw engine::Error("eval: only the walk card exists so far");
  const std::string onnxPath = o.model.empty() ? l.tree.directory + "/" + l.skill->model : o.model;
  const ai::LoadedPolicy policy = ai::loadPolicyOnnx(onnxPath);
  if (policy.observationSize() != robot::kObservationSize || policy.actionSize() != robot::kActionSize)
    throw engine::Error(onnxPath + ": network sizes do not match the shared layout");
  ai::WalkCardOptions card;
  card.episodes = o.episodes;
  card.seed = o.seed;
  card.threads = o.threads;
  std::printf("walk report card: %d episodes x %.0f s on flat ground with pushes, commands every %.0f s; "
              "%d standing episodes x %.0f s (model %s, hash %s)\n",
              card.episodes, card.episodeSeconds, card.segmentSeconds, card.standEpisodes, card.standSeconds,
              onnxPath.c_str(), engine::toHex(ai::onnxFileHash(onnxPath)).c_str());
  const ai::CardResult r = ai::runWalkCard(
      l.model, *l.skill, [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) { policy.act(obs, act); }, card);
  printCard(r);
  return r.pass ? 0 : 1;
}

}  // namespace apps
