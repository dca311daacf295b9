// multitask_cli_test.cpp — `treelearn multitask` end to end on a tiny budget (slow: it trains): the files it writes,
// each skill's rows per iteration, a resumed run that writes each iteration once, and a card run on its network.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "engine/core/file_io.h"
#include "tests/cli_run.h"

namespace {

using cli::CliRun;
using cli::run;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

TEST(MultiTaskCli, ATinyRunWritesItsNetworkSkillsAndPerSkillRowsAndResumesWithoutRepeatingThem) {
  const std::string dir = cli::tempDir("multitask", "tiny");
  // two skills, one environment each: 2 x 1024 steps an iteration; 2048 steps is one iteration, then resumed to two
  const CliRun first = run("multitask --skills walk squat --envs-per-skill 1 --steps 2048 --run-dir " + dir);
  ASSERT_EQ(first.code, 0) << first.out;
  EXPECT_NE(first.out.find("training one network on 2 skills"), std::string::npos) << first.out;
  EXPECT_EQ(engine::readFile(dir + "/skills.txt"), "walk\nsquat\n");
  const CliRun second = run("multitask --skills walk squat --envs-per-skill 1 --steps 4096 --resume --run-dir " + dir);
  ASSERT_EQ(second.code, 0) << second.out;
  const std::vector<std::string> rows = lines(engine::readFile(dir + "/skills.csv"));
  ASSERT_EQ(rows.size(), 5u) << engine::readFile(dir + "/skills.csv");  // a header, then 2 skills x 2 iterations
  EXPECT_EQ(rows[0].rfind("iteration,env_steps,skill,episodes,", 0), 0u);
  EXPECT_EQ(rows[1].rfind("1,2048,walk,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[2].rfind("1,2048,squat,", 0), 0u) << rows[2];
  EXPECT_EQ(rows[3].rfind("2,4096,walk,", 0), 0u) << rows[3];
  EXPECT_EQ(rows[4].rfind("2,4096,squat,", 0), 0u) << rows[4];
  EXPECT_TRUE(std::filesystem::exists(dir + "/multitask.policy.bin"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/log.csv"));
  // the card of the network as the squat (its one-hot), on one episode: it runs and gives its figures
  const CliRun card = run("eval squat --multitask " + dir + " --episodes 1");
  EXPECT_NE(card.out.find("one-hot 'squat'"), std::string::npos) << card.out;
  EXPECT_NE(card.out.find("episodes without a fall"), std::string::npos) << card.out;
  // a skill the run was not trained on is refused with the run's skills
  const CliRun other = run("eval run --multitask " + dir);
  EXPECT_EQ(other.code, 2) << other.out;
  EXPECT_NE(other.out.find("has no skill 'run' (it has walk, squat)"), std::string::npos) << other.out;
}

TEST(MultiTaskCli, ASkillGivenTwiceIsRefused) {
  const CliRun r = run("multitask --skills walk walk --steps 10 --run-dir " + cli::tempDir("multitask", "twice"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("skill 'walk' is given twice"), std::string::npos) << r.out;
}

}  // namespace
