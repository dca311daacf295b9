// train.cpp — `treelearn train SKILL`, `treelearn eval SKILL` and `treelearn ship SKILL`: wires the skill tree,
// the training environment, the PPO trainer, the report card and the ONNX export together. Training exports into
// its run folder; only `ship` (after the card) writes the models in the tree's folder. Prints progress; files are
// written atomically by the layers below.
#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <random>
#include <sstream>

#include "ai/env/skill_env.h"
#include "ai/eval/ground_card.h"
#include "ai/eval/velocity_card.h"
#include "ai/onnx/skill_metadata.h"
#include "ai/onnx/policy_onnx.h"
#include "ai/ppo/checkpoint.h"
#include "ai/ppo/gaussian.h"
#include "ai/ppo/ppo_config.h"
#include "ai/ppo/trainer.h"
#include "apps/commands.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"
#include "engine/loop/clock.h"
#include "game/session.h"
#include "robot/skill_layout.h"

namespace apps {
namespace {

ai::Trainer* gTrainer = nullptr;  // apps/ only: lets Ctrl-C stop training cleanly with a checkpoint

void onSigint(int) {
  if (gTrainer) gTrainer->requestStop();
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

// the model of skill `name` in modelsDir, checked against its tree entry, as the driver of one of a card's stages
ai::DrivingSkill drivingSkill(const Loaded& l, const std::string& name, const std::string& modelsDir, const std::string& why) {
  const robot::SkillDef* def = l.tree.find(name);
  const std::string path = modelsDir + "/" + def->model;
  if (!std::filesystem::exists(path))
    throw engine::Error(path + ": the card of '" + l.skill->name + "' needs the model of '" + name + "' (" + why + "): train " + name + " first");
  auto policy = std::make_shared<ai::LoadedPolicy>(ai::loadPolicyOnnx(path));
  ai::checkModelMatchesSkill(*policy, path, l.model, *def, l.tree.path);
  return {def, [policy](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) { policy->act(obs, act); }};
}

// the way a handover into `skill` goes in play: handover_from (or the parent) first, then each skill down to the
// parent (walk, one_leg for the kick)
std::vector<const robot::SkillDef*> handoverRoute(const robot::SkillTree& tree, const robot::SkillDef& skill) {
  const std::string from = skill.handoverFrom.empty() ? skill.parent : skill.handoverFrom;
  std::vector<const robot::SkillDef*> route;
  for (const robot::SkillDef* at = tree.find(skill.parent);; at = tree.find(at->parent)) {
    route.insert(route.begin(), at);
    if (at->name == from) return route;
  }
}

// the skills that drive a card's other stages: a ground card's parent (it lies down first) and a standup card's up
// skill (it takes over once the robot stands); none for the other kinds
struct CardDrivers {
  ai::DrivingSkill before, after;
  std::vector<ai::HandoverStage> leadIn;  // a lead_in card: handover_from (or the parent), then the skills between
};
CardDrivers loadCardDrivers(const Loaded& l, const std::string& modelsDir) {
  if (l.skill->card.leadIn) {
    CardDrivers d;
    for (const robot::SkillDef* at : handoverRoute(l.tree, *l.skill)) {
      const ai::DrivingSkill ds = drivingSkill(l, at->name, modelsDir, "its card starts as play enters the skill");
      d.leadIn.push_back({ds.def, ds.policy});
    }
    return d;
  }
  if (l.skill->card.kind == robot::CardDef::Kind::PushUp || l.skill->card.kind == robot::CardDef::Kind::Crawl)
    return {drivingSkill(l, l.skill->parent, modelsDir, "it lies down first"), {}, {}};
  if (l.skill->card.kind != robot::CardDef::Kind::StandUp) return {};
  return {drivingSkill(l, l.skill->parent, modelsDir, "it lies down first"),
          drivingSkill(l, l.skill->up, modelsDir, "it takes over once standing"), {}};
}

// runs the skill's card, whichever kind
ai::CardResult runCard(const Loaded& l, const ai::PolicyFn& act, const ai::CardRun& run, const CardDrivers& drivers) {
  if (run.card.kind == robot::CardDef::Kind::StandUp || run.card.kind == robot::CardDef::Kind::PushUp ||
      run.card.kind == robot::CardDef::Kind::Crawl)
    return ai::runGroundCard(l.model, *l.skill, act, run, drivers.before, drivers.after);
  return ai::runVelocityCard(l.model, *l.skill, act, run, drivers.leadIn);
}

std::string cardText(const ai::CardResult& card) {
  std::string out;
  char line[256];
  for (const ai::CardFigure& f : card.figures) {
    if (f.bar[0] == '(')
      std::snprintf(line, sizeof line, "  %-44s %10.3f   %s\n", f.name.c_str(), f.value, f.bar.c_str());
    else
      std::snprintf(line, sizeof line, "  %-44s %10.3f   bar %-14s %s\n", f.name.c_str(), f.value, f.bar.c_str(),
                    f.pass ? "PASS" : "FAIL");
    out += line;
  }
  return out + (card.pass ? "  CARD PASSED\n" : "  CARD FAILED\n");
}

// the skill's ONNX model at path, checked as play and eval check it (sizes, controller settings of the tree entry)
std::unique_ptr<ai::LoadedPolicy> loadSkillModel(const Loaded& l, const std::string& path) {
  auto policy = std::make_unique<ai::LoadedPolicy>(ai::loadPolicyOnnx(path));
  if (policy->observationSize() != robot::kObservationSize || policy->actionSize() != robot::kActionSize)
    throw engine::Error(path + ": network sizes do not match the shared layout");
  ai::checkModelMatchesSkill(*policy, path, l.model, *l.skill, l.tree.path);
  return policy;
}

// the card's first line: what it runs and on which model (`modelShown`, `hash`)
std::string cardHead(const Loaded& l, const ai::CardRun& run, const std::string& modelShown, const std::string& hash) {
  const robot::CardDef& def = l.skill->card;
  const std::string& name = l.skill->name;
  const char* onnxPath = modelShown.c_str();
  char head[1024];  // room for a long model path
  if (def.kind == robot::CardDef::Kind::StandUp)
    std::snprintf(head, sizeof head, "%s report card: %d episodes: %s lies down for %g-%g s, then %s (model %s, hash %s), "
                  "then %s takes over once it stands\n", name.c_str(), run.card.episodes, l.skill->parent.c_str(),
                  def.lieSeconds.lo, def.lieSeconds.hi, name.c_str(), onnxPath, hash.c_str(), l.skill->up.c_str());
  else if (def.kind == robot::CardDef::Kind::PushUp)
    std::snprintf(head, sizeof head, "%s report card: %d episodes: %s lies down for %g-%g s, then %s for %g s (model %s, hash %s)\n",
                  name.c_str(), run.card.episodes, l.skill->parent.c_str(), def.lieSeconds.lo, def.lieSeconds.hi,
                  name.c_str(), def.episodeSeconds, onnxPath, hash.c_str());
  else if (def.kind == robot::CardDef::Kind::Crawl) {
    char steer[160] = "";
    if (def.steer > 0)
      std::snprintf(steer, sizeof steer, ", steered toward its axis as a player would (wz = -%g x the error, within %g rad/s)",
                    def.steer, l.skill->commands.wz.hi);
    std::snprintf(head, sizeof head, "%s report card: %d episodes: %s lies down for %g-%g s, then %s at %g-%g m/s through a "
                  "tunnel %g m wide, its ceiling %g m up%s (model %s, hash %s)\n", name.c_str(), run.card.episodes,
                  l.skill->parent.c_str(), def.lieSeconds.lo, def.lieSeconds.hi, name.c_str(), def.vx.lo, def.vx.hi,
                  l.skill->terrain.width, l.skill->terrain.ceilingHeight, steer, onnxPath, hash.c_str());
  } else {
    std::string leadIn;  // "walk 1-3 s, to rest, one_leg 0-2 s, then " for a lead_in card
    if (def.leadIn) {
      char b[160];
      const std::vector<const robot::SkillDef*> route = handoverRoute(l.tree, *l.skill);
      for (size_t k = 0; k < route.size(); ++k) {
        const robot::Range& t = k == 0 ? l.skill->handoverSeconds : l.skill->handoverViaSeconds;
        std::snprintf(b, sizeof b, "%s%s %g-%g s", k == 0 ? "each entered as in play: " : ", ", route[k]->name.c_str(), t.lo, t.hi);
        leadIn += b;
      }
      leadIn = " (" + leadIn + ", then " + name + ")";
    }
    if (def.kind == robot::CardDef::Kind::Stairs && def.steer > 0) {  // the player's steering, as the crawl card says it
      char b[160];
      std::snprintf(b, sizeof b, ", steered square to the stairs as play's heading hold does (wz = -%g x the heading off them, within %g rad/s)",
                    def.steer, robot::headingHoldLimit(l.skill->commands));
      leadIn += b;
    }
    std::snprintf(head, sizeof head, "%s report card: %d episodes x %g s%s with pushes %s, commands every %g s%s (model %s, hash %s)\n",
                  name.c_str(), run.card.episodes, def.episodeSeconds, leadIn.c_str(), def.pushes ? "on" : "off",
                  def.segmentSeconds, def.standEpisodes ? ("; " + std::to_string(def.standEpisodes) + " standing episodes x " +
                                       std::to_string(int(def.standSeconds)) + " s").c_str() : "",
                  onnxPath, hash.c_str());
  }
  return head;
}

// prints the card's head, runs the card (the other stages' drivers from the tree's folder) and prints its figures;
// returns the result and the whole text, as `eval` records it
struct PrintedCard {
  ai::CardResult result;
  std::string text;
};
PrintedCard printCard(const Loaded& l, const ai::PolicyFn& act, const ai::CardRun& run, const std::string& modelShown,
                      const std::string& hash) {
  const std::string head = cardHead(l, run, modelShown, hash);
  std::fputs(head.c_str(), stdout);
  std::fflush(stdout);
  PrintedCard c;
  c.result = runCard(l, act, run, loadCardDrivers(l, l.tree.directory));
  const std::string figures = cardText(c.result);
  std::fputs(figures.c_str(), stdout);
  c.text = head + figures;
  return c;
}

// writes RUN/SKILL.onnx and RUN/SKILL.policy.bin (with where the policy came from) and says how to ship them
void exportToRun(const Loaded& l, const std::string& runDir, const ai::PolicyState& policy, const ai::PolicyInfo& info,
                 uint64_t seed, const std::string& source) {
  const std::string onnxPath = exportedModelPath(runDir, *l.skill), policyPath = exportedPolicyPath(runDir, *l.skill);
  exportSkill(l.model, *l.skill, policy, onnxPath, policyPath, info, seed);
  char score[64] = "no card score";
  if (!std::isnan(info.score)) std::snprintf(score, sizeof score, "card score %.3f", info.score);
  std::printf("exported %s and %s (%s: iteration %lld, %lld env steps, %s)\n", onnxPath.c_str(), policyPath.c_str(),
              source.c_str(), (long long)info.iteration, (long long)info.envSteps, score);
  const std::string tree = l.tree.path == engine::projectFile("assets/skills/tree.toml") ? "" : "--tree " + l.tree.path + " ";
  std::printf("the shipped model in %s is unchanged; to install this one once its card passes: treelearn %sship %s --from %s\n",
              l.tree.directory.c_str(), tree.c_str(), l.skill->name.c_str(), runDir.c_str());
}

}  // namespace

int runTrain(const TrainOptions& o) {
  const Loaded l = loadSkill(o.skill);
  const robot::SkillDef& skill = *l.skill;
  const std::string treeText = engine::readFile(l.tree.path);
  // [ppo], then the skill's own [skill.NAME.ppo] overrides (not inherited by its branches)
  ai::PpoConfig config = ai::parsePpoConfig(treeText, l.tree.path, "ppo");
  config = ai::parsePpoConfig(treeText, l.tree.path, "skill." + skill.name + ".ppo", config);
  if (!std::isnan(o.learningRate)) {
    if (!(o.learningRate > 0 && o.learningRate < 1)) throw engine::Error("--learning-rate must be in (0, 1)");
    config.learningRate = o.learningRate;  // decays linearly to the config's final rate, as usual
  }
  if (o.zeroOutput && (o.resume || !o.initFrom.empty() || skill.parent.empty()))
    throw engine::Error("--zero-output is a branch's initialisation from its parent: not with --resume, --init-from or for the root skill");
  if (!std::isnan(o.initLogStd) && (o.resume || (o.initFrom.empty() && skill.parent.empty())))
    throw engine::Error("--init-log-std sets the starting noise of a branch (from its parent) or of a fine-tune (--init-from): "
                        "not with --resume or for the root skill trained afresh");
  const int64_t steps = o.steps > 0 ? o.steps : skill.trainingSteps;
  const int envs = o.envs > 0 ? o.envs : skill.trainingEnvs;
  const std::string runDir = o.runDir.empty() ? "runs/" + skill.name : o.runDir;
  // the other skills' models (the parent's weights, handover and card drivers) are read from modelsDir; the
  // exported model goes into the run folder, never into the shipped models (`treelearn ship` installs it)
  const std::string modelsDir = o.modelsDir.empty() ? l.tree.directory : o.modelsDir;
  if (config.bufferSize % envs != 0)
    throw engine::Error("--envs " + std::to_string(envs) + " must divide the PPO buffer size " + std::to_string(config.bufferSize));

  ai::SkillEnvOptions envOptions;
  envOptions.numEnvs = envs;
  envOptions.threads = o.threads;
  std::shared_ptr<ai::LoadedPolicy> handoverPolicy;
  if (skill.handover > 0) {  // episodes that start under the parent's (or handover_from's) shipped model
    const robot::SkillDef* parent = l.tree.find(skill.handoverFrom.empty() ? skill.parent : skill.handoverFrom);
    const std::string path = modelsDir + "/" + parent->model;
    if (!std::filesystem::exists(path))
      throw engine::Error(path + ": the parent skill '" + parent->name + "' has no model yet (handover episodes start under it): train " +
                          parent->name + " first");
    handoverPolicy = std::make_shared<ai::LoadedPolicy>(ai::loadPolicyOnnx(path));
    envOptions.parent = parent;
    envOptions.parentPolicy = [handoverPolicy](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) { handoverPolicy->act(obs, act); };
    std::printf("handover episodes: %.0f %% start under '%s' (%s) for %.1f-%.1f s\n", 100 * skill.handover,
                parent->name.c_str(), path.c_str(), skill.handoverSeconds.lo, skill.handoverSeconds.hi);
    // the skills between handover_from and this one, which a routed request passes through in play
    const std::vector<const robot::SkillDef*> route = handoverRoute(l.tree, skill);
    for (auto it = route.begin() + 1; it != route.end(); ++it) {
      const robot::SkillDef* v = *it;
      const std::string vpath = modelsDir + "/" + v->model;
      if (!std::filesystem::exists(vpath))
        throw engine::Error(vpath + ": the skill '" + v->name + "' has no model yet (handover episodes route through it): train " +
                            v->name + " first");
      auto policy = std::make_shared<ai::LoadedPolicy>(ai::loadPolicyOnnx(vpath));
      envOptions.via.push_back({v, [policy](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) { policy->act(obs, act); }});
      std::printf("  then '%s' (%s) for %.1f-%.1f s at a zero command\n", v->name.c_str(), vpath.c_str(),
                  skill.handoverViaSeconds.lo, skill.handoverViaSeconds.hi);
    }
  }
  std::shared_ptr<ai::LoadedPolicy> backPolicy;
  if (skill.handoverBack > 0) {  // episodes that start under a child's shipped model (the way back up the tree)
    const robot::SkillDef* child = l.tree.find(skill.handoverBackFrom);
    const std::string path = modelsDir + "/" + child->model;
    if (!std::filesystem::exists(path))
      throw engine::Error(path + ": the skill '" + child->name + "' has no model yet (handover_back episodes start under it): train " +
                          child->name + " first, or set handover_back = 0");
    backPolicy = std::make_shared<ai::LoadedPolicy>(ai::loadPolicyOnnx(path));
    envOptions.back = {child, [backPolicy](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) { backPolicy->act(obs, act); }};
    std::printf("handover episodes back up the tree: %.0f %% start under '%s' (%s) for %.1f-%.1f s, then switch to '%s'\n",
                100 * skill.handoverBack, child->name.c_str(), path.c_str(), skill.handoverBackSeconds.lo,
                skill.handoverBackSeconds.hi, skill.name.c_str());
  }
  ai::SkillEnv env(l.model, skill, l.tree.path, envOptions);
  ai::TrainerOptions options;
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
  const ai::Trainer* trainerSeen = nullptr;  // set once the trainer exists (a resumed run's best is in its checkpoint)
  if (skill.card.kind != robot::CardDef::Kind::None && o.evalEvery > 0) {
    drivers = loadCardDrivers(l, modelsDir);
    // one card on the policy in memory: `label` heads its line, `what` names the card in its verdict
    auto scoreOn = [&](const ai::PolicyState& p, uint64_t seed, int episodes, const char* label, const char* what) {
      ai::CardRun card{skill.card, seed, o.threads};
      card.card.episodes = episodes;
      card.card.standEpisodes = std::min(4, skill.card.standEpisodes);
      const ai::CardResult r = runCard(
          l, [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) { ai::actDeterministic(p, obs, act); }, card, drivers);
      std::printf("  %s: ", label);
      for (const auto& f : r.figures) std::printf("%s %.3f  ", f.name.c_str(), f.value);
      std::printf("-> score %.3f (%d-episode card%s %s)\n", r.score, episodes, what, r.pass ? "PASSES" : "fails");
      return r.score;
    };
    options.evaluate = [&, scoreOn](const ai::PolicyState& p) {
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
  options.onIteration = [&](const ai::TrainerProgress& p) {
    ++iterationsRun;
    char episodes[96] = "no episode ended";  // long episodes can outlast an iteration's rollout
    if (!std::isnan(p.meanEpisodeReturn))
      std::snprintf(episodes, sizeof episodes, "episode return %.1f  length %.0f", p.meanEpisodeReturn, p.meanEpisodeLength);
    std::printf("iter %lld/%lld  steps %lld  %.0f steps/s  ETA %.0f min  reward/step %.3f  %s  kl %.4f  clip %.3f  ev %.2f  lr %.2g\n",
                (long long)p.iteration, (long long)p.totalIterations, (long long)p.envSteps, p.stepsPerSecond,
                p.etaSeconds / 60.0, p.meanReward, episodes, p.stats.approxKl, p.stats.clipFraction,
                p.stats.explainedVariance, p.stats.learningRate);
    if (!p.curriculumNote.empty()) std::printf("  %s\n", p.curriculumNote.c_str());
    std::fflush(stdout);
  };

  ai::Trainer trainer(env, config, options);
  trainerSeen = &trainer;
  if (!o.resume && !o.initFrom.empty()) {
    ai::PolicyState state = ai::loadPolicyState(o.initFrom);
    if (!std::isnan(o.initLogStd)) state.logStd.setConstant(float(o.initLogStd));  // e.g. less noise to polish with
    trainer.initialiseFrom(state, float(o.reinflateLogStd), /*fineTune=*/true);
    std::printf("initialised from %s (fine-tuning: fresh optimiser and schedules, the normaliser's statistics kept)%s\n",
                o.initFrom.c_str(), std::isnan(o.initLogStd) ? "" : ", log-std set");
  } else if (!o.resume && !skill.parent.empty()) {
    const robot::SkillDef* parent = l.tree.find(skill.parent);
    const std::string parentPolicy = modelsDir + "/" + parent->name + ".policy.bin";
    if (!std::filesystem::exists(parentPolicy))
      throw engine::Error(parentPolicy + ": the parent skill '" + parent->name + "' has no policy file yet: train " +
                          parent->name + " first (a branch starts from its parent's weights)");
    ai::PolicyState state = ai::loadPolicyState(parentPolicy);
    if (o.zeroOutput) ai::zeroActorOutput(&state);
    if (!std::isnan(o.initLogStd)) state.logStd.setConstant(float(o.initLogStd));
    trainer.initialiseFrom(state, float(o.reinflateLogStd));
    std::printf("initialised from parent '%s' (%s)%s\n", parent->name.c_str(), parentPolicy.c_str(),
                o.zeroOutput ? ", actor output layer zeroed: the branch starts as its prior alone" : "");
  }
  std::printf("training %s: %lld steps, %d envs on %d threads, seed %llu, run folder %s\n", skill.name.c_str(),
              (long long)steps, envs, o.threads, (unsigned long long)o.seed, runDir.c_str());
  gTrainer = &trainer;
  std::signal(SIGINT, onSigint);
  trainer.run();
  gTrainer = nullptr;
  if (o.resume && iterationsRun == 0)
    std::fprintf(stderr, "note: the checkpoint in %s is already at %lld env steps (iteration %lld), at or past --steps %lld: "
                 "nothing was trained; give a larger --steps to go on\n", runDir.c_str(), (long long)trainer.envSteps(),
                 (long long)trainer.iteration(), (long long)steps);

  // export the best-by-evaluation policy if there is one, else the final one
  const std::string best = runDir + "/best.bin";
  const bool haveBest = std::filesystem::exists(best);
  ai::PolicyInfo info{ai::ppoConfigHash(config), trainer.iteration(), trainer.envSteps(), std::nan("")};
  const ai::PolicyState chosen = haveBest ? ai::loadPolicyState(best, &info) : trainer.policy();
  exportToRun(l, runDir, chosen, info, o.seed, haveBest ? "best-by-evaluation policy" : "final policy");
  return 0;
}

std::string exportedModelPath(const std::string& runDir, const robot::SkillDef& skill) { return runDir + "/" + skill.model; }
std::string exportedPolicyPath(const std::string& runDir, const robot::SkillDef& skill) {
  return runDir + "/" + skill.name + ".policy.bin";
}

void exportSkill(const robot::RobotModel& model, const robot::SkillDef& skill, const ai::PolicyState& policy,
                 const std::string& onnxPath, const std::string& policyPath, const ai::PolicyInfo& info, uint64_t seed) {
  for (const std::string& path : {onnxPath, policyPath}) {
    const std::string dir = std::filesystem::path(path).parent_path().string();
    if (!dir.empty()) engine::makeDirectories(dir);
  }
  ai::PolicyExport e;
  e.actor = policy.actor;
  e.obsMean = policy.normalizer.mean();
  e.obsStd = policy.normalizer.stddev();
  e.obsClip = policy.normalizer.clip();
  e.metadata = ai::skillMetadata(model, skill, info.envSteps, seed);
  ai::savePolicyOnnx(onnxPath, e);
  ai::savePolicyState(policyPath, policy, info);
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
    info.configHash = c.configHash;
    info.iteration = c.iteration;
    info.envSteps = c.envSteps;  // no score: the last policy was not necessarily evaluated
  } else {
    source = runDir + "/best.bin";
    if (!std::filesystem::exists(source)) throw engine::Error(source + ": no evaluated policy to export yet");
    p = ai::loadPolicyState(source, &info);
  }
  exportToRun(l, runDir, p, info, o.seed, source);
  return 0;
}

int runEval(const EvalOptions& o) {
  const Loaded l = loadSkill(o.skill);
  const robot::CardDef& def = l.skill->card;
  if (def.kind == robot::CardDef::Kind::None)
    throw engine::Error(l.tree.path + ": skill '" + o.skill + "' has no [skill." + o.skill + ".card] table, so it has no report card");
  if (o.priorOnly && (o.sweep || !o.model.empty()))
    throw engine::Error("eval --prior-only runs the card with zero network output: it takes no --model or --sweep");
  if (!o.samplePolicy.empty() && (o.priorOnly || o.sweep || !o.model.empty()))
    throw engine::Error("eval --sample draws the card's actions from a policy file: it takes no --prior-only, --model or --sweep");
  const std::string onnxPath = o.priorOnly ? "none (the prior alone)"
                               : !o.samplePolicy.empty() ? o.samplePolicy + " (actions drawn from its Gaussian)"
                               : o.model.empty() ? l.tree.directory + "/" + l.skill->model : o.model;
  std::unique_ptr<ai::LoadedPolicy> policy;
  std::unique_ptr<ai::PolicyState> sampled;  // --sample: mean and log-std, with a seeded noise stream
  std::mt19937_64 noise(o.seed * 0x9E3779B97F4A7C15ull + 17);
  if (!o.samplePolicy.empty()) {
    sampled = std::make_unique<ai::PolicyState>(ai::loadPolicyState(o.samplePolicy));
    if (sampled->actor.inputSize() != robot::kObservationSize || sampled->actor.outputSize() != robot::kActionSize)
      throw engine::Error(o.samplePolicy + ": network sizes do not match the shared layout");
  } else if (!o.priorOnly) {
    policy = loadSkillModel(l, onnxPath);
  }
  const ai::PolicyFn act = [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) {
    if (sampled) {  // called once a tick for the whole batch, on one thread: the draws are in a fixed order
      Eigen::MatrixXf mean;
      ai::actDeterministic(*sampled, obs, &mean);
      ai::sampleGaussian(&noise, mean, sampled->logStd, a);
    } else if (policy) {
      policy->act(obs, a);
    } else {
      *a = Eigen::MatrixXf::Zero(robot::kActionSize, obs.cols());
    }
  };
  if (o.sweep) {
    std::vector<robot::SkillCommand> commands;
    for (double vx : {-0.6, -0.3, 0.3, 0.6, 0.9, 1.2, 1.5, 2.0}) commands.push_back({vx, 0, 0});
    for (double vy : {-0.4, 0.4}) commands.push_back({0, vy, 0});
    for (double wz : {-1.0, 1.0}) commands.push_back({0, 0, wz});
    commands.push_back({0, 0, 0});
    std::printf("%s speed sweep: each command held 10 s, no pushes, friction 1 (model %s)\n", o.skill.c_str(), onnxPath.c_str());
    std::printf("  %6s %6s %6s   %7s %7s %7s   %s\n", "vx_cmd", "vy_cmd", "wz_cmd", "vx", "vy", "wz", "fall");
    for (const ai::SweepRow& r : ai::runSpeedSweep(l.model, *l.skill, act, commands, 10.0, o.threads)) {
      char fall[32] = "no";
      if (r.fell) std::snprintf(fall, sizeof fall, "at %.2f s", r.secondsUp);
      std::printf("  %6.2f %6.2f %6.2f   %7.3f %7.3f %7.3f   %s\n", r.command.vx, r.command.vy, r.command.wz, r.mean.x(),
                  r.mean.y(), r.mean.z(), fall);
    }
    return 0;
  }
  ai::CardRun run{def, o.seed, o.threads};
  if (o.episodes > 0) run.card.episodes = o.episodes;
  const std::string hash = policy ? engine::toHex(ai::onnxFileHash(onnxPath)) : "-";
  const PrintedCard card = printCard(l, act, run, onnxPath, hash);
  const std::string& text = card.text;
  const ai::CardResult& r = card.result;
  // the shipped model's card with the card's own episodes and seed is kept next to it (for `treelearn tree`);
  // a record of the same model file must come out identical: training other skills never changes a skill
  if (policy && o.model.empty() && o.episodes == 0 && o.seed == 1) {
    const std::string record = cardRecordPath(l.tree, *l.skill);
    const bool same = std::filesystem::exists(record) &&
                      engine::readFile(record).find(engine::toHex(ai::onnxFileHash(onnxPath))) != std::string::npos;
    if (same && engine::readFile(record) != text) {
      std::printf("  RETENTION FAILED: the card differs from the one recorded for this model in %s\n", record.c_str());
      return 1;
    }
    if (same) std::printf("  identical to the card recorded for this model in %s\n", record.c_str());
    else engine::writeFileAtomic(record, text), std::printf("  recorded in %s\n", record.c_str());
  }
  return r.pass ? 0 : 1;
}

int runShip(const ShipOptions& o) {
  namespace fs = std::filesystem;
  const Loaded l = loadSkill(o.skill);
  const robot::SkillDef& skill = *l.skill;
  const std::string runDir = o.runDir.empty() ? "runs/" + skill.name : o.runDir;
  if (!fs::is_directory(runDir))
    throw engine::Error(runDir + ": no such run folder (`treelearn train " + skill.name + " --run-dir " + runDir + "` makes one)");
  const std::string onnxPath = exportedModelPath(runDir, skill), policyPath = exportedPolicyPath(runDir, skill);
  if (!fs::exists(onnxPath)) {
    std::string others;  // another skill's export in the folder: the wrong run, or the wrong skill named
    for (const auto& e : fs::directory_iterator(runDir))
      if (e.path().extension() == ".onnx") others += (others.empty() ? "" : ", ") + e.path().filename().string();
    throw engine::Error(onnxPath + ": the run folder holds no model of '" + skill.name + "' " +
                        (others.empty() ? "(train exports it when it ends; `treelearn train " + skill.name + " --export-only --run-dir " +
                                              runDir + "` exports the run's best)"
                                        : "but " + others + ": a run of another skill?"));
  }
  if (!fs::exists(policyPath))
    throw engine::Error(policyPath + ": missing next to " + onnxPath + " (a branch starts from it; `treelearn train " + skill.name +
                        " --export-only --run-dir " + runDir + "` exports both)");
  {
    const ai::LoadedPolicy file = ai::loadPolicyOnnx(onnxPath);
    const auto it = file.metadata.find("treelearn.skill");
    if (it != file.metadata.end() && it->second != skill.name)
      throw engine::Error(onnxPath + ": a model of skill '" + it->second + "', not of '" + skill.name + "'");
  }
  const std::unique_ptr<ai::LoadedPolicy> policy = loadSkillModel(l, onnxPath);
  ai::PolicyInfo info;
  const ai::PolicyState state = ai::loadPolicyState(policyPath, &info);
  const auto same = [](const auto& a, const auto& b) { return a.rows() == b.rows() && a.cols() == b.cols() && a == b; };
  bool sameActor = state.actor.layers() == policy->actor.layers() && same(state.normalizer.mean(), policy->obsMean);
  for (int k = 0; sameActor && k < state.actor.layers(); ++k)
    sameActor = same(state.actor.W[k], policy->actor.W[k]) && same(state.actor.b[k], policy->actor.b[k]);
  if (!sameActor)
    throw engine::Error(policyPath + " and " + onnxPath + " hold different policies (not one export): export the run again");

  const std::string installedOnnx = l.tree.directory + "/" + skill.model;
  const std::string installedPolicy = l.tree.directory + "/" + skill.name + ".policy.bin";
  const std::string hash = engine::toHex(ai::onnxFileHash(onnxPath));
  char score[64] = "no card score";
  if (!std::isnan(info.score)) std::snprintf(score, sizeof score, "training card score %.3f", info.score);
  std::printf("shipping %s (hash %s; iteration %lld, %lld env steps, %s) as %s, if its report card passes:\n",
              onnxPath.c_str(), hash.c_str(), (long long)info.iteration, (long long)info.envSteps, score, installedOnnx.c_str());
  std::string record;  // the card as `eval` records it for the installed model
  if (skill.card.kind == robot::CardDef::Kind::None) {
    if (!o.force)
      throw engine::Error(l.tree.path + ": skill '" + skill.name + "' has no [skill." + skill.name +
                          ".card] table, so its model cannot be judged (ship --force installs it without a card)");
    std::printf("  no report card for '%s': installed without one (--force)\n", skill.name.c_str());
  } else {
    const PrintedCard card = printCard(
        l, [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) { policy->act(obs, act); }, ai::CardRun{skill.card, 1, o.threads},
        installedOnnx, hash);
    if (!card.result.pass) {
      std::string failed;
      for (const ai::CardFigure& f : card.result.figures)
        if (f.bar[0] != '(' && !f.pass) {
          char b[256];
          std::snprintf(b, sizeof b, "%s%s %.3f, bar %s", failed.empty() ? "" : "; ", f.name.c_str(), f.value, f.bar.c_str());
          failed += b;
        }
      if (!o.force) {
        std::printf("REFUSED: the card of '%s' fails (%s): nothing was installed (ship --force installs it anyway)\n",
                    skill.name.c_str(), failed.c_str());
        return 1;
      }
      std::printf("  the card fails (%s): installed anyway (--force); its record says CARD FAILED\n", failed.c_str());
    }
    record = card.text;
  }
  // each file atomically (a temp file, then a rename): the branches' weights, the model play loads, its card
  engine::writeFileAtomic(installedPolicy, engine::readFile(policyPath));
  engine::writeFileAtomic(installedOnnx, engine::readFile(onnxPath));
  if (!record.empty()) engine::writeFileAtomic(cardRecordPath(l.tree, skill), record);
  std::printf("shipped %s and %s%s\n", installedOnnx.c_str(), installedPolicy.c_str(),
              record.empty() ? "" : (", card recorded in " + cardRecordPath(l.tree, skill)).c_str());
  return 0;
}

int runEvalAll(const EvalOptions& o) {
  if (o.priorOnly || o.sweep || !o.model.empty())
    throw engine::Error("eval all runs every shipped model's card and the switches: it takes no --prior-only, --sweep or --model");
  const robot::RobotModel model = robot::loadRobotModel(engine::projectFile("assets/robots/g1_23dof.toml"));
  const robot::SkillTree tree = robot::loadSkillTree(robot::defaultSkillTreePath(), model);
  std::vector<std::pair<std::string, std::string>> results;
  int connected = 0;
  for (const robot::SkillDef& s : tree.skills) {
    const bool hasModel = std::filesystem::exists(tree.directory + "/" + s.model);
    connected += hasModel && !s.parent.empty() && std::filesystem::exists(tree.directory + "/" + tree.find(s.parent)->model);
    if (!hasModel) {
      results.push_back({s.name, "FAIL (no model: treelearn train " + s.name + ")"});
      continue;
    }
    if (s.card.kind == robot::CardDef::Kind::None) {
      results.push_back({s.name, "FAIL (no card in the tree file)"});
      continue;
    }
    EvalOptions one = o;
    one.skill = s.name;
    one.model.clear();
    const int code = runEval(one);
    results.push_back({s.name, code == 0 ? "PASS" : "FAIL"});
    std::printf("\n");
  }
  if (connected > 0) {
    SwitchEvalOptions sw;
    sw.seed = o.seed;
    sw.threads = o.threads;
    sw.verbose = o.verbose;
    results.push_back({"switches", runSwitchEval(sw) == 0 ? "PASS" : "FAIL"});
  } else {
    results.push_back({"switches", "FAIL (no two connected skills have models)"});
  }
  bool pass = true;
  std::printf("\nall cards:\n");
  for (const auto& [name, result] : results) {
    std::printf("  %-10s %s\n", name.c_str(), result.c_str());
    pass = pass && result == "PASS";
  }
  std::printf("  %s\n", pass ? "ALL PASSED" : "NOT ALL PASSED");
  return pass ? 0 : 1;
}

}  // namespace apps
