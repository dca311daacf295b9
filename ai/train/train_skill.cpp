// train_skill.cpp — training a skill in-process (see train_skill.h).
#include "ai/train/train_skill.h"

#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>

#include "ai/env/skill_env.h"
#include "ai/onnx/policy_onnx.h"
#include "ai/onnx/skill_metadata.h"
#include "ai/ppo/gaussian.h"
#include "ai/ppo/ppo_config.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"

namespace ai {
namespace {

std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  char small[512];
  va_list again;
  va_copy(again, args);
  const int n = std::vsnprintf(small, sizeof small, fmt, args);
  va_end(args);
  std::string out;
  if (n < int(sizeof small)) {
    out = small;
  } else {
    out.resize(size_t(n) + 1);
    std::vsnprintf(out.data(), out.size(), fmt, again);
    out.resize(size_t(n));
  }
  va_end(again);
  return out;
}

// a formatted line into the log
void say(const Log& log, const char* fmt, ...) __attribute__((format(printf, 2, 3)));
void say(const Log& log, const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  char line[1024];
  std::vsnprintf(line, sizeof line, fmt, args);
  va_end(args);
  log(line);
}

}  // namespace

SkillEnvOptions skillEnvOptions(const SkillContext& l, const std::string& modelsDir, int envs, int threads,
                                const Log& log) {
  const SkillSpec& skill = *l.skill;
  SkillEnvOptions envOptions;
  envOptions.numEnvs = envs;
  envOptions.threads = threads;
  std::shared_ptr<LoadedPolicy> handoverPolicy;
  if (skill.handover > 0) {  // episodes that start under the parent's (or handover_from's) shipped model
    const SkillSpec* parent = l.tree.find(skill.handoverFrom.empty() ? skill.parent : skill.handoverFrom);
    const std::string path = modelsDir + "/" + parent->model;
    if (!std::filesystem::exists(path))
      throw engine::Error(path + ": the parent skill '" + parent->name +
                          "' has no model yet (handover episodes start under it): train " + parent->name + " first");
    handoverPolicy = std::make_shared<LoadedPolicy>(loadPolicyOnnx(path));
    envOptions.parent = parent;
    envOptions.parentPolicy = [handoverPolicy](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) {
      handoverPolicy->act(obs, act);
    };
    say(log, "handover episodes: %.0f %% start under '%s' (%s) for %.1f-%.1f s\n", 100 * skill.handover,
        parent->name.c_str(), path.c_str(), skill.handoverSeconds.lo, skill.handoverSeconds.hi);
    // the skills between handover_from and this one, which a routed request passes through in play
    const std::vector<const SkillSpec*> route = handoverRoute(l.tree, skill);
    for (auto it = route.begin() + 1; it != route.end(); ++it) {
      const SkillSpec* v = *it;
      const std::string vpath = modelsDir + "/" + v->model;
      if (!std::filesystem::exists(vpath))
        throw engine::Error(vpath + ": the skill '" + v->name +
                            "' has no model yet (handover episodes route through it): train " + v->name + " first");
      auto policy = std::make_shared<LoadedPolicy>(loadPolicyOnnx(vpath));
      envOptions.via.push_back(
          {v, [policy](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) { policy->act(obs, act); }});
      say(log, "  then '%s' (%s) for %.1f-%.1f s at a zero command\n", v->name.c_str(), vpath.c_str(),
          skill.handoverViaSeconds.lo, skill.handoverViaSeconds.hi);
    }
  }
  if (skill.playShare > 0)
    say(log, "play episodes: %.0f %% start from play's handover states (%s/%s)%s\n", 100 * skill.playShare,
        l.tree.directory.c_str(), skill.playEntries.c_str(),
        skill.handover + skill.handoverBack > 0 ? "; the handover shares above are of the other episodes" : "");
  std::shared_ptr<LoadedPolicy> backPolicy;
  if (skill.handoverBack > 0) {  // episodes that start under a child's shipped model (the way back up the tree)
    const SkillSpec* child = l.tree.find(skill.handoverBackFrom);
    const std::string path = modelsDir + "/" + child->model;
    if (!std::filesystem::exists(path))
      throw engine::Error(path + ": the skill '" + child->name +
                          "' has no model yet (handover_back episodes start under it): train " + child->name +
                          " first, or set handover_back = 0");
    backPolicy = std::make_shared<LoadedPolicy>(loadPolicyOnnx(path));
    envOptions.back = {child,
                       [backPolicy](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) { backPolicy->act(obs, act); }};
    say(log, "handover episodes back up the tree: %.0f %% start under '%s' (%s) for %.1f-%.1f s, then switch to '%s'\n",
        100 * skill.handoverBack, child->name.c_str(), path.c_str(), skill.handoverBackSeconds.lo,
        skill.handoverBackSeconds.hi, skill.name.c_str());
  }
  return envOptions;
}

TrainSkillResult trainSkill(const SkillContext& l, const TrainSkillOptions& o, const Log& logOnEveryRank,
                            const std::function<void(Trainer*)>& onTrainer) {
  const SkillSpec& skill = *l.skill;
  // under mpirun each rank steps a share of the environments; rank 0 prints, writes the run folder and exports
  const dist::Comm& comm = dist::world();
  const Log log = comm.isRoot() ? logOnEveryRank : Log([](const std::string&) {});
  const std::string treeText = engine::readFile(l.tree.path);
  // [ppo], then the skill's own [skill.NAME.ppo] overrides (not inherited by its branches)
  PpoConfig config = parsePpoConfig(treeText, l.tree.path, "ppo");
  config = parsePpoConfig(treeText, l.tree.path, "skill." + skill.name + ".ppo", config);
  // a branch from its parent's weights starts at [ppo] branch_learning_rate, so that its first updates adapt the
  // inherited policy rather than overwrite it (a resumed branch run keeps the config it began with)
  const bool fromParent = (!skill.parent.empty() && o.initFrom.empty()) || (o.initAsBranch && !o.initFrom.empty());
  if (!std::isnan(o.learningRate)) {
    if (!(o.learningRate > 0 && o.learningRate < 1)) throw engine::Error("--learning-rate must be in (0, 1)");
    config.learningRate = o.learningRate;  // decays linearly to the config's final rate, as usual
  } else if (fromParent) {
    config.learningRate = config.branchLearningRate;
  }
  if (o.linearRate) config.adaptiveLearningRate = false;
  if (o.zeroOutput && (o.resume || !o.initFrom.empty() || skill.parent.empty()))
    throw engine::Error(
        "--zero-output is a branch's initialisation from its parent: not with --resume, --init-from or for the root "
        "skill");
  if (!std::isnan(o.initLogStd) && (o.resume || (o.initFrom.empty() && skill.parent.empty())))
    throw engine::Error(
        "--init-log-std sets the starting noise of a branch (from its parent) or of a fine-tune (--init-from): "
        "not with --resume or for the root skill trained afresh");
  const int64_t steps = o.steps > 0 ? o.steps : skill.trainingSteps;
  const int envs = o.envs > 0 ? o.envs : skill.trainingEnvs;
  const std::string runDir = o.runDir.empty() ? "runs/" + skill.name : o.runDir;
  // the other skills' models (the parent's weights, handover and card drivers) are read from modelsDir; the
  // exported model goes into the run folder, never into the shipped models (`treelearn ship` installs it)
  const std::string modelsDir = o.modelsDir.empty() ? l.tree.directory : o.modelsDir;
  if (config.bufferSize % envs != 0)
    throw engine::Error("--envs " + std::to_string(envs) + " must divide the PPO buffer size " +
                        std::to_string(config.bufferSize));

  SkillEnvOptions envOptions = skillEnvOptions(l, modelsDir, envs, o.threads, log);
  const dist::EnvShare share = dist::envShare(envs, comm);
  envOptions.numEnvs = share.count;
  envOptions.firstEnv = share.first;
  envOptions.runEnvs = envs;
  envOptions.comm = &comm;
  SkillEnv env(l.model, skill, l.tree.path, envOptions);
  TrainerOptions options;
  options.comm = &comm;
  options.runDir = runDir;
  options.totalSteps = steps;
  options.seed = o.seed;
  options.resume = o.resume;
  options.evalEvery = std::max(1, o.evalEvery);
  options.updateThreads = o.threads;
  options.criticWarmupIterations = o.criticWarmup;
  options.freezeNormalizer = o.freezeNormalizer;
  CardDrivers drivers;
  double bestConfirmed = -std::numeric_limits<double>::infinity();  // --eval-confirm: the best confirmed score
  const Trainer* trainerSeen = nullptr;  // set once the trainer exists (a resumed run's best is in its checkpoint)
  if (skill.card.kind() != CardKind::None && o.evalEvery > 0) {
    drivers = loadCardDrivers(l, modelsDir);
    // one card on the policy in memory: `label` heads its line, `what` names the card in its verdict
    auto scoreOn = [&](const PolicyState& p, uint64_t seed, int episodes, const char* label, const char* what) {
      CardRun card{skill.card, seed, o.threads, &comm};  // every rank runs its share of the episodes
      card.card.episodes = episodes;
      if (DrivenCard* driven = card.card.driven()) driven->standEpisodes = std::min(4, driven->standEpisodes);
      const CardResult r = runSkillCard(
          l, [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) { actDeterministic(p, obs, act); }, card, drivers);
      std::string line = "  " + std::string(label) + ": ";
      for (const auto& f : r.figures) line += format("%s %.3f  ", f.name.c_str(), f.value);
      line += format("-> score %.3f (%d-episode card%s %s)\n", r.score, episodes, what, r.pass ? "PASSES" : "fails");
      log(line);
      return r.score;
    };
    options.evaluate = [&, scoreOn](const PolicyState& p) {
      // a fixed seed, so resumed runs score identically
      const double score = scoreOn(p, 1000 + o.seed, o.evalEpisodes, "eval", "");
      // the best of many evaluations on the same episodes is chosen partly for luck on them: a candidate is
      // scored again on other episodes (--eval-confirm), and that score is the one the best is kept by
      // a resumed run's best confirmed score is its checkpoint's best (every best a confirmed run keeps is one), so
      // it confirms exactly when the run would have gone on uninterrupted
      if (o.resume && std::isinf(bestConfirmed) && trainerSeen) bestConfirmed = trainerSeen->bestScore();
      if (o.evalConfirm <= 0 || score <= bestConfirmed) return score;
      const double confirmed = scoreOn(p, 2000 + o.seed, o.evalConfirm, "confirm", " on other episodes");
      bestConfirmed = std::max(bestConfirmed, confirmed);
      return confirmed;
    };
  }
  int64_t iterationsRun = 0;  // in this process (a resumed run at or past --steps runs none)
  options.onIteration = [&](const TrainerProgress& p) {
    ++iterationsRun;
    char episodes[96] = "no episode ended";  // long episodes can outlast an iteration's rollout
    if (!std::isnan(p.meanEpisodeReturn))
      std::snprintf(episodes, sizeof episodes, "episode return %.1f  length %.0f", p.meanEpisodeReturn,
                    p.meanEpisodeLength);
    say(log,
        "iter %lld/%lld  steps %lld  %.0f steps/s  ETA %.0f min  reward/step %.3f  %s  kl %.4f  clip %.3f  ev %.2f  lr "
        "%.2g\n",
        (long long)p.iteration, (long long)p.totalIterations, (long long)p.envSteps, p.stepsPerSecond,
        p.etaSeconds / 60.0, p.meanReward, episodes, p.stats.approxKl, p.stats.clipFraction, p.stats.explainedVariance,
        p.stats.learningRate);
    if (!p.curriculumNote.empty()) say(log, "  %s\n", p.curriculumNote.c_str());
  };

  Trainer trainer(env, config, options);
  trainerSeen = &trainer;
  if (!o.resume && !o.initFrom.empty()) {
    PolicyState state = loadPolicyState(o.initFrom);
    if (!std::isnan(o.initLogStd)) state.logStd.setConstant(float(o.initLogStd));  // e.g. less noise to polish with
    trainer.initialiseFrom(state, float(o.reinflateLogStd), /*fineTune=*/!o.initAsBranch);
    say(log, "initialised from %s (%s)%s\n", o.initFrom.c_str(),
        o.initAsBranch ? "as a branch from its parent: the normaliser's weight capped"
                       : "fine-tuning: fresh optimiser and schedules, the normaliser's statistics kept",
        std::isnan(o.initLogStd) ? "" : ", log-std set");
  } else if (!o.resume && !skill.parent.empty()) {
    const SkillSpec* parent = l.tree.find(skill.parent);
    const std::string parentPolicy = modelsDir + "/" + parent->name + ".policy.bin";
    if (!std::filesystem::exists(parentPolicy))
      throw engine::Error(parentPolicy + ": the parent skill '" + parent->name + "' has no policy file yet: train " +
                          parent->name + " first (a branch starts from its parent's weights)");
    PolicyState state = loadPolicyState(parentPolicy);
    if (o.zeroOutput) zeroActorOutput(&state);
    if (!std::isnan(o.initLogStd)) state.logStd.setConstant(float(o.initLogStd));
    trainer.initialiseFrom(state, float(o.reinflateLogStd));
    say(log, "initialised from parent '%s' (%s)%s; first learning rate %.2g%s\n", parent->name.c_str(),
        parentPolicy.c_str(), o.zeroOutput ? ", actor output layer zeroed: the branch starts as its prior alone" : "",
        config.learningRate, std::isnan(o.learningRate) ? " ([ppo] branch_learning_rate)" : " (--learning-rate)");
  }
  if (comm.size() > 1)
    say(log, "training %s: %lld steps, %d envs in %d ranks of %d (%d thread%s each), seed %llu, run folder %s\n",
        skill.name.c_str(), (long long)steps, envs, comm.size(), share.count, o.threads, o.threads == 1 ? "" : "s",
        (unsigned long long)o.seed, runDir.c_str());
  else
    say(log, "training %s: %lld steps, %d envs on %d threads, seed %llu, run folder %s\n", skill.name.c_str(),
        (long long)steps, envs, o.threads, (unsigned long long)o.seed, runDir.c_str());
  if (onTrainer) onTrainer(&trainer);
  trainer.run();
  if (onTrainer) onTrainer(nullptr);
  if (trainer.stoppedEarly()) {  // a stop request: the checkpoint goes on with --resume; a half-trained run exports
                                 // nothing
    say(log,
        "stopped at iteration %lld (%lld env steps): checkpoint %s/checkpoint.bin, go on with --resume; nothing "
        "exported\n",
        (long long)trainer.iteration(), (long long)trainer.envSteps(), runDir.c_str());
    return {runDir, iterationsRun, trainer.iteration(), trainer.envSteps(), steps, true};
  }

  if (comm.size() > 1)
    say(log, "ranks in step: all %d end with policy hash %s\n", comm.size(),
        engine::toHex(trainer.policyHashOnEveryRank()).c_str());
  // export the best-by-evaluation policy if there is one, else the final one (rank 0; every rank holds the same)
  if (!comm.isRoot()) return {runDir, iterationsRun, trainer.iteration(), trainer.envSteps(), steps};
  const std::string best = runDir + "/best.bin";
  const bool haveBest = std::filesystem::exists(best);
  PolicyInfo info{ppoConfigHash(config), trainer.iteration(), trainer.envSteps(), std::nan("")};
  const PolicyState chosen = haveBest ? loadPolicyState(best, &info) : trainer.policy();
  exportToRun(l, runDir, chosen, info, o.seed, haveBest ? "best-by-evaluation policy" : "final policy", log);
  return {runDir, iterationsRun, trainer.iteration(), trainer.envSteps(), steps};
}

std::string exportedModelPath(const std::string& runDir, const SkillSpec& skill) { return runDir + "/" + skill.model; }
std::string exportedPolicyPath(const std::string& runDir, const SkillSpec& skill) {
  return runDir + "/" + skill.name + ".policy.bin";
}

void exportSkill(const robot::RobotModel& model, const SkillSpec& skill, const PolicyState& policy,
                 const std::string& onnxPath, const std::string& policyPath, const PolicyInfo& info, uint64_t seed) {
  for (const std::string& path : {onnxPath, policyPath}) {
    const std::string dir = std::filesystem::path(path).parent_path().string();
    if (!dir.empty()) engine::makeDirectories(dir);
  }
  PolicyExport e;
  e.actor = policy.actor;
  e.obsMean = policy.normalizer.mean();
  e.obsStd = policy.normalizer.stddev();
  e.obsClip = policy.normalizer.clip();
  e.metadata = skillMetadata(model, skill, info.envSteps, seed);
  savePolicyOnnx(onnxPath, e);
  savePolicyState(policyPath, policy, info);
}

void exportToRun(const SkillContext& l, const std::string& runDir, const PolicyState& policy, const PolicyInfo& info,
                 uint64_t seed, const std::string& source, const Log& log) {
  const std::string onnxPath = exportedModelPath(runDir, *l.skill), policyPath = exportedPolicyPath(runDir, *l.skill);
  exportSkill(l.model, *l.skill, policy, onnxPath, policyPath, info, seed);
  char score[64] = "no card score";
  if (!std::isnan(info.score)) std::snprintf(score, sizeof score, "card score %.3f", info.score);
  say(log, "exported %s and %s (%s: iteration %lld, %lld env steps, %s)\n", onnxPath.c_str(), policyPath.c_str(),
      source.c_str(), (long long)info.iteration, (long long)info.envSteps, score);
  const std::string tree =
      l.tree.path == engine::projectFile("assets/skills/tree.toml") ? "" : "--tree " + l.tree.path + " ";
  say(log,
      "the shipped model in %s is unchanged; to install this one once its card passes: treelearn %sship %s --from %s\n",
      l.tree.directory.c_str(), tree.c_str(), l.skill->name.c_str(), runDir.c_str());
}

void exportFromRun(const SkillContext& l, const std::string& runDir, const std::string& exportFrom, uint64_t seed,
                   const Log& log) {
  PolicyState p;
  PolicyInfo info;
  std::string source;
  if (exportFrom == "last") {
    source = runDir + "/checkpoint.bin";
    const TrainerCheckpoint c = loadCheckpoint(source);
    p = c.policy;
    info.configHash = c.configHash;
    info.iteration = c.iteration;
    info.envSteps = c.envSteps;  // no score: the last policy was not necessarily evaluated
  } else {
    source = runDir + "/best.bin";
    if (!std::filesystem::exists(source)) throw engine::Error(source + ": no evaluated policy to export yet");
    p = loadPolicyState(source, &info);
  }
  exportToRun(l, runDir, p, info, seed, source, log);
}

}  // namespace ai
