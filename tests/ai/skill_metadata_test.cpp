// skill_metadata_test.cpp — a skill file records its controller, and a model that no longer fits its
// tree entry is refused with a message naming both files and the setting.
#include "ai/onnx/skill_metadata.h"

#include <gtest/gtest.h>

#include "engine/core/error.h"
#include "tests/fixtures.h"

namespace {

struct Fixture {
  robot::SkillTree tree = robot::loadSkillTree(fixtures::kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  const robot::SkillDef& walk = *tree.find("walk");

  ai::LoadedPolicy policyFor(const robot::SkillDef& skill) const {
    ai::LoadedPolicy p;
    for (const auto& [k, v] : ai::skillMetadata(fixtures::robotModel(), skill, 1000, 7)) p.metadata[k] = v;
    return p;
  }
};

TEST(SkillMetadata, ModelTrainedUnderTheSameEntryIsAccepted) {
  Fixture f;
  EXPECT_NO_THROW(
      ai::checkModelMatchesSkill(f.policyFor(f.walk), "walk.onnx", fixtures::robotModel(), f.walk, "tree.toml"));
}

TEST(SkillMetadata, ModelTrainedWithOtherGainsIsRefused) {
  Fixture f;
  robot::SkillDef trainedWith = f.walk;
  trainedWith.kp[0] += 50.0;  // the model was trained under stiffer hips than the tree now says
  try {
    ai::checkModelMatchesSkill(f.policyFor(trainedWith), "walk.onnx", fixtures::robotModel(), f.walk, "tree.toml");
    FAIL() << "a gain mismatch was accepted";
  } catch (const engine::Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("walk.onnx"), std::string::npos) << m;
    EXPECT_NE(m.find("tree.toml"), std::string::npos) << m;
    EXPECT_NE(m.find("treelearn.kp"), std::string::npos) << m;
  }
}

TEST(SkillMetadata, ModelTrainedWithAnotherPriorIsRefused) {
  Fixture f;
  robot::SkillDef trainedWith = f.walk;
  trainedWith.prior.halfPeriodTicks += 5;
  EXPECT_THROW(
      ai::checkModelMatchesSkill(f.policyFor(trainedWith), "walk.onnx", fixtures::robotModel(), f.walk, "tree.toml"),
      engine::Error);
}

TEST(SkillMetadata, OlderFilesWithoutAKeyAreNotComparedOnIt) {
  Fixture f;
  ai::LoadedPolicy p = f.policyFor(f.walk);
  p.metadata.erase("treelearn.action_filter");
  EXPECT_NO_THROW(ai::checkModelMatchesSkill(p, "walk.onnx", fixtures::robotModel(), f.walk, "tree.toml"));
}

}  // namespace
