// skill_controller_test.cpp — the phase prior and action mapping, with values worked by hand.
#include "robot/skill_controller.h"

#include <gtest/gtest.h>

#include "tests/fixtures.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>

#include "engine/core/error.h"

namespace {

using fixtures::kSource;

const robot::RobotModel& model() { return fixtures::robotModel(); }

}  // namespace

TEST(PhasePrior, LeftLegPeaksMidFirstHalfThenRightLeg) {
  double u1, u2;
  // T1 = 40: tp = 20 is the middle of the left phase: (1 - cos(pi)) / 2 = 1
  robot::phaseActivation(20, 40, &u1, &u2);
  EXPECT_DOUBLE_EQ(u1, 1.0);
  EXPECT_DOUBLE_EQ(u2, 0.0);
  // tp = 10: (1 - cos(pi/2)) / 2 = 0.5
  robot::phaseActivation(10, 40, &u1, &u2);
  EXPECT_NEAR(u1, 0.5, 1e-12);
  // tp = 60: right leg, (1 - cos(2 pi 20/40)) / 2 = 1
  robot::phaseActivation(60, 40, &u1, &u2);
  EXPECT_DOUBLE_EQ(u1, 0.0);
  EXPECT_DOUBLE_EQ(u2, 1.0);
}

TEST(PhasePrior, ClockWrapsAfterTwoHalfPeriods) {
  robot::PhaseClock c;
  for (int i = 0; i < 80; ++i) c.advance(40);
  EXPECT_EQ(c.tp, 80);
  c.advance(40);
  EXPECT_EQ(c.tp, 1);
}

TEST(SkillController, PriorBendsHipKneeAnkleAsThePaperSays) {
  robot::SkillDef skill;
  skill.prior.kind = robot::PriorDef::Kind::Phase;
  skill.prior.halfPeriodTicks = 40;
  skill.prior.dh = 0.5;
  skill.prior.d0 = 0.1;
  skill.kp.fill(10);
  skill.kd.fill(1);
  skill.actionScale.fill(0.25);
  std::array<float, robot::kActionSize> action{};
  action[12] = 2.0f;  // waist: 0 + 0.25 * 2 = 0.5 rad
  robot::SkillCommand cmd;
  cmd.vx = 0.5;
  robot::PdCommand pd;
  robot::skillPdCommand(model(), skill, action, robot::PhaseClock{20}, cmd, &pd);
  // left leg at its peak: A = 0.5 * 1 + 0.1 = 0.6; right leg: B = 0.1
  EXPECT_NEAR(pd.target[0], -0.1 - 0.6, 1e-12);   // hip pitch
  EXPECT_NEAR(pd.target[3], 0.3 + 1.2, 1e-12);    // knee +2A
  EXPECT_NEAR(pd.target[4], -0.2 - 0.6, 1e-12);   // ankle pitch
  EXPECT_NEAR(pd.target[6], -0.1 - 0.1, 1e-12);   // right hip pitch
  EXPECT_NEAR(pd.target[9], 0.3 + 0.2, 1e-12);
  EXPECT_NEAR(pd.target[12], 0.5, 1e-12);
  // standing still: dh is dropped when every command is zero
  robot::skillPdCommand(model(), skill, action, robot::PhaseClock{20}, robot::SkillCommand{}, &pd);
  EXPECT_NEAR(pd.target[0], -0.1 - 0.1, 1e-12);
}

TEST(SkillController, StandRampFadesTheSteppingOutAndBackInOverItsTicks) {
  robot::SkillDef skill;
  skill.prior.kind = robot::PriorDef::Kind::Phase;
  skill.prior.halfPeriodTicks = 40;
  skill.prior.dh = 0.5;
  skill.prior.standRampTicks = 40;  // 0.4 s
  skill.kp.fill(10);
  skill.kd.fill(1);
  skill.actionScale.fill(0.25);
  const std::array<float, robot::kActionSize> action{};
  robot::SkillCommand walk;
  walk.vx = 0.5;
  robot::PhaseClock clock;
  EXPECT_EQ(clock.gait, 0.0);  // a fresh clock stands
  for (int i = 0; i < 20; ++i) clock.advance(skill.prior, walk);
  EXPECT_NEAR(clock.gait, 0.5, 1e-12);  // 20 of 40 ticks
  // tp = 20 is the left leg's peak: the hip gets -dh x gait = -0.25 on top of its default -0.1
  robot::PdCommand pd;
  robot::skillPdCommand(model(), skill, action, clock, walk, &pd);
  EXPECT_EQ(clock.tp, 20);
  EXPECT_NEAR(pd.target[0], -0.1 - 0.25, 1e-12);
  for (int i = 0; i < 30; ++i) clock.advance(skill.prior, walk);
  EXPECT_DOUBLE_EQ(clock.gait, 1.0);  // saturates
  // a zero command fades the stepping out at the same rate, not in one tick
  for (int i = 0; i < 10; ++i) clock.advance(skill.prior, robot::SkillCommand{});
  EXPECT_NEAR(clock.gait, 0.75, 1e-12);
  for (int i = 0; i < 30; ++i) clock.advance(skill.prior, robot::SkillCommand{});
  EXPECT_NEAR(clock.gait, 0.0, 1e-12);
  robot::skillPdCommand(model(), skill, action, clock, walk, &pd);
  EXPECT_NEAR(pd.target[0], -0.1, 1e-12);  // no stepping left
  // without a ramp the gait follows the command in the tick it changes (the lab's rule)
  skill.prior.standRampTicks = 0;
  clock.advance(skill.prior, walk);
  EXPECT_EQ(clock.gait, 1.0);
}

TEST(SkillController, StrideSwingsTheHipsBackAtLiftOffAndForwardAtTouchDown) {
  robot::SkillDef skill;
  skill.prior.kind = robot::PriorDef::Kind::Phase;
  skill.prior.halfPeriodTicks = 40;
  skill.prior.stride = 0.25;  // rad per m/s
  skill.kp.fill(10);
  skill.kd.fill(1);
  const std::array<float, robot::kActionSize> action{};
  robot::SkillCommand cmd;
  cmd.vx = 0.8;  // swing amplitude 0.2 rad
  robot::PdCommand pd;
  // tp = 0: the left leg lifts off, extended back (+0.2, hip pitch > 0 is backward); the right leg is forward
  robot::skillPdCommand(model(), skill, action, robot::PhaseClock{0}, cmd, &pd);
  EXPECT_NEAR(pd.target[0], -0.1 + 0.2, 1e-12);
  EXPECT_NEAR(pd.target[4], -0.2 - 0.2, 1e-12);  // its ankle compensates: the sole stays level
  EXPECT_NEAR(pd.target[6], -0.1 - 0.2, 1e-12);
  EXPECT_NEAR(pd.target[10], -0.2 + 0.2, 1e-12);
  EXPECT_NEAR(pd.target[13], 0.2, 1e-12);  // no arm swing configured: shoulders at their default
  skill.prior.armSwing = 0.5;             // 0.4 rad at 0.8 m/s: the left arm forward while its leg is back
  robot::skillPdCommand(model(), skill, action, robot::PhaseClock{0}, cmd, &pd);
  EXPECT_NEAR(pd.target[13], 0.2 - 0.4, 1e-12);
  EXPECT_NEAR(pd.target[18], 0.2 + 0.4, 1e-12);
  skill.prior.armSwing = 0.0;
  // tp = T1: the left leg touches down in front (cos(pi) = -1)
  robot::skillPdCommand(model(), skill, action, robot::PhaseClock{40}, cmd, &pd);
  EXPECT_NEAR(pd.target[0], -0.1 - 0.2, 1e-12);
  EXPECT_NEAR(pd.target[6], -0.1 + 0.2, 1e-12);
  // mid-swing the hips pass each other; backwards commands swing the other way
  robot::skillPdCommand(model(), skill, action, robot::PhaseClock{20}, cmd, &pd);
  EXPECT_NEAR(pd.target[0], -0.1, 1e-12);
  cmd.vx = -0.8;
  robot::skillPdCommand(model(), skill, action, robot::PhaseClock{0}, cmd, &pd);
  EXPECT_NEAR(pd.target[0], -0.1 - 0.2, 1e-12);
}

TEST(SkillController, TargetsStayInsideJointLimits) {
  robot::SkillDef skill;
  skill.kp.fill(10);
  skill.actionScale.fill(2.0);
  std::array<float, robot::kActionSize> action;
  action.fill(100.0f);  // clipped to kActionClip = 4 -> 8 rad, then to the limits
  robot::PdCommand pd;
  robot::skillPdCommand(model(), skill, action, robot::PhaseClock{0}, robot::SkillCommand{}, &pd);
  for (size_t j = 0; j < size_t(robot::kNumJoints); ++j) EXPECT_DOUBLE_EQ(pd.target[j], model().joints[j].upper);
}

TEST(SkillTree, ShippedTreeLoadsWithWalkAsRoot) {
  const robot::SkillTree tree = robot::loadSkillTree(kSource + "/assets/skills/tree.toml", model());
  const robot::SkillDef* walk = tree.find("walk");
  ASSERT_NE(walk, nullptr);
  EXPECT_EQ(walk->parent, "");
  EXPECT_EQ(walk->key, 0);
  EXPECT_EQ(walk->prior.kind, robot::PriorDef::Kind::Phase);
  EXPECT_GT(walk->kp[3], 0.0);                   // knee
  EXPECT_DOUBLE_EQ(walk->actionScale[13], 0.0);  // arms are held
  // issue 3's bars are the walk's card
  EXPECT_EQ(walk->card.kind, robot::CardDef::Kind::Velocity);
  EXPECT_EQ(walk->card.episodes, 50);
  EXPECT_DOUBLE_EQ(walk->card.noFallPercent, 95.0);
  EXPECT_DOUBLE_EQ(walk->card.speedError, 0.15);
  EXPECT_DOUBLE_EQ(walk->card.yawError, 0.2);
  EXPECT_DOUBLE_EQ(walk->card.standDrift, 0.2);
}

TEST(SkillTree, BranchInheritsTheControllerTablesItDoesNotWrite) {
  const std::string dir = testing::TempDir() + "/tree_inherit";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/t.toml") << "[skill.walk]\nparent = \"\"\nkey = 0\naction_filter = 0.8\n[skill.walk.rewards]\nlive = 1\n"
                                    "[skill.walk.gains]\nhip_pitch=[300,5]\nhip_roll=[1,1]\nhip_yaw=[1,1]\nknee=[450,8]\n"
                                    "ankle_pitch=[1,1]\nankle_roll=[1,1]\nwaist_yaw=[1,1]\nshoulder_pitch=[1,1]\n"
                                    "shoulder_roll=[1,1]\nshoulder_yaw=[1,1]\nelbow=[1,1]\nwrist_roll=[1,1]\n"
                                    "[skill.walk.action_scale]\nknee = 0.5\n"
                                    "[skill.walk.termination]\nmax_tilt_deg = 25\n"
                                    // 'a' sorts before 'walk', so the file order is not the resolution order
                                    "[skill.a]\nparent = \"walk\"\nkey = 1\naction_filter = 0.5\n[skill.a.rewards]\nlive = 1\n";
  const robot::SkillTree tree = robot::loadSkillTree(dir + "/t.toml", model());
  const robot::SkillDef& a = *tree.find("a");
  EXPECT_DOUBLE_EQ(a.kp[0], 300.0);  // left hip pitch, from walk
  EXPECT_DOUBLE_EQ(a.kd[3], 8.0);    // left knee
  EXPECT_DOUBLE_EQ(a.actionScale[3], 0.5);
  EXPECT_DOUBLE_EQ(a.termination.maxTiltDegrees, 25.0);
  EXPECT_DOUBLE_EQ(a.actionFilter, 0.5);  // its own
}

TEST(SkillTree, BadEntriesAreLocated) {
  const std::string dir = testing::TempDir() + "/tree_bad";
  std::filesystem::create_directories(dir);
  auto errorOf = [&](const std::string& text) -> std::string {
    std::ofstream(dir + "/t.toml") << text;
    try {
      robot::loadSkillTree(dir + "/t.toml", model());
    } catch (const engine::Error& e) {
      return e.what();
    }
    return "";
  };
  const std::string gains = "[skill.walk.gains]\nhip_pitch=[1,1]\nhip_roll=[1,1]\nhip_yaw=[1,1]\nknee=[1,1]\n"
                            "ankle_pitch=[1,1]\nankle_roll=[1,1]\nwaist_yaw=[1,1]\nshoulder_pitch=[1,1]\n"
                            "shoulder_roll=[1,1]\nshoulder_yaw=[1,1]\nelbow=[1,1]\nwrist_roll=[1,1]\n";
  EXPECT_NE(errorOf("[skill.walk]\nparent = \"\"\nkey = 0\nspeed = 3\n").find("t.toml:4: unknown key 'speed'"),
            std::string::npos);
  EXPECT_NE(errorOf("[skill.walk]\nparent = \"\"\nkey = 12\n").find("t.toml:3:"), std::string::npos);
  EXPECT_NE(errorOf("[skill.walk]\nparent = \"\"\nkey = 0\n[skill.walk.gains]\nhips = [1, 1]\n").find("t.toml:5:"),
            std::string::npos);
  EXPECT_NE(errorOf("[skill.walk]\nparent = \"nothing\"\nkey = 0\n[skill.walk.rewards]\nlive = 1\n" + gains)
                .find("unknown parent 'nothing'"),
            std::string::npos);
  const std::string cycle = "[skill.walk]\nparent = \"\"\nkey = 0\n[skill.walk.rewards]\nlive = 1\n" + gains +
                            "[skill.a]\nparent = \"b\"\nkey = 1\n[skill.a.rewards]\nlive = 1\n" +
                            std::regex_replace(gains, std::regex("walk"), "a") +
                            "[skill.b]\nparent = \"a\"\nkey = 2\n[skill.b.rewards]\nlive = 1\n" +
                            std::regex_replace(gains, std::regex("walk"), "b");
  EXPECT_NE(errorOf(cycle).find("cycle"), std::string::npos) << errorOf(cycle);
  const std::string walk = "[skill.walk]\nparent = \"\"\nkey = 0\n[skill.walk.rewards]\nlive = 1\n" + gains;
  const std::string badMix = walk + "[skill.walk.card]\ntype = \"velocity\"\nmix = [0.5, 0.5, 0.5, 0.0]\n";
  EXPECT_NE(errorOf(badMix).find("t.toml:21: skill.walk.card.mix must add up to 1"), std::string::npos) << errorOf(badMix);
  const std::string badType = walk + "[skill.walk.card]\ntype = \"juggling\"\n";
  EXPECT_NE(errorOf(badType).find("t.toml:19: skill.walk.card.type"), std::string::npos) << errorOf(badType);
  const std::string badRamp = walk + "[skill.walk.commands]\nvx = [0, 1]\nramp = 2\n";
  EXPECT_NE(errorOf(badRamp).find("t.toml:21: skill.walk.commands.ramp must be true or false"), std::string::npos)
      << errorOf(badRamp);
  const std::string rootHandover = walk + "[skill.walk.training]\nhandover = 0.5\n";  // the root has no parent
  EXPECT_NE(errorOf(rootHandover).find("t.toml:20: skill.walk.training.handover needs a parent"), std::string::npos)
      << errorOf(rootHandover);
}
