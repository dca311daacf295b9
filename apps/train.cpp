// train.cpp — `treelearn train SKILL`, `treelearn eval SKILL` and `treelearn ship SKILL`: the options to
// ai::trainSkill and the cards of ai/eval/skill_card.h, and what they print. Training exports into its run folder;
// only `ship` (after the card) writes the models in the tree's folder. Files are written atomically by the layers
// below.
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>

#include "ai/env/multi_task_env.h"
#include "ai/eval/skill_card.h"
#include "ai/onnx/policy_onnx.h"
#include "ai/ppo/checkpoint.h"
#include "ai/ppo/gaussian.h"
#include "ai/train/train_skill.h"
#include "apps/commands.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"
#include "robot/skill_layout.h"

namespace apps {
namespace {

ai::Trainer* gTrainer = nullptr;  // apps/ only: lets Ctrl-C stop training cleanly with a checkpoint

// the first Ctrl-C asks for a stop at the end of the iteration (a checkpoint, no export); a second one ends the
// process at once, which leaves the last checkpoint whole (it is written atomically)
void onSigint(int) {
  if (gTrainer) gTrainer->requestStop();
  std::signal(SIGINT, SIG_DFL);
}

// SIGUSR1 asks for the same stop. Under mpirun it is the way: mpirun forwards SIGUSR1 to every rank, while Ctrl-C
// makes it kill the ranks (the last checkpoint stays whole, but the iteration in progress is lost)
volatile std::sig_atomic_t gStopAsked = 0;  // a SIGUSR1 that came before the trainer existed (while loading)
void onSigusr1(int) {
  gStopAsked = 1;
  if (gTrainer) gTrainer->requestStop();
}

void stopOnSignals(ai::Trainer* t) {
  gTrainer = t;
  std::signal(SIGINT, t ? onSigint : SIG_DFL);
  if (t && gStopAsked) t->requestStop();
}

void printLine(const std::string& line) {
  std::fputs(line.c_str(), stdout);
  std::fflush(stdout);
}

// prints the card's head, runs the card (the other stages' drivers from the tree's folder) and prints its figures;
// returns the result and the whole text, as `eval` records it
struct PrintedCard {
  ai::CardResult result;
  std::string text;
};
PrintedCard printCard(const ai::SkillContext& l, const ai::PolicyFn& act, const ai::CardRun& run,
                      const std::string& modelShown, const std::string& hash) {
  // under mpirun every rank runs its share of the episodes and gets the same figures; rank 0 prints them
  const bool root = !run.comm || run.comm->isRoot();
  const std::string head = ai::cardHead(l, run, modelShown, hash);
  if (root) std::fputs(head.c_str(), stdout), std::fflush(stdout);
  PrintedCard c;
  c.result = ai::runSkillCard(l, act, run, ai::loadCardDrivers(l, l.tree.directory));
  const std::string figures = ai::cardText(c.result);
  if (root) std::fputs(figures.c_str(), stdout);
  c.text = head + figures;
  return c;
}

}  // namespace

int runTrain(const TrainOptions& o) {
  const ai::SkillContext l = ai::loadSkillContext(o.skill);
  std::signal(SIGUSR1, onSigusr1);  // from the start: the ranks load at their own pace
  const ai::TrainSkillResult r = ai::trainSkill(l, o, printLine, stopOnSignals);
  if (r.stopped) return 130;  // stopped by Ctrl-C (128 + SIGINT, as a shell reports it)
  if (o.resume && r.iterationsRun == 0 && ai::dist::world().isRoot())
    std::fprintf(stderr,
                 "note: the checkpoint in %s is already at %lld env steps (iteration %lld), at or past --steps %lld: "
                 "nothing was trained; give a larger --steps to go on\n",
                 r.runDir.c_str(), (long long)r.envSteps, (long long)r.iteration, (long long)r.steps);
  return 0;
}

int runMultiTask(const ai::TrainMultiOptions& o) {
  std::signal(SIGUSR1, onSigusr1);
  const ai::TrainMultiResult r = ai::trainMultiTask(o, printLine, stopOnSignals);
  return r.stopped ? 130 : 0;
}

int runExport(const TrainOptions& o) {
  const ai::SkillContext l = ai::loadSkillContext(o.skill);
  ai::exportFromRun(l, o.runDir.empty() ? "runs/" + o.skill : o.runDir, o.exportFrom, o.seed, printLine);
  return 0;
}

int runEval(const EvalOptions& o) {
  const ai::SkillContext l = ai::loadSkillContext(o.skill);
  const ai::CardDef& def = l.skill->card;
  if (def.kind() == ai::CardKind::None)
    throw engine::Error(l.tree.path + ": skill '" + o.skill + "' has no [skill." + o.skill +
                        ".card] table, so it has no report card");
  if (o.priorOnly && (o.sweep || !o.model.empty()))
    throw engine::Error("eval --prior-only runs the card with zero network output: it takes no --model or --sweep");
  if (!o.samplePolicy.empty() && (o.priorOnly || o.sweep || !o.model.empty()))
    throw engine::Error(
        "eval --sample draws the card's actions from a policy file: it takes no --prior-only, --model or --sweep");
  if (!o.multitask.empty() && (o.priorOnly || o.sweep || !o.model.empty() || !o.samplePolicy.empty()))
    throw engine::Error(
        "eval --multitask runs the card on a multi-task run's network: it takes no --prior-only, --sweep, --model or "
        "--sample");
  const std::string onnxPath =
      o.priorOnly            ? "none (the prior alone)"
      : !o.multitask.empty() ? o.multitask + "/multitask.policy.bin (the multi-task network, one-hot '" + o.skill + "')"
      : !o.samplePolicy.empty() ? o.samplePolicy + " (actions drawn from its Gaussian)"
      : o.model.empty()         ? l.tree.directory + "/" + l.skill->model
                                : o.model;
  std::unique_ptr<ai::LoadedPolicy> policy;
  std::unique_ptr<ai::PolicyState> sampled;  // --sample: mean and log-std, with a seeded noise stream
  std::mt19937_64 noise(o.seed * 0x9E3779B97F4A7C15ull + 17);
  std::unique_ptr<ai::MultiTaskPolicy> multi;  // --multitask: the run's network and this skill's one-hot
  int multiIndex = -1;
  if (!o.multitask.empty()) {
    multi = std::make_unique<ai::MultiTaskPolicy>(ai::loadMultiTaskPolicy(o.multitask));
    multiIndex = multi->indexOf(o.skill, o.multitask);
  } else if (!o.samplePolicy.empty()) {
    sampled = std::make_unique<ai::PolicyState>(ai::loadPolicyState(o.samplePolicy));
    if (sampled->actor.inputSize() != robot::kObservationSize || sampled->actor.outputSize() != robot::kActionSize)
      throw engine::Error(o.samplePolicy + ": network sizes do not match the shared layout");
  } else if (!o.priorOnly) {
    policy = ai::loadSkillModel(l, onnxPath);
  }
  const ai::PolicyFn act = [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) {
    if (multi) {
      ai::actDeterministic(multi->policy, ai::MultiTaskEnv::withTask(obs, multiIndex, int(multi->skills.size())), a);
    } else if (sampled) {  // called once a tick for the whole batch, on one thread: the draws are in a fixed order
      Eigen::MatrixXf mean;
      ai::actDeterministic(*sampled, obs, &mean);
      ai::sampleGaussian(&noise, mean, sampled->logStd, a);
    } else if (policy) {
      policy->act(obs, a);
    } else {
      *a = Eigen::MatrixXf::Zero(robot::kActionSize, obs.cols());
    }
  };
  const ai::dist::Comm& comm = ai::dist::world();
  if (comm.size() > 1 && (o.rewards > 0 || o.sweep))
    throw engine::Error(
        "under mpirun eval runs a report card (its episodes shared by the ranks): not --rewards or --sweep");
  if (o.rewards > 0) {
    if (o.priorOnly || o.sweep)
      throw engine::Error("eval --rewards measures a model: it takes no --prior-only or --sweep");
    const int envs = 20;
    const ai::RewardFigures f =
        ai::measureRewards(l, act, l.tree.directory, envs, o.rewards, o.seed, o.threads, [](const std::string&) {});
    std::printf(
        "%s rewards in its training episodes: %d rollouts x %d environments, %lld steps, deterministic actions, seed "
        "%llu (model %s)\n",
        o.skill.c_str(), o.rewards, envs, (long long)f.steps, (unsigned long long)o.seed, onnxPath.c_str());
    std::printf("  episodes ended       %d (%.0f %% fell)\n", f.episodes, 100.0 * f.fellShare);
    std::printf("  mean episode return  %.2f\n", f.meanReturn);
    std::printf("  mean episode length  %.1f steps\n", f.meanLength);
    std::printf("  reward per step      %.4f\n", f.rewardPerStep);
    return 0;
  }
  if (o.sweep) {
    std::vector<robot::SkillCommand> commands;
    for (double vx : {-0.6, -0.3, 0.3, 0.6, 0.9, 1.2, 1.5, 2.0}) commands.push_back({vx, 0, 0});
    for (double vy : {-0.4, 0.4}) commands.push_back({0, vy, 0});
    for (double wz : {-1.0, 1.0}) commands.push_back({0, 0, wz});
    commands.push_back({0, 0, 0});
    for (double vx : {0.3, 0.6, 1.0})
      for (double wz : {0.3, 0.6, -0.6}) commands.push_back({vx, 0, wz});
    std::printf("%s speed sweep: each command held 10 s, no pushes, friction 1 (model %s)\n", o.skill.c_str(),
                onnxPath.c_str());
    std::printf("  %6s %6s %6s   %7s %7s %7s   %s\n", "vx_cmd", "vy_cmd", "wz_cmd", "vx", "vy", "wz", "fall");
    for (const ai::SweepRow& r : ai::runSpeedSweep(l.model, *l.skill, act, commands, 10.0, o.threads)) {
      char fall[32] = "no";
      if (r.fell) std::snprintf(fall, sizeof fall, "at %.2f s", r.secondsUp);
      std::printf("  %6.2f %6.2f %6.2f   %7.3f %7.3f %7.3f   %s\n", r.command.vx, r.command.vy, r.command.wz,
                  r.mean.x(), r.mean.y(), r.mean.z(), fall);
    }
    return 0;
  }
  ai::CardRun run{def, o.seed, o.threads, &comm};
  if (o.episodes > 0) run.card.episodes = o.episodes;
  if (o.steer >= 0) {
    if (ai::StairsCard* stairs = run.card.as<ai::StairsCard>())
      stairs->steer = o.steer;
    else if (ai::CrawlCard* crawl = run.card.as<ai::CrawlCard>())
      crawl->steer = o.steer;
    else
      throw engine::Error("eval --steer: skill '" + o.skill + "' has neither a stairs nor a crawl card");
  }
  const std::string hash = policy ? engine::toHex(ai::onnxFileHash(onnxPath)) : "-";
  const PrintedCard card = printCard(l, act, run, onnxPath, hash);
  const std::string& text = card.text;
  const ai::CardResult& r = card.result;
  // the shipped model's card with the card's own episodes and seed is kept next to it (for `treelearn tree`);
  // a record of the same model file must come out identical: training other skills never changes a skill
  if (policy && o.model.empty() && o.episodes == 0 && o.seed == 1 && comm.isRoot()) {
    const std::string record = cardRecordPath(l.tree, *l.skill);
    const bool same = std::filesystem::exists(record) &&
                      engine::readFile(record).find(engine::toHex(ai::onnxFileHash(onnxPath))) != std::string::npos;
    if (same && engine::readFile(record) != text) {
      std::printf("  RETENTION FAILED: the card differs from the one recorded for this model in %s\n", record.c_str());
      return 1;
    }
    if (same)
      std::printf("  identical to the card recorded for this model in %s\n", record.c_str());
    else
      engine::writeFileAtomic(record, text), std::printf("  recorded in %s\n", record.c_str());
  }
  return r.pass ? 0 : 1;
}

int runShip(const ShipOptions& o) {
  namespace fs = std::filesystem;
  const ai::SkillContext l = ai::loadSkillContext(o.skill);
  const ai::SkillSpec& skill = *l.skill;
  const std::string runDir = o.runDir.empty() ? "runs/" + skill.name : o.runDir;
  if (!fs::is_directory(runDir))
    throw engine::Error(runDir + ": no such run folder (`treelearn train " + skill.name + " --run-dir " + runDir +
                        "` makes one)");
  const std::string onnxPath = ai::exportedModelPath(runDir, skill), policyPath = ai::exportedPolicyPath(runDir, skill);
  if (!fs::exists(onnxPath)) {
    std::string others;  // another skill's export in the folder: the wrong run, or the wrong skill named
    for (const auto& e : fs::directory_iterator(runDir))
      if (e.path().extension() == ".onnx") others += (others.empty() ? "" : ", ") + e.path().filename().string();
    throw engine::Error(onnxPath + ": the run folder holds no model of '" + skill.name + "' " +
                        (others.empty() ? "(train exports it when it ends; `treelearn train " + skill.name +
                                              " --export-only --run-dir " + runDir + "` exports the run's best)"
                                        : "but " + others + ": a run of another skill?"));
  }
  if (!fs::exists(policyPath))
    throw engine::Error(policyPath + ": missing next to " + onnxPath + " (a branch starts from it; `treelearn train " +
                        skill.name + " --export-only --run-dir " + runDir + "` exports both)");
  {
    const ai::LoadedPolicy file = ai::loadPolicyOnnx(onnxPath);
    const auto it = file.metadata.find("treelearn.skill");
    if (it != file.metadata.end() && it->second != skill.name)
      throw engine::Error(onnxPath + ": a model of skill '" + it->second + "', not of '" + skill.name + "'");
  }
  const std::unique_ptr<ai::LoadedPolicy> policy = ai::loadSkillModel(l, onnxPath);
  ai::PolicyInfo info;
  const ai::PolicyState state = ai::loadPolicyState(policyPath, &info);
  const auto same = [](const auto& a, const auto& b) { return a.rows() == b.rows() && a.cols() == b.cols() && a == b; };
  bool sameActor = state.actor.layers() == policy->actor.layers() && same(state.normalizer.mean(), policy->obsMean);
  for (int k = 0; sameActor && k < state.actor.layers(); ++k)
    sameActor = same(state.actor.W[k], policy->actor.W[k]) && same(state.actor.b[k], policy->actor.b[k]);
  if (!sameActor)
    throw engine::Error(policyPath + " and " + onnxPath +
                        " hold different policies (not one export): export the run again");

  const std::string installedOnnx = l.tree.directory + "/" + skill.model;
  const std::string installedPolicy = l.tree.directory + "/" + skill.name + ".policy.bin";
  const std::string hash = engine::toHex(ai::onnxFileHash(onnxPath));
  char score[64] = "no card score";
  if (!std::isnan(info.score)) std::snprintf(score, sizeof score, "training card score %.3f", info.score);
  std::printf("shipping %s (hash %s; iteration %lld, %lld env steps, %s) as %s, if its report card passes:\n",
              onnxPath.c_str(), hash.c_str(), (long long)info.iteration, (long long)info.envSteps, score,
              installedOnnx.c_str());
  std::string record;  // the card as `eval` records it for the installed model
  if (skill.card.kind() == ai::CardKind::None) {
    if (!o.force)
      throw engine::Error(l.tree.path + ": skill '" + skill.name + "' has no [skill." + skill.name +
                          ".card] table, so its model cannot be judged (ship --force installs it without a card)");
    std::printf("  no report card for '%s': installed without one (--force)\n", skill.name.c_str());
  } else {
    const PrintedCard card = printCard(
        l, [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) { policy->act(obs, act); },
        ai::CardRun{skill.card, 1, o.threads}, installedOnnx, hash);
    if (!card.result.pass) {
      std::string failed;
      for (const ai::CardFigure& f : card.result.figures)
        if (f.bar[0] != '(' && !f.pass) {
          char b[256];
          std::snprintf(b, sizeof b, "%s%s %.3f, bar %s", failed.empty() ? "" : "; ", f.name.c_str(), f.value,
                        f.bar.c_str());
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
  engine::writeFileAtomic(installedPolicy, engine::readFile(policyPath, engine::kMaxModelFileBytes));
  engine::writeFileAtomic(installedOnnx, engine::readFile(onnxPath, engine::kMaxModelFileBytes));
  if (!record.empty()) engine::writeFileAtomic(cardRecordPath(l.tree, skill), record);
  std::printf("shipped %s and %s%s\n", installedOnnx.c_str(), installedPolicy.c_str(),
              record.empty() ? "" : (", card recorded in " + cardRecordPath(l.tree, skill)).c_str());
  return 0;
}

int runEvalAll(const EvalOptions& o) {
  if (o.priorOnly || o.sweep || !o.model.empty())
    throw engine::Error(
        "eval all runs every shipped model's card and the switches: it takes no --prior-only, --sweep or --model");
  const robot::RobotModel model = robot::loadRobotModel(engine::projectFile("assets/robots/g1_23dof.toml"));
  const ai::TrainingTree tree = ai::loadTrainingTree(robot::defaultSkillTreePath(), model);
  std::vector<std::pair<std::string, std::string>> results;
  int connected = 0;
  for (const ai::SkillSpec& s : tree.skills) {
    const bool hasModel = std::filesystem::exists(tree.directory + "/" + s.model);
    connected +=
        hasModel && !s.parent.empty() && std::filesystem::exists(tree.directory + "/" + tree.find(s.parent)->model);
    if (!hasModel) {
      results.push_back({s.name, "FAIL (no model: treelearn train " + s.name + ")"});
      continue;
    }
    if (s.card.kind() == ai::CardKind::None) {
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
