// experiment.cpp — `treelearn experiment compare`: the paper's §4 comparison, resumably (docs/comparison.md). The
// tree arm trains each of the six skills from its parent's shipped weights (the walk from scratch) with `train`'s
// defaults; the multi-task arm trains one network on all six from scratch at the paper's budget and at the tree's
// total, and from the walk's shipped weights at the paper's budget. Every run goes on from its checkpoint when the
// command is given again, and a finished run is not run again; then every final policy is measured the same way (its
// rewards in the skill's own training episodes and its report card) into OUT/results.csv, a row per arm, seed and
// skill, rows already there kept.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "ai/env/multi_task_env.h"
#include "ai/eval/skill_card.h"
#include "ai/onnx/policy_onnx.h"
#include "ai/ppo/checkpoint.h"
#include "ai/ppo/gaussian.h"
#include "ai/ppo/ppo_config.h"
#include "ai/train/train_multi.h"
#include "ai/train/train_skill.h"
#include "apps/commands.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "game/switch_matrix.h"
#include "levels/level.h"

namespace apps {
namespace {

namespace fs = std::filesystem;

constexpr const char* kResultsHeader =
    "arm,seed,skill,env_steps,episodes,mean_episode_return,reward_per_step,fell_share,card_score,card_pass\n";
// after stage N of the paper's order (walk, run, squat, jump, crawl, one_leg), the card of a skill learnt so far:
// on the sequential arm's one network (forgetting) or on the tree's own model of the skill (retention)
constexpr const char* kMatricesHeader = "arm,seed,stage,skill,stage_skill,card_score,card_pass\n";
// the tree arm's switch matrix: every allowed switch into or out of one of the six, on levels/flat as `eval switches`
constexpr const char* kSwitchesHeader = "arm,seed,from,to,trials,success_percent,worst_latency_ticks\n";

// the multi-task arms: from scratch at 1x and 6x the paper's steps in all, and from the walk's weights at 1x
const std::vector<std::string>& multiTaskArms() {
  static const std::vector<std::string> arms = {"multitask1x", "multitask6x", "multitaskwalk"};
  return arms;
}

void printLine(const std::string& line) {
  std::fputs(line.c_str(), stdout);
  std::fflush(stdout);
}

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

// the rows of a results file by their key (its first `keyColumns` columns)
std::map<std::string, std::string> readRows(const std::string& path, const char* header, int keyColumns) {
  std::map<std::string, std::string> rows;
  std::istringstream in(std::filesystem::exists(path) ? engine::readFile(path, engine::kMaxDataFileBytes) : "");
  std::string line;
  if (!in || !std::getline(in, line)) return rows;
  if (line + "\n" != header) throw engine::Error(path + ":1: columns differ from this build's; move the old file away");
  while (std::getline(in, line)) {
    size_t comma = 0;
    for (int i = 0; i < keyColumns && comma != std::string::npos; ++i) comma = line.find(',', i ? comma + 1 : 0);
    if (comma != std::string::npos) rows[line.substr(0, comma)] = line;
  }
  return rows;
}

void writeRows(const std::string& path, const char* header, const std::map<std::string, std::string>& rows) {
  std::string text = header;
  for (const auto& [key, row] : rows) text += row + "\n";
  engine::writeFileAtomic(path, text);
}

// a card and the rewards measure of one policy acting as `l`'s skill
struct Measured {
  ai::RewardFigures rewards;
  ai::CardResult card;
};
ai::CardResult cardOf(const ai::SkillContext& l, const ai::PolicyFn& act, const ExperimentOptions& o) {
  ai::CardRun card{l.skill->card, 1, o.threads};
  if (o.cardEpisodes > 0) card.card.episodes = o.cardEpisodes;
  return ai::runSkillCard(l, act, card, ai::loadCardDrivers(l, l.tree.directory));
}
Measured measure(const ai::SkillContext& l, const ai::PolicyFn& act, int seed, const ExperimentOptions& o) {
  return {ai::measureRewards(l, act, l.tree.directory, o.rewardEnvs, o.rewardRollouts, uint64_t(seed), o.threads,
                             [](const std::string&) {}),
          cardOf(l, act, o)};
}

// a policy file's network acting deterministically (the sequential arm's, under any skill's controller)
ai::PolicyFn policyActor(std::shared_ptr<const ai::PolicyState> p) {
  return [p](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) { ai::actDeterministic(*p, obs, a); };
}

}  // namespace

int runExperimentCompare(const ExperimentOptions& o) {
  if (!(o.stepsScale > 0) || !std::isfinite(o.stepsScale))
    throw engine::Error("--steps-scale must be a positive number");
  const std::vector<std::string>& skills = ai::paperComparisonSkills();
  const int64_t budget = std::max<int64_t>(1, std::llround(1e7 * o.stepsScale));  // per skill
  engine::makeDirectories(o.out);
  const std::string resultsPath = o.out + "/results.csv", matrixPath = o.out + "/matrices.csv",
                    switchesPath = o.out + "/switches.csv";
  std::map<std::string, std::string> results = readRows(resultsPath, kResultsHeader, 3);
  std::map<std::string, std::string> matrices = readRows(matrixPath, kMatricesHeader, 4);
  std::map<std::string, std::string> switches = readRows(switchesPath, kSwitchesHeader, 4);
  std::printf("the comparison in %s: %lld steps per skill (--steps-scale %g), seeds 1-%d\n", o.out.c_str(),
              (long long)budget, o.stepsScale, o.seeds);
  // each skill's tree entry and robot, read once (a context's skill points into its own tree: moved, never copied)
  std::map<std::string, ai::SkillContext> contexts;
  for (const std::string& skill : skills) contexts.emplace(skill, ai::loadSkillContext(skill));
  auto context = [&](const std::string& skill) -> const ai::SkillContext& { return contexts.at(skill); };
  const ai::SkillContext& root = context(skills.front());
  const double branchRate =
      ai::parsePpoConfig(engine::readFile(root.tree.path), root.tree.path, "ppo").branchLearningRate;

  for (int seed = 1; seed <= o.seeds; ++seed) {
    const std::string seedDir = "seed" + std::to_string(seed);
    auto treeRun = [&](const std::string& skill) { return o.out + "/tree/" + seedDir + "/" + skill; };
    // the sequential arm's stage k (from 0): its first is the tree arm's walk (the same run), then one network on
    auto stageRun = [&](size_t k) {
      return k == 0 ? treeRun(skills[0])
                    : o.out + "/sequential/" + seedDir + "/" + std::to_string(k + 1) + "_" + skills[k];
    };
    auto train = [&](const std::string& what, const ai::SkillContext& l, ai::TrainSkillOptions t) {
      if (fs::exists(ai::exportedPolicyPath(t.runDir, *l.skill))) {
        std::printf("%s, seed %d: done (%s)\n", what.c_str(), seed, t.runDir.c_str());
        return true;
      }
      t.resume = fs::exists(t.runDir + "/checkpoint.bin");
      std::printf("%s, seed %d: %s\n", what.c_str(), seed, t.resume ? "resumed" : "started");
      return !ai::trainSkill(l, t, printLine).stopped;
    };
    auto options = [&](const std::string& runDir) {
      ai::TrainSkillOptions t;
      t.steps = budget;
      t.seed = uint64_t(seed);
      t.threads = o.threads;
      t.runDir = runDir;
      t.evalEvery = 0;  // the final policy, as the multi-task arm's
      return t;
    };
    // the tree arm: each skill from its parent's shipped weights, as `train SKILL` trains it
    for (const std::string& skill : skills) {
      const ai::SkillContext& l = context(skill);
      ai::TrainSkillOptions t = options(treeRun(skill));
      t.linearRate = l.skill->parent.empty();  // from scratch, as the paper's and the multi-task arm's
      if (!train("tree arm, " + skill, l, t)) return 130;
    }
    // the sequential arm: one network, each skill in turn from the one before it, started as a branch is
    for (size_t k = 1; k < skills.size(); ++k) {
      const ai::SkillContext& l = context(skills[k]);
      ai::TrainSkillOptions t = options(stageRun(k));
      const ai::SkillContext& before = context(skills[k - 1]);
      t.initFrom = ai::exportedPolicyPath(stageRun(k - 1), *before.skill);
      t.initAsBranch = true;
      t.learningRate = branchRate;
      if (!train("sequential arm, stage " + std::to_string(k + 1) + " " + skills[k], l, t)) return 130;
    }
    // the multi-task arm, from scratch at the paper's budget (every skill's steps together) and at the tree arm's
    // total, and from the walk's shipped weights at the paper's budget (inheritance without isolation)
    for (const std::string& arm : multiTaskArms()) {
      const int times = arm == "multitask6x" ? int(skills.size()) : 1;
      ai::TrainMultiOptions m;
      m.steps = budget * times;
      m.seed = uint64_t(seed);
      m.threads = o.threads;
      m.runDir = o.out + "/" + arm + "/" + seedDir;
      if (arm == "multitaskwalk") m.initFrom = engine::projectFile("assets/skills/walk.policy.bin");
      if (fs::exists(m.runDir + "/multitask.policy.bin")) {
        std::printf("%s arm, seed %d: done (%s)\n", arm.c_str(), seed, m.runDir.c_str());
        continue;
      }
      m.resume = fs::exists(m.runDir + "/checkpoint.bin");
      if (ai::trainMultiTask(m, printLine).stopped) return 130;
    }

    // the measures, the same for every arm: the final policies into results.csv
    std::vector<std::string> arms = {"tree", "sequential"};
    for (const std::string& arm : multiTaskArms()) arms.push_back(arm);
    for (const std::string& arm : arms) {
      std::shared_ptr<ai::MultiTaskPolicy> multi;
      if (arm.rfind("multitask", 0) == 0)
        multi = std::make_shared<ai::MultiTaskPolicy>(ai::loadMultiTaskPolicy(o.out + "/" + arm + "/" + seedDir));
      std::shared_ptr<const ai::PolicyState> last;  // the sequential arm's network after its last stage
      if (arm == "sequential") {
        const ai::SkillContext& l = context(skills.back());
        last = std::make_shared<ai::PolicyState>(
            ai::loadPolicyState(ai::exportedPolicyPath(stageRun(skills.size() - 1), *l.skill)));
      }
      for (const std::string& skill : skills) {
        const std::string key = arm + "," + std::to_string(seed) + "," + skill;
        if (results.count(key)) continue;
        const ai::SkillContext& l = context(skill);
        std::shared_ptr<ai::LoadedPolicy> model;
        ai::PolicyFn act;
        int64_t steps = budget;
        if (multi) {
          const int index = multi->indexOf(skill, o.out + "/" + arm + "/" + seedDir);
          steps = arm == "multitask6x" ? budget : budget / int64_t(skills.size());
          act = [multi, index](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) {
            ai::actDeterministic(multi->policy, ai::MultiTaskEnv::withTask(obs, index, int(multi->skills.size())), a);
          };
        } else if (last) {
          act = policyActor(last);
        } else {
          model = ai::loadSkillModel(l, ai::exportedModelPath(treeRun(skill), *l.skill));
          act = [model](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) { model->act(obs, a); };
        }
        const Measured m = measure(l, act, seed, o);
        const ai::RewardFigures& f = m.rewards;
        results[key] = key + "," + std::to_string(steps) + "," + std::to_string(f.episodes) + "," + fmt(f.meanReturn) +
                       "," + fmt(f.rewardPerStep) + "," + fmt(f.fellShare) + "," + fmt(m.card.score) + "," +
                       (m.card.pass ? "1" : "0");
        writeRows(resultsPath, kResultsHeader, results);  // after every row: a stop loses at most the one measured
        std::printf("%-13s seed %d %-8s return %8.1f  reward/step %.3f  fell %3.0f %%  card %s\n", arm.c_str(), seed,
                    skill.c_str(), f.meanReturn, f.rewardPerStep, 100 * f.fellShare, m.card.pass ? "PASS" : "fail");
      }
    }
    // after each stage k, the cards of the skills learnt so far: on the sequential arm's one network (forgetting)
    // and on the tree's own models (retention)
    for (size_t k = 0; k < skills.size(); ++k) {
      const ai::SkillContext& stageSkill = context(skills[k]);
      const auto network = std::make_shared<const ai::PolicyState>(
          ai::loadPolicyState(ai::exportedPolicyPath(stageRun(k), *stageSkill.skill)));
      for (size_t j = 0; j <= k; ++j) {
        const ai::SkillContext& l = context(skills[j]);
        for (const std::string& arm : {std::string("sequential"), std::string("tree")}) {
          const std::string key =
              std::string(arm) + "," + std::to_string(seed) + "," + std::to_string(k + 1) + "," + skills[j];
          if (matrices.count(key)) continue;
          std::shared_ptr<ai::LoadedPolicy> model;
          ai::PolicyFn act = policyActor(network);
          if (arm == "tree") {
            model = ai::loadSkillModel(l, ai::exportedModelPath(treeRun(skills[j]), *l.skill));
            act = [model](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) { model->act(obs, a); };
          }
          const ai::CardResult c = cardOf(l, act, o);
          matrices[key] = key + "," + skills[k] + "," + fmt(c.score) + "," + (c.pass ? "1" : "0");
          writeRows(matrixPath, kMatricesHeader, matrices);
          std::printf("%-10s seed %d after stage %zu (%s): %-8s card %s, score %.3f\n", arm.c_str(), seed, k + 1,
                      skills[k].c_str(), skills[j].c_str(), c.pass ? "PASS" : "fail", c.score);
        }
      }
    }
    // the tree arm's switch matrix: its six models in place of the shipped ones (the other skills' shipped models
    // drive the rest of a trial, such as prone before the crawl); measured at once, so one row stands for all
    const std::string seedKey = "tree," + std::to_string(seed) + ",";
    const auto have = switches.lower_bound(seedKey);
    if (have == switches.end() || have->first.compare(0, seedKey.size(), seedKey) != 0) {
      std::map<std::string, std::string> models;
      for (const std::string& skill : skills)
        models[skill] = ai::exportedModelPath(treeRun(skill), *context(skill).skill);
      const robot::SkillSet set = loadSkills(root.model, models);
      game::SwitchMatrixOptions so;
      so.trials = o.switchTrials;
      so.seed = uint64_t(seed);
      so.threads = o.threads;
      so.anyOf = skills;
      const game::SwitchMatrix sm =
          game::runSwitchMatrix(levels::loadLevel(engine::projectFile("levels/flat")), root.model, set, so);
      for (const game::SwitchRow& row : sm.rows) {
        double latency = 0;
        for (const game::SwitchTrial& t : row.trials) latency = std::max(latency, t.switched ? t.latencyTicks : 0.0);
        const std::string key = seedKey + row.from->def.name + "," + row.to->def.name;
        switches[key] =
            key + "," + std::to_string(row.trials.size()) + "," + fmt(row.successPercent()) + "," + fmt(latency);
        std::printf("tree arm, seed %d: switch %s -> %s %3.0f %% of %zu trials\n", seed, row.from->def.name.c_str(),
                    row.to->def.name.c_str(), row.successPercent(), row.trials.size());
      }
      writeRows(switchesPath, kSwitchesHeader, switches);
    }
  }
  std::printf("results: %s, %s and %s; figures: python3 scripts/compare_figures.py %s\n", resultsPath.c_str(),
              matrixPath.c_str(), switchesPath.c_str(), o.out.c_str());
  return 0;
}

}  // namespace apps
