// train_skill_test.cpp — training a skill in-process, as `treelearn train` does.
#include "ai/train/train_skill.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "ai/onnx/policy_onnx.h"
#include "tests/fixtures.h"

namespace {

TEST(TrainSkill, OneIterationExportsIntoTheRunFolderAndLeavesTheTreesModelsAlone) {
  const ai::SkillContext walk = ai::loadSkillContext("walk");
  const std::string shipped = walk.tree.directory + "/" + walk.skill->model;
  const uint64_t before = ai::onnxFileHash(shipped);
  const std::string run = testing::TempDir() + "/train_skill_walk";
  std::filesystem::remove_all(run);
  ai::TrainSkillOptions o;
  o.steps = 1;  // one iteration: the PPO buffer's steps
  o.runDir = run;
  o.evalEvery = 0;
  o.threads = 2;
  std::string log;
  const ai::TrainSkillResult r = ai::trainSkill(walk, o, [&](const std::string& line) { log += line; });
  EXPECT_EQ(r.iterationsRun, 1);
  EXPECT_EQ(r.runDir, run);
  EXPECT_NE(log.find("iter 1/1"), std::string::npos) << log;
  EXPECT_NE(log.find("the shipped model in"), std::string::npos) << log;
  ASSERT_TRUE(std::filesystem::exists(ai::exportedModelPath(run, *walk.skill)));
  ai::PolicyInfo info;
  ai::loadPolicyState(ai::exportedPolicyPath(run, *walk.skill), &info);
  EXPECT_EQ(info.iteration, 1);  // the final policy (no evaluation chose a best one)
  EXPECT_GT(info.envSteps, 0);
  EXPECT_EQ(ai::onnxFileHash(shipped), before);
  std::filesystem::remove_all(run);
}

TEST(TrainSkill, AnUnknownSkillIsAnErrorThatListsTheTree) {
  try {
    ai::loadSkillContext("flying");
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("unknown skill 'flying'"), std::string::npos) << e.what();
    for (const char* name : {"walk", "standup", "crawl"})
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

}  // namespace
