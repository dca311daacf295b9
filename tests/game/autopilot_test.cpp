// autopilot_test.cpp — the autopilot's decisions from hand-made cues: which skill key it presses when, and
// that it holds W only while the skill should move forward.
#include "game/autopilot.h"

#include <gtest/gtest.h>

namespace {

std::string keys(const std::vector<engine::KeyEvent>& ev) {
  std::string s;
  for (const engine::KeyEvent& e : ev)
    s += std::string(e.action == engine::KeyAction::kTap ? "tap " : e.action == engine::KeyAction::kDown ? "down " : "up ") +
         e.key + ";";
  return s;
}

}  // namespace

TEST(Autopilot, StartsWalkingForward) {
  game::Autopilot a;
  EXPECT_EQ(keys(a.decide(0, {})), "tap 0;down W;");
  EXPECT_EQ(keys(a.decide(1, {})), "");
}

TEST(Autopilot, RunsFromAGhostAndSlowsBeforeTheStairs) {
  game::Autopilot a;
  a.decide(0, {});
  game::Cues c;
  c.ghost = 3.0;
  EXPECT_EQ(keys(a.decide(1, c)), "tap 1;");  // W stays held
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Run);
  c.stepAhead = 1.2;  // stairs coming: back to walk first
  EXPECT_EQ(keys(a.decide(2, c)), "tap 0;");
  c.stepAhead = 0.4;
  EXPECT_EQ(keys(a.decide(3, c)), "tap 2;");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Stairs);
  // on flat ground again for half a metre: walk
  c = {};
  c.x = 10.0;
  EXPECT_EQ(keys(a.decide(4, c)), "");
  c.x = 10.6;
  EXPECT_EQ(keys(a.decide(5, c)), "tap 0;");
}

TEST(Autopilot, LiesDownCrawlsThroughATunnelAndStandsUpAfterIt) {
  game::Autopilot a;
  a.decide(0, {});
  game::Cues c;
  c.ceilingAhead = 0.6;
  EXPECT_EQ(keys(a.decide(1, c)), "tap 7;up W;");
  c.pelvisHeight = 0.3;  // lying
  EXPECT_EQ(keys(a.decide(2, c)), "tap 9;down W;");
  c.ceilingAhead = 1e9;
  c.underCeiling = true;
  c.x = 20.0;
  EXPECT_EQ(keys(a.decide(3, c)), "");
  c.underCeiling = false;
  c.x = 20.3;  // not yet clear by 0.5 m
  EXPECT_EQ(keys(a.decide(4, c)), "");
  c.x = 20.6;
  EXPECT_EQ(keys(a.decide(5, c)), "tap 0;up W;");  // key 0 from crawl is routed through standup
  c.pelvisHeight = 0.75;
  EXPECT_EQ(keys(a.decide(200, c)), "down W;");
}

TEST(Autopilot, JumpsUnderABoxUntilItIsHitThenKicksTheBall) {
  game::Autopilot a;
  a.decide(0, {});
  game::Cues c;
  c.boxOverhead = true;
  EXPECT_EQ(keys(a.decide(1, c)), "tap 4;up W;");
  c.boxJustHit = true;
  EXPECT_EQ(keys(a.decide(50, c)), "tap 0;down W;");
  c = {};
  c.ballAhead = 0.4;
  EXPECT_EQ(keys(a.decide(60, c)), "tap 5;up W;");
  EXPECT_EQ(keys(a.decide(300, c)), "tap 6;");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Kick);
}
