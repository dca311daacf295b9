// skill_metadata_test.cpp — a skill file records its controller, and a model that no longer fits its
// tree entry is refused with a message naming both files and the setting.
#include "ai/onnx/skill_metadata.h"

#include <gtest/gtest.h>

#include "engine/core/error.h"
#include "engine/core/hash.h"
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

// the message a check throws, "" if it passes
std::string refusal(const ai::LoadedPolicy& p, const robot::SkillDef& skill, const robot::RobotModel& model) {
  try {
    ai::checkModelMatchesSkill(p, "walk.onnx", model, skill, "tree.toml");
  } catch (const engine::Error& e) {
    return e.what();
  }
  return "";
}

TEST(SkillMetadata, AModelWithoutAnIdentifyingKeyIsRefusedNamingTheKey) {
  Fixture f;
  for (const char* key : {"treelearn.skill", "treelearn.robot_hash", "treelearn.action_filter", "treelearn.kp"}) {
    ai::LoadedPolicy p = f.policyFor(f.walk);
    p.metadata.erase(key);
    const std::string m = refusal(p, f.walk, fixtures::robotModel());
    EXPECT_NE(m.find(std::string("walk.onnx: metadata key '") + key + "' is missing"), std::string::npos) << m;
  }
  // all metadata stripped
  EXPECT_NE(refusal(ai::LoadedPolicy{}, f.walk, fixtures::robotModel()).find("is missing"), std::string::npos);
}

TEST(SkillMetadata, AnotherSkillsModelIsRefused) {
  Fixture f;
  const std::string m = refusal(f.policyFor(*f.tree.find("run")), f.walk, fixtures::robotModel());
  EXPECT_NE(m.find("walk.onnx: is the model of skill 'run', but tree.toml gives it to 'walk'"), std::string::npos) << m;
}

TEST(SkillMetadata, AModelOfAnotherRobotIsRefused) {
  Fixture f;
  robot::RobotModel other = fixtures::robotModel();
  other.hash ^= 1;  // another URDF or robot file
  const std::string m = refusal(f.policyFor(f.walk), f.walk, other);
  EXPECT_NE(m.find("walk.onnx: skill 'walk' was trained for robot model " + engine::toHex(fixtures::robotModel().hash)),
            std::string::npos)
      << m;
}

}  // namespace
