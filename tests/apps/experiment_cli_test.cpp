// experiment_cli_test.cpp — `treelearn experiment compare` at a thousandth of the paper's budget (slow: it trains
// every arm): every run, result row and figure is written, and given again it trains nothing and keeps its rows.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "engine/core/file_io.h"
#include "tests/cli_run.h"

namespace {

namespace fs = std::filesystem;
using cli::CliRun;
using cli::run;
using cli::shell;

const char* kSkills[] = {"walk", "run", "squat", "jump", "crawl", "one_leg"};

TEST(ExperimentCli, ASmokeComparisonWritesEveryArmsRunResultsAndFiguresAndResumesToNothingLeft) {
  const std::string dir = cli::tempDir("experiment", "smoke");
  const std::string args =
      "experiment compare --out " + dir +
      " --steps-scale 0.001 --reward-envs 2 --reward-rollouts 1 --card-episodes 1 --switch-trials 1";
  const CliRun first = run(args);
  ASSERT_EQ(first.code, 0) << first.out;
  for (const char* skill : kSkills) {
    EXPECT_TRUE(fs::exists(dir + "/tree/seed1/" + skill + "/" + skill + ".policy.bin")) << skill;
    EXPECT_TRUE(fs::exists(dir + "/tree/seed1/" + skill + "/log.csv")) << skill;
  }
  for (int stage = 2; stage <= 6; ++stage) {  // the sequential arm: stage 1 is the tree arm's walk
    const std::string skill = kSkills[stage - 1];
    EXPECT_TRUE(
        fs::exists(dir + "/sequential/seed1/" + std::to_string(stage) + "_" + skill + "/" + skill + ".policy.bin"))
        << stage;
  }
  for (const char* arm : {"multitask1x", "multitask6x", "multitaskwalk"}) {
    EXPECT_TRUE(fs::exists(dir + "/" + arm + "/seed1/multitask.policy.bin")) << arm;
    EXPECT_TRUE(fs::exists(dir + "/" + arm + "/seed1/skills.csv")) << arm;
  }
  // 5 arms x 6 skills, each with its measures
  const std::string results = engine::readFile(dir + "/results.csv");
  std::vector<std::string> rows;
  std::istringstream in(results);
  for (std::string l; std::getline(in, l);) rows.push_back(l);
  ASSERT_EQ(rows.size(), 31u) << results;
  EXPECT_EQ(rows[0],
            "arm,seed,skill,env_steps,episodes,mean_episode_return,reward_per_step,fell_share,card_score,"
            "card_pass");
  for (const char* arm : {"tree,1,", "sequential,1,", "multitask1x,1,", "multitask6x,1,", "multitaskwalk,1,"})
    for (const char* skill : kSkills)
      EXPECT_NE(results.find(std::string(arm) + skill + ","), std::string::npos) << arm << skill;
  // after stage N, the cards of the N skills learnt so far, on the sequential network and on the tree's models:
  // 2 x (1 + 2 + ... + 6) rows; the tree's card of a skill is the same at every stage (its model never changes)
  const std::string matrices = engine::readFile(dir + "/matrices.csv");
  std::vector<std::string> cells;
  std::istringstream m(matrices);
  for (std::string l; std::getline(m, l);) cells.push_back(l);
  ASSERT_EQ(cells.size(), 43u) << matrices;
  EXPECT_EQ(cells[0], "arm,seed,stage,skill,stage_skill,card_score,card_pass");
  auto row = [&](const std::string& key) {
    for (const std::string& l : cells)
      if (l.rfind(key + ",", 0) == 0) return l.substr(key.size() + 1);
    return std::string("missing " + key);
  };
  EXPECT_EQ(row("tree,1,6,walk").substr(row("tree,1,6,walk").find(',')),
            row("tree,1,1,walk").substr(row("tree,1,1,walk").find(',')));  // retention: the same card
  EXPECT_EQ(row("sequential,1,6,one_leg").rfind("one_leg,", 0), 0u);
  // the tree arm's switch matrix: the switches into or out of the six, one trial each here; none between two others
  const std::string switches = engine::readFile(dir + "/switches.csv");
  EXPECT_EQ(switches.rfind("arm,seed,from,to,trials,success_percent,worst_latency_ticks\n", 0), 0u) << switches;
  for (const char* pair : {"walk,run", "run,walk", "squat,jump", "jump,squat", "prone,crawl", "walk,one_leg"})
    EXPECT_NE(switches.find(std::string("\ntree,1,") + pair + ",1,"), std::string::npos) << pair << "\n" << switches;
  EXPECT_EQ(switches.find("tree,1,prone,pushup,"), std::string::npos) << switches;
  // given again: every run is done and every row there, so nothing is trained or measured again
  const CliRun again = run(args);
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_EQ(again.out.find("training "), std::string::npos) << again.out;
  EXPECT_NE(again.out.find("tree arm, one_leg, seed 1: done"), std::string::npos) << again.out;
  EXPECT_EQ(engine::readFile(dir + "/results.csv"), results);
  EXPECT_EQ(engine::readFile(dir + "/matrices.csv"), matrices);
  EXPECT_EQ(engine::readFile(dir + "/switches.csv"), switches);
  // the figures
  const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  if (shell(python + " -c 'import matplotlib'").code != 0)
    GTEST_SKIP() << "matplotlib is missing (Debian: apt-get install python3-matplotlib, in scripts/setup.sh)";
  const CliRun figures = shell(python + " scripts/compare_figures.py " + dir);
  ASSERT_EQ(figures.code, 0) << figures.out;
  for (const std::string name : {"radar", "cards", "reward_walk", "reward_one_leg", "forgetting", "retention"}) {
    const std::string png = engine::readFile(dir + "/figures/" + name + ".png");
    EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << name;
  }
}

}  // namespace
