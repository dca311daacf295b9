// skill_controller_test.cpp — the phase prior and action mapping, with values worked by hand.
#include "robot/skill_controller.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>

#include "engine/core/error.h"
#include "robot/skill_layout.h"
#include "tests/fixtures.h"

namespace {

using fixtures::kSource;

const robot::RobotModel& model() { return fixtures::robotModel(); }

}  // namespace

using fixtures::kWalkGains;

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
  EXPECT_NEAR(pd.target[0], -0.1 - 0.6, 1e-12);  // hip pitch
  EXPECT_NEAR(pd.target[3], 0.3 + 1.2, 1e-12);   // knee +2A
  EXPECT_NEAR(pd.target[4], -0.2 - 0.6, 1e-12);  // ankle pitch
  EXPECT_NEAR(pd.target[6], -0.1 - 0.1, 1e-12);  // right hip pitch
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
  skill.prior.armSwing = 0.5;              // 0.4 rad at 0.8 m/s: the left arm forward while its leg is back
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
}

TEST(SkillTree, BranchInheritsTheControllerTablesItDoesNotWrite) {
  const std::string dir = testing::TempDir() + "/tree_inherit";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/t.toml")
      << "[skill.walk]\nparent = \"\"\nkey = 0\naction_filter = 0.8\n[skill.walk.rewards]\nlive = 1\n"
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

TEST(SkillTree, ATreeNamedWithoutAFolderFindsItsModelsInTheWorkingFolder) {
  // `treelearn --tree t.toml ...` from the tree's own folder: the models are beside it (not at "/walk.onnx")
  const std::string dir = testing::TempDir() + "/tree_bare";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/t.toml") << "[skill.walk]\nparent = \"\"\nkey = 0\n[skill.walk.rewards]\nlive = 1\n"
                                    "[skill.walk.gains]\nhip_pitch=[1,1]\nhip_roll=[1,1]\nhip_yaw=[1,1]\nknee=[1,1]\n"
                                    "ankle_pitch=[1,1]\nankle_roll=[1,1]\nwaist_yaw=[1,1]\nshoulder_pitch=[1,1]\n"
                                    "shoulder_roll=[1,1]\nshoulder_yaw=[1,1]\nelbow=[1,1]\nwrist_roll=[1,1]\n";
  const std::filesystem::path before = std::filesystem::current_path();
  std::filesystem::current_path(dir);
  std::string bare;
  try {
    bare = robot::loadSkillTree("t.toml", model()).directory;
  } catch (...) {
    std::filesystem::current_path(before);
    throw;
  }
  std::filesystem::current_path(before);
  EXPECT_EQ(bare, ".");
  EXPECT_EQ(robot::loadSkillTree(dir + "/t.toml", model()).directory, dir);
}

namespace {
// the error the runtime's loader gives for `text` as a tree file (t.toml in a temp folder `name`), or "" when it loads
std::string treeError(const std::string& name, const std::string& text) {
  try {
    robot::loadSkillTree(fixtures::writeTree(name, text), model());
  } catch (const engine::Error& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(SkillTree, BadEntriesAreLocated) {
  auto errorOf = [](const std::string& text) { return treeError("tree_bad", text); };
  const std::string gains = kWalkGains;
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
  const std::string keyless = std::regex_replace(walk, std::regex("key = 0\n"), "");  // nothing routes through it
  EXPECT_NE(errorOf(keyless).find("t.toml:1: skill.walk: missing key (only a skill that is another's `up`"),
            std::string::npos)
      << errorOf(keyless);
  const std::string badSettle = walk + "[skill.a]\nparent = \"walk\"\nkey = 1\nsettle_first = \"yes\"\n";
  EXPECT_NE(errorOf(badSettle).find("t.toml:22: skill.a.settle_first must be true or false"), std::string::npos)
      << errorOf(badSettle);
  const std::string badLine = walk + "[skill.walk.commands]\nvx = [0, 1]\nline_command = 1\n";
  EXPECT_NE(errorOf(badLine).find("t.toml:21: skill.walk.commands.line_command must be true or false"),
            std::string::npos)
      << errorOf(badLine);
  const std::string lineAndStep =
      walk + "[skill.walk.commands]\nvx = [0, 1]\nline_command = true\nstep_command = true\n";
  EXPECT_NE(
      errorOf(lineAndStep).find("t.toml:19: skill.walk.commands: line_command, step_command and ball_command all use"),
      std::string::npos)
      << errorOf(lineAndStep);
  const std::string lookBackAlone = walk + "[skill.walk.commands]\nvx = [0, 1]\nstep_look_back = true\n";
  EXPECT_NE(errorOf(lookBackAlone).find("t.toml:21: skill.walk.commands: step_look_back needs step_command = true"),
            std::string::npos)
      << errorOf(lookBackAlone);
  const std::string steerNoTurn = walk + "[skill.walk.commands]\nvx = [0, 1]\nwz = [0, 0]\nline_steer = 1.0\n";
  EXPECT_NE(
      errorOf(steerNoTurn)
          .find("t.toml:22: skill.walk.commands.line_steer steers with wz, and the skill's commands need a wz range"),
      std::string::npos)
      << errorOf(steerNoTurn);
  // a whole number is whole (never truncated), a model is a file beside the tree, and every way up reaches the root
  EXPECT_NE(errorOf("[skill.walk]\nparent = \"\"\nkey = 0.5\n").find("t.toml:3: skill.walk.key must be a whole number"),
            std::string::npos);
  EXPECT_NE(errorOf("[skill.walk]\nparent = \"\"\nkey = 0\nmodel = \"../../dev/zero\"\n")
                .find("t.toml:4: skill.walk.model must be a file name in the tree's folder"),
            std::string::npos);
  const std::string upCycle =
      walk + "[skill.a]\nparent = \"walk\"\nup = \"b\"\nkey = 1\n" + "[skill.b]\nparent = \"a\"\nup = \"a\"\n";
  EXPECT_NE(errorOf(upCycle).find("skill.a: its way up (`up`, else the parent) goes round in a cycle"),
            std::string::npos)
      << errorOf(upCycle);
  // the tables training owns are not the runtime's to read: a bad card loads here (ai::loadTrainingTree refuses it)
  EXPECT_EQ(errorOf(walk + "[skill.walk.card]\ntype = \"juggling\"\n"), "");
  const std::string backwardWindow = walk + "[skill.a]\nparent = \"walk\"\nkey = 1\nswitch_in_phase = [0.8, 0.3]\n";
  EXPECT_NE(errorOf(backwardWindow).find("t.toml:22: skill.a.switch_in_phase: low is above high"), std::string::npos)
      << errorOf(backwardWindow);
  // keyframes: times must increase, keys need an offset, and only a keyframes prior takes keys
  const std::string backwards =
      walk +
      "[skill.walk.prior]\ntype = \"keyframes\"\nkeys = [\n  { t = 1.0, offset = { knee = 1 } },\n"
      "  { t = 0.5, offset = { knee = 0 } },\n]\n";
  EXPECT_NE(errorOf(backwards).find("t.toml:23: skill.walk.prior.keys: times must increase"), std::string::npos)
      << errorOf(backwards);
  const std::string noOffset = walk + "[skill.walk.prior]\ntype = \"keyframes\"\nkeys = [{ t = 1.0 }]\n";
  EXPECT_NE(errorOf(noOffset).find("t.toml:21: skill.walk.prior.keys: each key needs t = s and offset"),
            std::string::npos)
      << errorOf(noOffset);
  const std::string keysOnPhase =
      walk + "[skill.walk.prior]\ntype = \"phase\"\nkeys = [{ t = 1.0, offset = { knee = 1 } }]\n";
  EXPECT_NE(errorOf(keysOnPhase).find("t.toml:19: skill.walk.prior: a \"keyframes\" prior needs keys"),
            std::string::npos)
      << errorOf(keysOnPhase);
  // a prior takes only its type's keys: a pose prior has no gait period to set
  const std::string poseT1 = walk + "[skill.walk.prior]\ntype = \"pose\"\noffset = { knee = 1 }\nT1 = 30\n";
  EXPECT_NE(errorOf(poseT1).find("t.toml:22: skill.walk.prior.T1 is not a key of a \"pose\" prior"), std::string::npos)
      << errorOf(poseT1);
  // a repeating keyframes cycle starts over from the default pose, and goes round the phase circle once
  const std::string notHome =
      walk + "[skill.walk.prior]\ntype = \"keyframes\"\nrepeat = true\nkeys = [{ t = 0.5, offset = { knee = 1 } }]\n";
  EXPECT_NE(errorOf(notHome).find(
                "t.toml:21: skill.walk.prior.repeat: the last key must be within 0.05 rad of the default pose"),
            std::string::npos)
      << errorOf(notHome);
  const std::string odd = walk +
                          "[skill.walk.prior]\ntype = \"keyframes\"\nrepeat = true\nkeys = [{ t = 0.3, offset = { knee "
                          "= 1 } }, { t = 0.51, offset = { knee = 0 } }]\n";
  EXPECT_NE(errorOf(odd).find("an even number of hundredths"), std::string::npos) << errorOf(odd);
  // a lead-in and a cycle: from a key (not the last) to the last, which repeats it
  const std::string keys3 =
      "keys = [{ t = 0.5, offset = { knee = 1 } }, { t = 1.0, offset = { knee = 0.5 } }, { t = 1.5, offset = { knee = "
      "%s } }]\n";
  auto withFrom = [&](const char* from, const char* last) {
    char k[256];
    std::snprintf(k, sizeof k, keys3.c_str(), last);
    return walk + "[skill.walk.prior]\ntype = \"keyframes\"\nrepeat_from = " + from + "\n" + k;
  };
  EXPECT_NE(errorOf(withFrom("0.7", "1"))
                .find("t.toml:21: skill.walk.prior.repeat_from must be the t of a key before the last"),
            std::string::npos)
      << errorOf(withFrom("0.7", "1"));
  EXPECT_NE(errorOf(withFrom("1.5", "1")).find("must be the t of a key before the last"), std::string::npos);
  EXPECT_NE(errorOf(withFrom("0.5", "0.5"))
                .find("t.toml:21: skill.walk.prior.repeat_from: the last key must be within 0.05 rad of the key at "
                      "repeat_from"),
            std::string::npos)
      << errorOf(withFrom("0.5", "0.5"));
  EXPECT_NE(errorOf(withFrom("0.5", "0") + "repeat = true\n").find("give one of them"), std::string::npos)
      << errorOf(withFrom("0.5", "0") + "repeat = true\n");
}

TEST(KeyframesPrior, EasesBetweenKeysAndHoldsTheLastWithTheClockStopped) {
  robot::SkillDef skill;
  skill.prior.kind = robot::PriorDef::Kind::Keyframes;
  robot::PriorDef::Keyframe a, b;
  a.tick = 100;
  a.offset[3] = 1.0;  // left knee +1 rad at 1 s
  b.tick = 200;
  b.offset[3] = 0.4;    // then +0.4 at 2 s
  b.offset[13] = -2.0;  // and the left shoulder pitch -2
  skill.prior.keyframes = {a, b};
  skill.prior.halfPeriodTicks = 200;
  skill.kp.fill(10);
  skill.kd.fill(1);
  const std::array<float, robot::kActionSize> none{};
  auto target = [&](int tp, size_t j) {
    robot::PdCommand pd;
    robot::skillPdCommand(model(), skill, none, robot::PhaseClock{tp}, robot::SkillCommand{}, &pd);
    return pd.target[j] - model().joints[j].defaultPosition;
  };
  EXPECT_DOUBLE_EQ(target(0, 3), 0.0);     // tick 0: the default pose
  EXPECT_NEAR(target(50, 3), 0.5, 1e-12);  // half-way to the first key: (1 - cos(pi/2)) / 2 = 0.5
  EXPECT_NEAR(target(25, 3), 0.5 * (1 - std::cos(M_PI / 4)), 1e-12);  // eased, not linear (0.146, not 0.25)
  EXPECT_NEAR(target(100, 3), 1.0, 1e-12);                            // at the key
  EXPECT_NEAR(target(150, 3), 0.7, 1e-12);                            // half-way between the keys
  EXPECT_NEAR(target(150, 13), -1.0, 1e-12);
  EXPECT_NEAR(target(500, 3), 0.4, 1e-12);  // after the last key: held
  // the clock counts to the last key and stops there; a switch into the skill starts it from the beginning
  robot::PhaseClock clock;
  for (int i = 0; i < 300; ++i) clock.advance(skill.prior, robot::SkillCommand{});
  EXPECT_EQ(clock.tp, 200);
  robot::PriorDef walk;
  walk.kind = robot::PriorDef::Kind::Phase;
  walk.halfPeriodTicks = 40;
  robot::PhaseClock midStep{30};
  robot::carryPhase(walk, skill.prior, &midStep);
  EXPECT_EQ(midStep.tp, 0);
}

TEST(KeyframesPrior, ARepeatingMotionWrapsItsClockToTheStart) {
  const std::string dir = testing::TempDir() + "/tree_repeat";
  std::filesystem::create_directories(dir);
  const std::string gains = kWalkGains;
  std::ofstream(dir + "/t.toml")
      << "[skill.walk]\nparent = \"\"\nkey = 0\nprior = { type = \"keyframes\", repeat = true, keys = "
         "[{ t = 0.3, offset = { knee = 1.0 } }, { t = 1.2, offset = { knee = 0.0 } }] }\n"
         "[skill.walk.rewards]\nlive = 1\n" +
             gains;
  const robot::SkillTree tree = robot::loadSkillTree(dir + "/t.toml", model());
  const robot::PriorDef& prior = tree.find("walk")->prior;
  EXPECT_EQ(prior.cycleTicks, 120);      // the last key's tick
  EXPECT_EQ(prior.halfPeriodTicks, 60);  // the phase observation goes once round per cycle
  robot::PhaseClock clock;
  for (int i = 0; i < 119; ++i) clock.advance(prior, robot::SkillCommand{});
  EXPECT_EQ(clock.tp, 119);
  clock.advance(prior, robot::SkillCommand{});
  EXPECT_EQ(clock.tp, 0);  // the cycle starts over (a one-shot clock would hold at 120)
  for (int i = 0; i < 30; ++i) clock.advance(prior, robot::SkillCommand{});
  robot::PdCommand pd;
  robot::skillPdCommand(model(), *tree.find("walk"), std::array<float, robot::kActionSize>{}, clock,
                        robot::SkillCommand{}, &pd);
  EXPECT_NEAR(pd.target[3] - model().joints[3].defaultPosition, 1.0, 1e-12);  // the second cycle's first key
  // a lead-in, then the cycle from the key at repeat_from to the last (which repeats it)
  std::ofstream(dir + "/t.toml")
      << "[skill.walk]\nparent = \"\"\nkey = 0\nprior = { type = \"keyframes\", repeat_from = 0.5, keys = "
         "[{ t = 0.5, offset = { knee = 1.0 } }, { t = 0.9, offset = { knee = 0.2 } }, { t = 1.3, offset = { knee = "
         "1.0 } }] }\n"
         "[skill.walk.rewards]\nlive = 1\n" +
             gains;
  const robot::SkillTree leadIn = robot::loadSkillTree(dir + "/t.toml", model());
  const robot::PriorDef& cycle = leadIn.find("walk")->prior;
  EXPECT_EQ(cycle.cycleStartTick, 50);
  EXPECT_EQ(cycle.halfPeriodTicks, 40);  // the cycle 0.5 -> 1.3 s is 80 ticks
  robot::PhaseClock lead;
  for (int i = 0; i < 129; ++i) lead.advance(cycle, robot::SkillCommand{});
  EXPECT_EQ(lead.tp, 129);
  lead.advance(cycle, robot::SkillCommand{});
  EXPECT_EQ(lead.tp, 50);  // back to the cycle's first key, not to the lead-in from the default pose
  for (int i = 0; i < 40; ++i) lead.advance(cycle, robot::SkillCommand{});
  robot::skillPdCommand(model(), *leadIn.find("walk"), std::array<float, robot::kActionSize>{}, lead,
                        robot::SkillCommand{}, &pd);
  EXPECT_NEAR(pd.target[3] - model().joints[3].defaultPosition, 0.2, 1e-12);  // half way round: the middle key
  double s0, c0, s1, c1;  // the phase observation is continuous across the wrap (once round per cycle)
  robot::phaseSignal(129, cycle.halfPeriodTicks, &s0, &c0);
  robot::phaseSignal(50, cycle.halfPeriodTicks, &s1, &c1);
  EXPECT_NEAR(std::atan2(s1, c1) - std::atan2(s0, c0), 2 * M_PI / 80, 1e-9);
  // only keyframes repeat
  std::ofstream(dir + "/t.toml")
      << "[skill.walk]\nparent = \"\"\nkey = 0\nprior = { type = \"phase\", repeat = true }\n"
         "[skill.walk.rewards]\nlive = 1\n" +
             gains;
  try {
    robot::loadSkillTree(dir + "/t.toml", model());
    ADD_FAILURE() << "a repeating phase prior loaded";
  } catch (const engine::Error& e) {
    EXPECT_NE(std::string(e.what()).find("t.toml:4: skill.walk.prior.repeat: only a \"keyframes\" prior repeats"),
              std::string::npos)
        << e.what();
  }
}

TEST(LineCommand, AuxSlotsHoldTheHeadingErrorAndTheOffsetLeftOfTheLine) {
  // upright, turned 0.2 rad left about z: the ground heading is the pelvis's x axis, (cos 0.2, sin 0.2)
  robot::Sensors s;
  s.baseRotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()));
  s.basePosition = Eigen::Vector3d(1.0, 0.3, 0.78);
  robot::SkillCommand c;
  c.vx = 0.3;
  robot::lineIntoCommand(s, Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), &c);
  EXPECT_NEAR(c.aux0, 0.2, 1e-12);  // turned left of the line's direction
  EXPECT_NEAR(c.aux1, 0.3, 1e-12);  // 0.3 m left of a line along +x
  EXPECT_DOUBLE_EQ(c.vx, 0.3);      // the velocity slots are the keys'
  // a line along +y through (0, 2): the pelvis at x = 1 is 1 m to its right, heading 0.2 rad is 1.37 rad right of it
  robot::lineIntoCommand(s, Eigen::Vector2d(0, 2), Eigen::Vector2d(0, 1), &c);
  EXPECT_NEAR(c.aux0, 0.2 - M_PI / 2, 1e-12);
  EXPECT_NEAR(c.aux1, -1.0, 1e-12);
  s.basePosition.x() = 5.0;  // the offset is clamped to 2 m
  robot::lineIntoCommand(s, Eigen::Vector2d(0, 2), Eigen::Vector2d(0, 1), &c);
  EXPECT_DOUBLE_EQ(c.aux1, -2.0);
  // face down on all fours (pitched 90 deg nose down about y): the heading is the pelvis's z axis on the ground, +x
  s.baseRotation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));
  s.basePosition = Eigen::Vector3d(2.0, -0.1, 0.3);
  robot::lineIntoCommand(s, Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), &c);
  EXPECT_NEAR(c.aux0, 0.0, 1e-12);
  EXPECT_NEAR(c.aux1, -0.1, 1e-12);
}

TEST(StepCommand, AuxSlotsHoldTheNextRiseAheadAndHowFarAwayItsEdgeIs) {
  // a 0.15 m step whose edge is 0.43 m ahead of the pelvis, and a ball on the floor between (rays pass it)
  engine::PhysicsWorld world;
  world.addGround(1.0);
  world.addStaticBox(Eigen::Vector3d(1.43 + 0.5, 0, 0.075), Eigen::Quaterniond::Identity(),
                     Eigen::Vector3d(0.5, 1, 0.075), 1.0);
  world.addBall(engine::BallDef{}, Eigen::Vector3d(1.2, 0, 0.11));
  EXPECT_NEAR(world.groundHeight(1.2, 0, 0.8), 0.0, 1e-6);   // through the ball to the floor
  EXPECT_NEAR(world.groundHeight(1.6, 0, 0.8), 0.15, 1e-6);  // the step's tread
  EXPECT_NEAR(world.groundHeight(1.6, 0, 0.1), 0.0, 1e-6);   // from inside the step: the floor under it
  robot::Sensors s;
  s.basePosition = Eigen::Vector3d(1.0, 0.0, 0.78);
  robot::SkillCommand c;
  c.vx = 0.5;
  robot::stepIntoCommand(s, world, false, &c);
  EXPECT_NEAR(c.aux0, 0.15, 1e-6);
  EXPECT_NEAR(c.aux1, 0.43, 0.1 / 32 + 1e-9);  // the edge found to 1/16 of the 0.1 m sampling, its middle reported
  EXPECT_DOUBLE_EQ(c.vx, 0.5);                 // the velocity slots are the keys'
  // turned round: flat floor as far as it looks
  s.baseRotation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()));
  robot::stepIntoCommand(s, world, false, &c);
  EXPECT_DOUBLE_EQ(c.aux0, 0.0);
  EXPECT_DOUBLE_EQ(c.aux1, robot::kStepLookahead);
  // on the tread 0.1 m from its edge, facing back: the step down
  s.basePosition = Eigen::Vector3d(1.53, 0.0, 0.93);
  robot::stepIntoCommand(s, world, false, &c);
  EXPECT_NEAR(c.aux0, -0.15, 1e-6);
  EXPECT_NEAR(c.aux1, 0.10, 0.1 / 32 + 1e-9);
}

TEST(StepCommand, LookingBackShowsTheLastEdgeATrailingHeelHasStillToCross) {
  // the last tread of a staircase down, 0.15 m high, its edge at x = 2.0; beyond it flat floor
  engine::PhysicsWorld world;
  world.addGround(1.0);
  world.addStaticBox(Eigen::Vector3d(1.5, 0, 0.075), Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.5, 1, 0.075),
                     1.0);
  robot::Sensors s;
  s.basePosition = Eigen::Vector3d(2.1, 0.0, 0.78);  // the pelvis 0.1 m past the edge
  s.footPosition = {Eigen::Vector3d(1.9, 0.1, 0.19),
                    Eigen::Vector3d(2.3, -0.1, 0.04)};  // left heel at 1.86, on the tread
  robot::SkillCommand c;
  robot::stepIntoCommand(s, world, false, &c);  // ahead alone: flat floor
  EXPECT_DOUBLE_EQ(c.aux0, 0.0);
  EXPECT_DOUBLE_EQ(c.aux1, robot::kStepLookahead);
  robot::stepIntoCommand(s, world, true, &c);  // the step down the left foot has still to take, 0.1 m behind
  EXPECT_NEAR(c.aux0, -0.15, 1e-6);
  EXPECT_NEAR(c.aux1, -0.1, 0.24 / 32 + 1e-9);  // halved 4 times between the pelvis and the heel 0.24 m behind it
  s.footPosition[0].x() = 2.05;                 // that heel down past the edge (2.01): flat again
  robot::stepIntoCommand(s, world, true, &c);
  EXPECT_DOUBLE_EQ(c.aux0, 0.0);
  EXPECT_DOUBLE_EQ(c.aux1, robot::kStepLookahead);
  // a riser ahead wins over one behind: the pelvis on the tread 0.3 m before its edge, a heel on the floor behind
  s.basePosition = Eigen::Vector3d(1.7, 0.0, 0.93);
  s.footPosition = {Eigen::Vector3d(0.9, 0.1, 0.04), Eigen::Vector3d(1.8, -0.1, 0.19)};
  robot::stepIntoCommand(s, world, true, &c);
  EXPECT_NEAR(c.aux0, -0.15, 1e-6);
  EXPECT_NEAR(c.aux1, 0.3, 0.1 / 32 + 1e-9);
  // going up: on the tread, a heel still on the floor below its riser (x = 1.0), 0.15 m behind the pelvis
  s.basePosition = Eigen::Vector3d(1.15, 0.0, 0.93);
  s.footPosition = {Eigen::Vector3d(0.95, 0.1, 0.04), Eigen::Vector3d(1.3, -0.1, 0.19)};
  robot::stepIntoCommand(s, world, true, &c);  // the tread's far edge is 0.85 m ahead, out of sight
  EXPECT_NEAR(c.aux0, 0.15, 1e-6);
  EXPECT_NEAR(c.aux1, -0.15, 0.24 / 32 + 1e-9);
}

TEST(Termination, GroundSkillsMayLieFaceDownButNotRollOntoTheirSideOrBack) {
  robot::TerminationDef upright;  // 30 deg, 0.5 m
  robot::TerminationDef ground;
  ground.maxTiltDegrees = 45;
  ground.maxForwardPitchDegrees = 120;
  ground.minHeight = 0;
  // pitch about y (nose down for positive), then a roll about the body's long (z) axis: onto a side both upright
  // and face down
  auto pitched = [](double pitchDeg, double rollDeg, double z) {
    robot::Sensors s;
    s.baseRotation = Eigen::AngleAxisd(pitchDeg * M_PI / 180, Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(rollDeg * M_PI / 180, Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d e = s.baseRotation.toRotationMatrix().eulerAngles(2, 1, 0);
    s.yaw = e[0], s.pitch = e[1], s.roll = e[2];
    s.basePosition = Eigen::Vector3d(0, 0, z);
    return s;
  };
  EXPECT_NEAR(robot::forwardPitch(pitched(90, 0, 0.12)), M_PI / 2, 1e-9);
  EXPECT_NEAR(robot::forwardPitch(pitched(-60, 0, 0.5)), -M_PI / 3, 1e-9);
  EXPECT_NEAR(robot::sideLean(pitched(90, 30, 0.12)), M_PI / 6, 1e-9);  // face down, rolled 30 deg: the left side up
  EXPECT_NEAR(robot::sideLean(pitched(0, 30, 0.7)), 0.0, 1e-9);         // upright, a turn about z is no lean
  EXPECT_FALSE(robot::hasFallen(ground, pitched(90, 0, 0.12)));         // lying face down
  EXPECT_FALSE(robot::hasFallen(ground, pitched(110, 10, 0.12)));
  EXPECT_TRUE(robot::hasFallen(ground, pitched(90, 50, 0.12)));  // rolled onto a side
  EXPECT_TRUE(robot::hasFallen(ground, pitched(-50, 0, 0.3)));   // onto its back
  EXPECT_TRUE(robot::hasFallen(ground, pitched(130, 0, 0.2)));   // over the head
  robot::Sensors leaning = pitched(0, 0, 0.75);                  // upright skills keep the Euler check: 40 deg of roll
  leaning.roll = 40 * M_PI / 180;
  EXPECT_TRUE(robot::hasFallen(upright, leaning));
  EXPECT_FALSE(robot::hasFallen(upright, pitched(20, 0, 0.75)));
  EXPECT_TRUE(robot::hasFallen(upright, pitched(40, 0, 0.75)));
  EXPECT_TRUE(robot::hasFallen(upright, pitched(0, 0, 0.45)));
}

TEST(Switching, AStandUpHandsOverToAnUprightSkillOnlyOnceTheRobotStandsStill) {
  robot::SkillDef standup, walk, crawl;
  standup.name = "standup", standup.up = "walk";
  standup.termination.maxForwardPitchDegrees = 120;  // a ground skill (it lies face down at first)
  crawl.termination.maxForwardPitchDegrees = 120;
  walk.name = "walk";
  auto sensors = [](double z, double tiltDeg, double vz) {
    robot::Sensors s;
    s.baseRotation = Eigen::AngleAxisd(tiltDeg * M_PI / 180, Eigen::Vector3d::UnitY());
    s.tilt = tiltDeg * M_PI / 180;
    s.basePosition = Eigen::Vector3d(0, 0, z);
    s.linearVelocity = s.baseRotation.inverse() * Eigen::Vector3d(0, 0, vz);  // body frame
    s.footContact = {true, true};
    return s;
  };
  EXPECT_FALSE(robot::postureAllowsSwitch(standup, walk, sensors(0.12, 86, 0.0), 0));  // lying face down
  EXPECT_FALSE(robot::postureAllowsSwitch(standup, walk, sensors(0.40, 30, 0.0), 0));  // on hands and knees
  EXPECT_FALSE(robot::postureAllowsSwitch(standup, walk, sensors(0.72, 12, 0.0), 0));  // up, tilted 12 deg
  EXPECT_FALSE(robot::postureAllowsSwitch(standup, walk, sensors(0.72, 5, 0.4), 0));   // up, still rising at 0.4 m/s
  EXPECT_TRUE(robot::postureAllowsSwitch(standup, walk, sensors(0.72, 5, 0.05), 0));   // standing, settled
  robot::Sensors airborne = sensors(0.78, 0, 0.0);
  airborne.footContact = {true, false};
  EXPECT_FALSE(robot::postureAllowsSwitch(standup, walk, airborne, 0));  // one foot still coming down
  // between ground skills, or out of an upright one, posture never holds a switch back
  EXPECT_TRUE(robot::postureAllowsSwitch(standup, crawl, sensors(0.12, 86, 0.0), 0));
  EXPECT_TRUE(robot::postureAllowsSwitch(walk, standup, sensors(0.5, 25, 0.3), 0));
}

TEST(Switching, AKeyPoseSkillTakesOverOnlyOnceTheRobotStandsSettled) {
  robot::SkillDef squat, jump, walk;
  squat.name = "squat", jump.name = "jump", walk.name = "walk";
  jump.prior.kind = robot::PriorDef::Kind::Keyframes;
  robot::Sensors s;
  s.basePosition = Eigen::Vector3d(0, 0, 0.78);
  s.footContact = {true, true};
  EXPECT_TRUE(robot::postureAllowsSwitch(squat, jump, s, 0));  // standing still
  s.qd[3] = 1.2;                                               // the left knee still bending (stepping in place)
  EXPECT_FALSE(robot::postureAllowsSwitch(squat, jump, s, 0));
  EXPECT_TRUE(robot::postureAllowsSwitch(squat, walk, s, 0));  // a policy's skill takes over as before
  s.qd[3] = 0.1;
  s.footContact = {true, false};  // one foot up
  EXPECT_FALSE(robot::postureAllowsSwitch(squat, jump, s, 0));
  s.footContact = {true, true};
  s.linearVelocity = Eigen::Vector3d(0.4, 0, 0);  // moving
  EXPECT_FALSE(robot::postureAllowsSwitch(squat, jump, s, 0));
}

TEST(Switching, ASettleFirstSkillWaitsUntilTheRobotHasStoppedDriftingAndUpToThreeSeconds) {
  robot::SkillDef walk, squat, oneLeg;
  walk.name = "walk", squat.name = "squat", oneLeg.name = "one_leg";
  walk.commands.vx = {-0.6, 1.2};
  oneLeg.settleFirst = true;  // squat and one_leg: no velocity command, still skills
  const robot::SkillCommand zero;
  robot::Sensors s;
  s.basePosition = Eigen::Vector3d(0, 0, 0.78);
  s.footContact = {true, true};
  s.linearVelocity = Eigen::Vector3d(0.1, 0, 0);                        // at rest: slower than 0.15 m/s, both feet down
  EXPECT_TRUE(robot::readyForSwitch(walk, squat, zero, zero, s, 0.3));  // the squat whatever the drift
  EXPECT_FALSE(robot::readyForSwitch(walk, oneLeg, zero, zero, s, 0.05));  // still drifting 0.05 m/s
  EXPECT_TRUE(robot::readyForSwitch(walk, oneLeg, zero, zero, s, 0.03));
  s.footContact = {true, false};  // stopped, but a foot up (stepping in place)
  EXPECT_FALSE(robot::readyForSwitch(walk, oneLeg, zero, zero, s, 0.0));
  s.footContact = {true, true};
  robot::SkillCommand braking;
  braking.vx = 0.2;  // the walk still braking toward zero
  EXPECT_FALSE(robot::readyForSwitch(walk, oneLeg, zero, braking, s, 0.0));
  // the drift is the velocity low-passed over 0.4 s: one tick of 0.1 m/s from rest is 0.1 x 0.01 / 0.4 = 0.0025;
  // swaying back and forth it averages out
  Eigen::Vector2d drift = Eigen::Vector2d::Zero();
  robot::updateDrift(s, &drift);
  EXPECT_NEAR(drift.x(), 0.0025, 1e-12);
  for (int t = 0; t < 400; ++t) {
    s.linearVelocity.y() = (t / 20) % 2 ? 0.2 : -0.2;  // stepping in place: 0.2 m/s sideways, each way for 0.2 s
    s.linearVelocity.x() = 0.0;
    robot::updateDrift(s, &drift);
  }
  // a square wave of +-a, each half T long, low-passed with time constant tau peaks at a tanh(T / 2 tau) = 0.049 m/s
  EXPECT_LT(drift.norm(), 0.05);
  EXPECT_GT(drift.norm(), 0.04);
  EXPECT_EQ(robot::maxSwitchWaitTicks(squat), robot::kMaxRestWaitTicks);     // 1.5 s, then the switch is forced
  EXPECT_EQ(robot::maxSwitchWaitTicks(oneLeg), robot::kMaxSettleWaitTicks);  // 3 s
  EXPECT_EQ(robot::maxSwitchWaitTicks(walk), robot::kMaxSlowWaitTicks);
}

TEST(Switching, OutOfJumpsInARowTheNextSkillTakesOverInTheClosingStandAStillOneOnceTheDriftHasStopped) {
  robot::SkillDef jump, squat, walk, kick;
  jump.name = "jump", squat.name = "squat", walk.name = "walk", kick.name = "kick";
  walk.commands.vx = {-0.6, 1.2};
  jump.prior.kind = kick.prior.kind = robot::PriorDef::Kind::Keyframes;
  jump.prior.keyframes = {{35, {}}, {120, {}}, {160, {}}};  // crouch ... the default pose at 1.2 s, held to 1.6 s
  jump.prior.cycleTicks = 160;
  kick.prior.keyframes = jump.prior.keyframes;  // the same keys, once (no cycle)
  EXPECT_TRUE(robot::isKeyPoseCycle(jump));
  EXPECT_FALSE(robot::isKeyPoseCycle(kick));
  EXPECT_EQ(robot::closingStandTick(jump.prior), 120);
  robot::PhaseClock crouching, standing;
  crouching.tp = 30, standing.tp = 130;
  EXPECT_FALSE(robot::cycleAllowsSwitch(jump, squat, crouching, 0.0, 0));  // not in a crouch
  EXPECT_FALSE(robot::cycleAllowsSwitch(jump, squat, standing, 0.05, 0));  // still drifting
  EXPECT_TRUE(robot::cycleAllowsSwitch(jump, squat, standing, 0.03, 0));
  EXPECT_TRUE(robot::cycleAllowsSwitch(jump, squat, standing, 0.05, robot::kMaxSettleWaitTicks));  // waited 3 s
  EXPECT_FALSE(robot::cycleAllowsSwitch(jump, squat, crouching, 0.0, robot::kMaxSettleWaitTicks));
  // the walk waits for the landing too (the closing stand), and steps out of a drift
  EXPECT_FALSE(robot::cycleAllowsSwitch(jump, walk, crouching, 0.2, 0));
  EXPECT_TRUE(robot::cycleAllowsSwitch(jump, walk, standing, 0.2, 0));
  EXPECT_TRUE(robot::cycleAllowsSwitch(kick, squat, crouching, 0.2, 0));
  // the clock holds in the closing stand while a switch out of the cycle is waited for, and only there
  EXPECT_TRUE(robot::holdsClosingStand(jump, standing, true));
  EXPECT_FALSE(robot::holdsClosingStand(jump, standing, false));
  EXPECT_FALSE(robot::holdsClosingStand(jump, crouching, true));
  EXPECT_FALSE(robot::holdsClosingStand(kick, standing, true));
}

TEST(Switching, OutOfAKeyPoseSkillAfterThreeSecondsRestOnBothFeetIsEnough) {
  robot::SkillDef kick, oneLeg;
  kick.name = "kick", oneLeg.name = "one_leg";
  kick.prior.kind = robot::PriorDef::Kind::Keyframes;
  robot::Sensors s;
  s.basePosition = Eigen::Vector3d(0, 0, 0.78);
  s.footContact = {true, true};
  s.qd[9] = 1.5;  // a knee still moving as the kicking foot taps down: not settled
  EXPECT_FALSE(robot::postureAllowsSwitch(kick, oneLeg, s, 0));
  EXPECT_FALSE(robot::postureAllowsSwitch(kick, oneLeg, s, robot::kMaxSettleWaitTicks - 1));
  EXPECT_TRUE(robot::postureAllowsSwitch(kick, oneLeg, s, robot::kMaxSettleWaitTicks));   // at rest on both feet
  EXPECT_FALSE(robot::postureAllowsSwitch(oneLeg, kick, s, robot::kMaxSettleWaitTicks));  // into it: settled only
  s.footContact = {true, false};                                                          // the foot in the air
  EXPECT_FALSE(robot::postureAllowsSwitch(kick, oneLeg, s, robot::kMaxSettleWaitTicks));
  s.footContact = {true, true};
  s.angularVelocity = Eigen::Vector3d(0, 0, 0.5);  // turning on the spot faster than 0.3 rad/s
  EXPECT_FALSE(robot::postureAllowsSwitch(kick, oneLeg, s, robot::kMaxSettleWaitTicks));
  s.angularVelocity = Eigen::Vector3d::Zero();
  s.linearVelocity = Eigen::Vector3d(0, 0, -0.3);  // sinking into a landing
  EXPECT_FALSE(robot::postureAllowsSwitch(kick, oneLeg, s, robot::kMaxSettleWaitTicks));
}

TEST(Switching, ASkillWithAPhaseWindowTakesOverOnlyInThatPartOfTheGaitCycle) {
  robot::SkillDef walk, run, squat;
  walk.name = "walk", run.name = "run", squat.name = "squat";
  walk.prior.kind = robot::PriorDef::Kind::Phase;
  walk.prior.halfPeriodTicks = 40;  // a cycle of 80 ticks
  run.switchInPhase = {0.5, 0.82};  // tp 40..65
  robot::PhaseClock c;
  for (const auto& [tp, allowed] :
       std::vector<std::pair<int, bool>>{{1, false}, {39, false}, {40, true}, {65, true}, {66, false}, {80, false}}) {
    c.tp = tp;
    EXPECT_EQ(robot::phaseAllowsSwitch(walk, run, c), allowed) << "tp " << tp;
    EXPECT_TRUE(robot::phaseAllowsSwitch(walk, squat, c)) << "no window: any phase, tp " << tp;
  }
  c.tp = 1;
  robot::SkillDef still = walk;
  still.prior.kind = robot::PriorDef::Kind::Pose;  // from a skill without a gait the window does not apply
  EXPECT_TRUE(robot::phaseAllowsSwitch(still, run, c));
}

TEST(Switching, AGroundBranchTakesOverFromProneOnlyOnceTheRobotLiesStill) {
  robot::SkillDef prone, pushup;
  prone.name = "prone", prone.parent = "walk";
  pushup.name = "pushup", pushup.parent = "prone";
  prone.termination.maxForwardPitchDegrees = 120;  // both ground skills
  pushup.termination.maxForwardPitchDegrees = 120;
  auto sensors = [](double z, double pitchDeg, double speed) {
    robot::Sensors s;
    s.baseRotation = Eigen::AngleAxisd(pitchDeg * M_PI / 180, Eigen::Vector3d::UnitY());
    s.basePosition = Eigen::Vector3d(0, 0, z);
    s.linearVelocity = s.baseRotation.inverse() * Eigen::Vector3d(0, 0, -speed);  // sinking, body frame
    return s;
  };
  EXPECT_FALSE(
      robot::postureAllowsSwitch(prone, pushup, sensors(0.78, 0, 0.0), 0));  // still standing (prone's first tick)
  EXPECT_FALSE(robot::postureAllowsSwitch(prone, pushup, sensors(0.40, 60, 0.5), 0));  // going down onto the hands
  EXPECT_FALSE(robot::postureAllowsSwitch(prone, pushup, sensors(0.13, 86, 0.3), 0));  // down, still sinking
  EXPECT_FALSE(robot::postureAllowsSwitch(prone, pushup, sensors(0.13, 50, 0.0), 0));  // low, but not face down
  EXPECT_TRUE(robot::postureAllowsSwitch(prone, pushup, sensors(0.13, 86, 0.05), 0));  // lying face down, still
  EXPECT_TRUE(robot::postureAllowsSwitch(pushup, prone, sensors(0.20, 60, 0.3), 0));   // back down: not held
}

TEST(Prior, TheTurnTermTwistsTheJointsByTheYawRateCommand) {
  const std::string dir = testing::TempDir() + "/tree_turn";
  std::filesystem::create_directories(dir);
  const std::string gains = kWalkGains;
  auto load = [&](const std::string& turn) {
    std::ofstream(dir + "/t.toml")
        << "[skill.walk]\nparent = \"\"\nkey = 0\nprior = { type = \"keyframes\", " + turn +
               "keys = [{ t = 0.3, offset = { knee = 1.0 } }] }\n[skill.walk.rewards]\nlive = 1\n" + gains;
    return robot::loadSkillTree(dir + "/t.toml", model());
  };
  const robot::SkillTree tree = load("turn = { waist_yaw = 1.0, left_hip_yaw = -0.5 }, ");
  const robot::SkillDef& walk = *tree.find("walk");
  auto offset = [&](double wz, size_t j) {
    robot::SkillCommand c;
    c.wz = wz;
    robot::PdCommand pd;
    robot::skillPdCommand(model(), walk, std::array<float, robot::kActionSize>{}, robot::PhaseClock{30}, c, &pd);
    return pd.target[j] - model().joints[j].defaultPosition;
  };
  const size_t waist = 12, leftHipYaw = 2, rightHipYaw = 8, leftKnee = 3;
  EXPECT_NEAR(offset(0.05, waist), 0.05, 1e-12);    // 1 rad per rad/s
  EXPECT_NEAR(offset(-0.05, waist), -0.05, 1e-12);  // the other way for a right turn
  EXPECT_NEAR(offset(0.04, leftHipYaw), -0.02, 1e-12);
  EXPECT_DOUBLE_EQ(offset(0.04, rightHipYaw), 0.0);  // "left_" names one side only
  EXPECT_DOUBLE_EQ(offset(0.0, waist), 0.0);
  EXPECT_DOUBLE_EQ(offset(0.05, leftKnee), offset(0.0, leftKnee));  // the keys are untouched
  EXPECT_DOUBLE_EQ(load("").find("walk")->prior.turn[waist], 0.0);  // none: no term
  for (const char* bad : {"turn = 0.5, ", "turn = { waist_yaw = 2.0 }, ", "turn = { neck = 0.1 }, "}) {
    try {
      load(bad);
      ADD_FAILURE() << "loaded " << bad;
    } catch (const engine::Error& e) {
      EXPECT_NE(std::string(e.what()).find("t.toml:4: skill.walk.prior.turn"), std::string::npos) << e.what();
    }
  }
}
