// experiment.cpp — `treelearn experiment compare`: the paper's §4 comparison, resumably (docs/comparison.md). The
// tree arm trains each of the six skills from its parent's shipped weights (the walk from scratch) with `train`'s
// defaults; the multi-task arm trains one network on all six from scratch at the paper's budget and at the tree's
// total, and from the walk's shipped weights at the paper's budget. Every run goes on from its checkpoint when the command is given again, and a finished run is not run
// again; then every final policy is measured the same way (its rewards in the skill's own training episodes and its
// report card) into OUT/results.csv, a row per arm, seed and skill, rows already there kept.
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
#include "ai/ppo/gaussian.h"
#include "ai/train/train_multi.h"
#include "ai/train/train_skill.h"
#include "apps/commands.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"

namespace apps {
namespace {

namespace fs = std::filesystem;

constexpr const char* kResultsHeader =
    "arm,seed,skill,env_steps,episodes,mean_episode_return,reward_per_step,fell_share,card_score,card_pass\n";

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

// the rows of OUT/results.csv by their key "arm,seed,skill"
std::map<std::string, std::string> readResults(const std::string& path) {
  std::map<std::string, std::string> rows;
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line)) return rows;
  if (line + "\n" != kResultsHeader)
    throw engine::Error(path + ":1: columns differ from this build's; move the old results away");
  while (std::getline(in, line)) {
    size_t comma = line.find(',');
    comma = comma == std::string::npos ? comma : line.find(',', comma + 1);
    comma = comma == std::string::npos ? comma : line.find(',', comma + 1);
    if (comma != std::string::npos) rows[line.substr(0, comma)] = line;
  }
  return rows;
}

void writeResults(const std::string& path, const std::map<std::string, std::string>& rows) {
  std::string text = kResultsHeader;
  for (const auto& [key, row] : rows) text += row + "\n";
  engine::writeFileAtomic(path, text);
}

}  // namespace

int runExperimentCompare(const ExperimentOptions& o) {
  if (!(o.stepsScale > 0) || !std::isfinite(o.stepsScale))
    throw engine::Error("--steps-scale must be a positive number");
  const std::vector<std::string>& skills = ai::paperComparisonSkills();
  const int64_t budget = std::max<int64_t>(1, std::llround(1e7 * o.stepsScale));  // per skill
  engine::makeDirectories(o.out);
  const std::string resultsPath = o.out + "/results.csv";
  std::map<std::string, std::string> results = readResults(resultsPath);
  std::printf("the comparison in %s: %lld steps per skill (--steps-scale %g), seeds 1-%d\n", o.out.c_str(),
              (long long)budget, o.stepsScale, o.seeds);

  for (int seed = 1; seed <= o.seeds; ++seed) {
    const std::string seedDir = "seed" + std::to_string(seed);
    // the tree arm: each skill from its parent's shipped weights, as `train SKILL` trains it
    for (const std::string& skill : skills) {
      const ai::SkillContext l = ai::loadSkillContext(skill);
      ai::TrainSkillOptions t;
      t.steps = budget;
      t.seed = uint64_t(seed);
      t.threads = o.threads;
      t.runDir = o.out + "/tree/" + seedDir + "/" + skill;
      t.evalEvery = 0;                         // the final policy, as the multi-task arm's
      t.linearRate = l.skill->parent.empty();  // from scratch, as the paper's and the multi-task arm's
      if (fs::exists(ai::exportedPolicyPath(t.runDir, *l.skill))) {
        std::printf("tree arm, %s, seed %d: done (%s)\n", skill.c_str(), seed, t.runDir.c_str());
        continue;
      }
      t.resume = fs::exists(t.runDir + "/checkpoint.bin");
      std::printf("tree arm, %s, seed %d: %s\n", skill.c_str(), seed, t.resume ? "resumed" : "started");
      if (ai::trainSkill(l, t, printLine).stopped) return 130;
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
    // the measures, the same for every arm
    std::vector<std::string> arms = {"tree"};
    for (const std::string& arm : multiTaskArms()) arms.push_back(arm);
    for (const std::string& arm : arms) {
      std::unique_ptr<ai::MultiTaskPolicy> multi;
      if (arm != "tree")
        multi = std::make_unique<ai::MultiTaskPolicy>(ai::loadMultiTaskPolicy(o.out + "/" + arm + "/" + seedDir));
      for (const std::string& skill : skills) {
        const std::string key = arm + "," + std::to_string(seed) + "," + skill;
        if (results.count(key)) continue;
        const ai::SkillContext l = ai::loadSkillContext(skill);
        std::unique_ptr<ai::LoadedPolicy> model;
        int index = -1;
        int64_t steps = budget;
        if (multi) {
          index = multi->indexOf(skill, o.out + "/" + arm + "/" + seedDir);
          steps = arm == "multitask6x" ? budget : budget / int64_t(skills.size());
        } else {
          model = ai::loadSkillModel(l, ai::exportedModelPath(o.out + "/tree/" + seedDir + "/" + skill, *l.skill));
        }
        const ai::PolicyFn act = [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) {
          if (multi)
            ai::actDeterministic(multi->policy, ai::MultiTaskEnv::withTask(obs, index, int(multi->skills.size())), a);
          else
            model->act(obs, a);
        };
        const ai::RewardFigures f = ai::measureRewards(l, act, l.tree.directory, o.rewardEnvs, o.rewardRollouts,
                                                       uint64_t(seed), o.threads, [](const std::string&) {});
        ai::CardRun card{l.skill->card, 1, o.threads};
        if (o.cardEpisodes > 0) card.card.episodes = o.cardEpisodes;
        const ai::CardResult c = ai::runSkillCard(l, act, card, ai::loadCardDrivers(l, l.tree.directory));
        results[key] = key + "," + std::to_string(steps) + "," + std::to_string(f.episodes) + "," + fmt(f.meanReturn) +
                       "," + fmt(f.rewardPerStep) + "," + fmt(f.fellShare) + "," + fmt(c.score) + "," +
                       (c.pass ? "1" : "0");
        writeResults(resultsPath, results);  // after every row: a stop loses at most the one being measured
        std::printf("%-12s seed %d %-8s return %8.1f  reward/step %.3f  fell %3.0f %%  card %s\n", arm.c_str(), seed,
                    skill.c_str(), f.meanReturn, f.rewardPerStep, 100 * f.fellShare, c.pass ? "PASS" : "fail");
      }
    }
  }
  std::printf("results: %s; figures: python3 scripts/compare_figures.py %s\n", resultsPath.c_str(), o.out.c_str());
  return 0;
}

}  // namespace apps
