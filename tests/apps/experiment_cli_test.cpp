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
      "experiment compare --out " + dir + " --steps-scale 0.001 --reward-envs 2 --reward-rollouts 1 --card-episodes 1";
  const CliRun first = run(args);
  ASSERT_EQ(first.code, 0) << first.out;
  for (const char* skill : kSkills) {
    EXPECT_TRUE(fs::exists(dir + "/tree/seed1/" + skill + "/" + skill + ".policy.bin")) << skill;
    EXPECT_TRUE(fs::exists(dir + "/tree/seed1/" + skill + "/log.csv")) << skill;
  }
  for (const char* arm : {"multitask1x", "multitask6x", "multitaskwalk"}) {
    EXPECT_TRUE(fs::exists(dir + "/" + arm + "/seed1/multitask.policy.bin")) << arm;
    EXPECT_TRUE(fs::exists(dir + "/" + arm + "/seed1/skills.csv")) << arm;
  }
  // 4 arms x 6 skills, each with its measures
  const std::string results = engine::readFile(dir + "/results.csv");
  std::vector<std::string> rows;
  std::istringstream in(results);
  for (std::string l; std::getline(in, l);) rows.push_back(l);
  ASSERT_EQ(rows.size(), 25u) << results;
  EXPECT_EQ(rows[0],
            "arm,seed,skill,env_steps,episodes,mean_episode_return,reward_per_step,fell_share,card_score,"
            "card_pass");
  for (const char* arm : {"tree,1,", "multitask1x,1,", "multitask6x,1,", "multitaskwalk,1,"})
    for (const char* skill : kSkills)
      EXPECT_NE(results.find(std::string(arm) + skill + ","), std::string::npos) << arm << skill;
  // given again: every run is done and every row there, so nothing is trained or measured again
  const CliRun again = run(args);
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_EQ(again.out.find("training "), std::string::npos) << again.out;
  EXPECT_NE(again.out.find("tree arm, one_leg, seed 1: done"), std::string::npos) << again.out;
  EXPECT_EQ(engine::readFile(dir + "/results.csv"), results);
  // the figures
  const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  if (shell(python + " -c 'import matplotlib'").code != 0)
    GTEST_SKIP() << "matplotlib is missing (Debian: apt-get install python3-matplotlib, in scripts/setup.sh)";
  const CliRun figures = shell(python + " scripts/compare_figures.py " + dir);
  ASSERT_EQ(figures.code, 0) << figures.out;
  for (const std::string name : {"radar", "cards", "reward_walk", "reward_one_leg"}) {
    const std::string png = engine::readFile(dir + "/figures/" + name + ".png");
    EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << name;
  }
}

}  // namespace
