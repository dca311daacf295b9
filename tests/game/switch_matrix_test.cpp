// switch_matrix_test.cpp — which switches `eval switches` tries.
#include "game/switch_matrix.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "tests/fixtures.h"

namespace {

robot::SkillSet shippedSet(const std::string& without = "") {
  robot::SkillSet set;
  for (const robot::SkillDef& def :
       robot::loadSkillTree(fixtures::kSource + "/assets/skills/tree.toml", fixtures::robotModel()).skills)
    if (def.name != without) set.skills.push_back({def, {}});
  return set;
}

bool has(const std::vector<std::pair<const robot::Skill*, const robot::Skill*>>& pairs, const std::string& from,
         const std::string& to) {
  return std::any_of(pairs.begin(), pairs.end(),
                     [&](const auto& p) { return p.first->def.name == from && p.second->def.name == to; });
}

TEST(SwitchMatrix, EveryEdgeOfTheTreeIsTriedDownAndOnItsWayUp) {
  const robot::SkillSet set = shippedSet();
  std::vector<std::string> untried;
  const auto pairs = game::switchPairs(set, &untried);
  // six upright branches both ways (12); walk -> prone; prone, pushup and crawl up to the stand-up; the stand-up's
  // parent edge prone -> standup (already there) and its way up to the walk; prone -> pushup, prone -> crawl
  EXPECT_EQ(pairs.size(), 19u);
  EXPECT_TRUE(untried.empty());
  EXPECT_TRUE(has(pairs, "run", "walk"));
  EXPECT_TRUE(has(pairs, "kick", "one_leg"));
  EXPECT_TRUE(has(pairs, "crawl", "standup"));
  EXPECT_TRUE(has(pairs, "standup", "walk"));
  EXPECT_FALSE(has(pairs, "prone", "walk"));  // lying down, the robot goes up through the stand-up
}

TEST(SwitchMatrix, AWayUpWithoutItsModelIsNamedAsUntried) {
  const robot::SkillSet set = shippedSet("standup");
  std::vector<std::string> untried;
  const auto pairs = game::switchPairs(set, &untried);
  EXPECT_FALSE(has(pairs, "crawl", "standup"));
  ASSERT_FALSE(untried.empty());
  EXPECT_NE(untried.front().find("no model for standup"), std::string::npos) << untried.front();
}

}  // namespace
