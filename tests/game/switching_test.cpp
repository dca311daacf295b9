// switching_test.cpp — the skill runtime: routes along the tree, and a switch that does not jump the joint
// targets (the filtered action and the gait phase carry over).
#include <gtest/gtest.h>

#include <cmath>

#include "ai/onnx/policy_onnx.h"
#include "engine/input/key_script.h"
#include "game/session.h"
#include "tests/fixtures.h"

namespace {

using fixtures::kSource;

// a small tree: walk -> {run, squat -> jump}; every policy outputs the same constant action: zero, or a
// balanced crouch (hip pitch -a, knee +2a, ankle pitch -a on both legs)
robot::SkillSet tree(float crouch) {
  const robot::SkillTree shipped = robot::loadSkillTree(kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  robot::SkillDef base = *shipped.find("walk");
  base.prior.kind = robot::PriorDef::Kind::None;  // no gait: targets move only with the action
  robot::SkillSet set;
  auto add = [&](const std::string& name, const std::string& parent, int key) {
    robot::SkillDef d = base;
    d.name = name;
    d.parent = parent;
    d.key = key;
    set.skills.push_back({d, [crouch](const Eigen::MatrixXf&, Eigen::MatrixXf* a) {
                            a->setZero(robot::kActionSize, 1);
                            for (int leg : {0, 6}) {
                              (*a)(leg + 0, 0) = -crouch;     // hip pitch
                              (*a)(leg + 3, 0) = 2 * crouch;  // knee
                              (*a)(leg + 4, 0) = -crouch;     // ankle pitch
                            }
                          }});
  };
  add("walk", "", 0);
  add("run", "walk", 1);
  add("squat", "walk", 3);
  add("jump", "squat", 4);
  return set;
}

std::string hop(const robot::SkillSet& s, const std::string& from, const std::string& to) {
  const robot::Skill* h = s.nextHop(*s.byName(from), *s.byName(to));
  return h ? h->def.name : "-";
}

}  // namespace

TEST(SkillSet, RoutesGoUpToTheCommonAncestorThenDown) {
  const robot::SkillSet s = tree(0.0f);
  EXPECT_EQ(hop(s, "walk", "run"), "run");
  EXPECT_EQ(hop(s, "run", "walk"), "walk");
  EXPECT_EQ(hop(s, "run", "jump"), "walk");
  EXPECT_EQ(hop(s, "walk", "jump"), "squat");
  EXPECT_EQ(hop(s, "jump", "run"), "squat");
  EXPECT_EQ(hop(s, "squat", "jump"), "jump");
  EXPECT_EQ(hop(s, "jump", "jump"), "-");
}

TEST(SkillSet, AGroundSkillGoesUpThroughItsUpSkill) {
  // walk -> prone -> {crawl, standup}; prone's way up is standup (it cannot switch back to walk lying down) and
  // standup's is walk: from crawl, key 0 runs prone, standup, then walk
  robot::SkillSet s = tree(0.0f);
  auto add = [&](const std::string& name, const std::string& parent, const std::string& up, int key) {
    robot::SkillDef d = s.skills.front().def;
    d.name = name, d.parent = parent, d.up = up, d.key = key;
    s.skills.push_back({d, s.skills.front().policy});
  };
  add("prone", "walk", "standup", 7);
  add("crawl", "prone", "", 8);
  robot::SkillSet withoutStandup = s;
  add("standup", "prone", "walk", 9);
  EXPECT_EQ(hop(s, "crawl", "walk"), "prone");
  EXPECT_EQ(hop(s, "prone", "walk"), "standup");
  EXPECT_EQ(hop(s, "standup", "walk"), "walk");
  EXPECT_EQ(hop(s, "prone", "run"), "standup");
  EXPECT_EQ(hop(s, "walk", "crawl"), "prone");
  EXPECT_EQ(hop(s, "prone", "crawl"), "crawl");
  EXPECT_EQ(hop(s, "standup", "crawl"), "walk");  // standup ends standing: down again from walk
  // without a standup model the robot stays down: no route up, but the way down still works
  EXPECT_EQ(hop(withoutStandup, "prone", "walk"), "-");
  EXPECT_EQ(hop(withoutStandup, "prone", "crawl"), "crawl");
  // a keyless stand-up (the tree's: 11 skills, 10 keys) is requested by the key of the way up from it, the walk's
  EXPECT_EQ(s.requestKey(*s.byName("standup")), 9);
  s.skills.back().def.key = -1;
  EXPECT_EQ(s.requestKey(*s.byName("standup")), 0);
  EXPECT_EQ(s.requestKey(*s.byName("crawl")), 8);
  EXPECT_EQ(s.byKey(-1), nullptr);
}

TEST(Session, RoutedRequestSwitchesOneEdgeAtATime) {
  const levels::Level flat = levels::loadLevel(kSource + "/levels/flat");
  const robot::SkillSet skills = tree(0.0f);
  game::Session s(flat, fixtures::robotModel(), game::SessionOptions{1, &skills});
  s.step(engine::parseKeyScript("0.00 tap 1\n", "k"));  // run, via nothing: the first skill is taken directly
  for (int i = 0; i < 20; ++i) s.step({});
  EXPECT_EQ(s.activeSkillName(), "run");
  s.step({{s.tick(), engine::KeyAction::kTap, '4'}});  // jump: run -> walk -> squat -> jump
  for (int i = 0; i < 3 * robot::kMinHopTicks + 5; ++i) s.step({});
  ASSERT_EQ(s.telemetry().switches.size(), 4u);
  const auto& sw = s.telemetry().switches;
  EXPECT_EQ(sw[1].from + ">" + sw[1].to, "run>walk");
  EXPECT_EQ(sw[2].from + ">" + sw[2].to, "walk>squat");
  EXPECT_EQ(sw[3].from + ">" + sw[3].to, "squat>jump");
  EXPECT_EQ(sw[2].tick - sw[1].tick, robot::kMinHopTicks);  // an intermediate skill runs its minimum time
  EXPECT_EQ(s.activeSkillName(), "jump");
}

TEST(Session, SwitchKeepsTheJointTargetsContinuous) {
  const levels::Level flat = levels::loadLevel(kSource + "/levels/flat");
  const robot::SkillSet skills = tree(0.3f);  // both skills hold the same crouch
  game::Session s(flat, fixtures::robotModel(), game::SessionOptions{1, &skills});
  s.step(engine::parseKeyScript("0.00 tap 0\n", "k"));
  for (int i = 0; i < 100; ++i) s.step({});  // the 0.8 low-pass has settled (0.8^100 ~ 2e-10)
  const robot::JointArray before = s.robot().command().target;
  s.step({{s.tick(), engine::KeyAction::kTap, '1'}});
  ASSERT_EQ(s.activeSkillName(), "run") << "tilt " << s.sensors().tilt;
  const robot::JointArray after = s.robot().command().target;
  double jump = 0, bent = 0;
  for (size_t j = 0; j < before.size(); ++j) {
    jump = std::max(jump, std::abs(after[j] - before[j]));
    bent = std::max(bent, std::abs(before[j] - fixtures::robotModel().joints[j].defaultPosition));
  }
  // the pose is really away from the default: the knee bends by its action scale x 0.6 (the largest offset)
  EXPECT_NEAR(bent, 0.6 * skills.skills[0].def.actionScale[3], 1e-6);
  EXPECT_LT(jump, 1e-6);  // and the switch did not move any target
}

TEST(Session, SwitchFadesTheOldPriorOutOverThreeTenthsOfASecond) {
  // walk (stepping prior) -> squat (key pose at amplitude 0 = the default pose), both policies output zero:
  // switched at the left knee's peak (+2 dh = 1.04 rad), the targets move there over 30 ticks, not in one
  const levels::Level flat = levels::loadLevel(kSource + "/levels/flat");
  const robot::SkillTree shipped = robot::loadSkillTree(kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  robot::SkillSet set;
  const auto zero = [](const Eigen::MatrixXf&, Eigen::MatrixXf* a) { a->setZero(robot::kActionSize, 1); };
  robot::SkillDef walk = *shipped.find("walk");
  walk.prior.standStill = false;  // stepping whatever the command
  set.skills.push_back({walk, zero});
  robot::SkillDef squat = *shipped.find("squat");
  squat.commands.vx = {0.0, walk.commands.vx.hi};  // moving, as fast as the walk: it takes over at once, in mid-step
  set.skills.push_back({squat, zero});
  game::Session s(flat, fixtures::robotModel(), game::SessionOptions{1, &set});
  s.step(engine::parseKeyScript("0.00 tap 0\n", "k"));
  const int t1 = walk.prior.halfPeriodTicks;
  for (int i = 1; i < t1 / 2; ++i) s.step({});  // the left leg at its peak (tp = T1 / 2)
  const double kneeBend = s.robot().command().target[3] - fixtures::robotModel().joints[3].defaultPosition;
  EXPECT_NEAR(kneeBend, 2.0 * walk.prior.dh, 1e-6);
  robot::JointArray previous = s.robot().command().target;
  s.step({{s.tick(), engine::KeyAction::kTap, '3'}});
  ASSERT_EQ(s.activeSkillName(), "squat");
  double largestStep = 0;
  for (int i = 0; i < robot::kSwitchFadeTicks + 5; ++i) {
    const robot::JointArray now = s.robot().command().target;
    for (size_t j = 0; j < now.size(); ++j) largestStep = std::max(largestStep, std::abs(now[j] - previous[j]));
    previous = now;
    s.step({});
  }
  // a linear fade of ~1.04 rad over 30 ticks moves at most ~0.035 rad per tick, plus the gait's own motion
  EXPECT_LT(largestStep, 0.1);
  for (size_t j = 0; j < previous.size(); ++j)  // faded out: the squat's targets (its default pose)
    EXPECT_NEAR(previous[j], fixtures::robotModel().joints[j].defaultPosition, 1e-9) << "joint " << j;
}

TEST(Session, AStillSkillWaitsUntilTheCommandHasRampedToZeroAndTheRobotRests) {
  // walk (no gait, zero action: the robot stands) with W held for 1 s: vx = 1.2 m/s. The squat key then brakes
  // the command at the keys' 0.02 m/s per tick, so the squat (a still skill) takes over 60 ticks later; the run
  // (a moving skill) would take over at once.
  const levels::Level flat = levels::loadLevel(kSource + "/levels/flat");
  const robot::SkillTree shipped = robot::loadSkillTree(kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  const auto zero = [](const Eigen::MatrixXf&, Eigen::MatrixXf* a) { a->setZero(robot::kActionSize, 1); };
  robot::SkillDef walk = *shipped.find("walk");
  walk.prior.kind = robot::PriorDef::Kind::None;
  robot::SkillDef squat = *shipped.find("squat");
  ASSERT_TRUE(robot::isStillSkill(squat));
  ASSERT_FALSE(robot::isStillSkill(walk));
  robot::SkillSet set;
  set.skills.push_back({walk, zero});
  set.skills.push_back({squat, zero});
  game::Session s(flat, fixtures::robotModel(), game::SessionOptions{1, &set});
  s.step(engine::parseKeyScript("0.00 tap 0\n0.00 down W\n", "k"));
  for (int i = 0; i < 99; ++i) s.step({});
  EXPECT_NEAR(s.command().vx, 1.2, 1e-9);
  const int64_t key = s.tick();
  s.step({{key, engine::KeyAction::kTap, '3'}});
  while (s.activeSkillName() != "squat" && s.tick() < key + 300) s.step({});
  ASSERT_EQ(s.activeSkillName(), "squat");
  EXPECT_NEAR(double(s.telemetry().switches.back().tick - key), 60.0,
              1.0);  // 61 if 1.2 - 60 x 0.02 leaves a rounding crumb
}

TEST(Session, ASlowerSkillTakesOverOnceTheCommandHasRampedToItsTopSpeed) {
  // run (no gait, zero action: the robot stands) with W held for 1.2 s: vx = 2.2 m/s, the run's top (reached after
  // 1.1 s). The walk key brakes the run's command at the keys' 0.02 m/s per tick to the walk's top, 1.2 m/s: 50 ticks.
  // The standing pelvis is within the 0-1.2 m/s both train at but more than kTargetSlack below the command, so the walk
  // takes over at the longest wait, 250 ticks.
  const levels::Level flat = levels::loadLevel(kSource + "/levels/flat");
  const robot::SkillTree shipped = robot::loadSkillTree(kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  const auto zero = [](const Eigen::MatrixXf&, Eigen::MatrixXf* a) { a->setZero(robot::kActionSize, 1); };
  robot::SkillDef walk = *shipped.find("walk"), run = *shipped.find("run");
  walk.prior.kind = robot::PriorDef::Kind::None;
  run.prior.kind = robot::PriorDef::Kind::None;
  ASSERT_DOUBLE_EQ(run.commands.vx.hi, 2.2);
  ASSERT_DOUBLE_EQ(walk.commands.vx.hi, 1.2);
  ASSERT_TRUE(robot::switchWaits(run, walk));
  ASSERT_TRUE(robot::switchWaits(walk, run));  // the walk may back up; the run never does
  robot::SkillSet set;
  set.skills.push_back({walk, zero});
  set.skills.push_back({run, zero});
  game::Session s(flat, fixtures::robotModel(), game::SessionOptions{1, &set});
  s.step(engine::parseKeyScript("0.00 tap 1\n0.00 down W\n", "k"));
  for (int i = 0; i < 119; ++i) s.step({});
  ASSERT_EQ(s.activeSkillName(), "run");
  EXPECT_NEAR(s.command().vx, 2.2, 1e-9);
  const int64_t key = s.tick();
  s.step({{key, engine::KeyAction::kTap, '0'}});
  while (s.activeSkillName() != "walk" && s.tick() < key + 300) s.step({});
  ASSERT_EQ(s.activeSkillName(), "walk");
  EXPECT_EQ(s.telemetry().switches.back().tick - key, robot::kMaxSlowWaitTicks);
  // back to the run with W still held: the keys' 2.2 m/s, clamped to the band, is 1.2 again: the longest wait
  const int64_t back = s.tick();
  s.step({{back, engine::KeyAction::kTap, '1'}});
  while (s.activeSkillName() != "run" && s.tick() < back + 300) s.step({});
  ASSERT_EQ(s.activeSkillName(), "run");
  EXPECT_EQ(s.telemetry().switches.back().tick - back, robot::kMaxSlowWaitTicks);
}

TEST(Session, ARunWithAPhaseWindowTakesOverWhenTheWalksGaitReachesIt) {
  // the walk's stepping prior (80-tick cycle, zero action) from rest; the run (no gait) may take over only in
  // 0.5-0.82 of the walk's cycle. Asked at tick 10 it waits for tp 40; asked at tick 50, inside, it goes at once.
  const levels::Level flat = levels::loadLevel(kSource + "/levels/flat");
  const robot::SkillTree shipped = robot::loadSkillTree(kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  const auto zero = [](const Eigen::MatrixXf&, Eigen::MatrixXf* a) { a->setZero(robot::kActionSize, 1); };
  robot::SkillDef walk = *shipped.find("walk"), run = *shipped.find("run");
  walk.prior.standStill = false;
  ASSERT_EQ(walk.prior.halfPeriodTicks, 40);
  run.prior.kind = robot::PriorDef::Kind::None;
  run.switchInPhase = {0.5, 0.82};
  robot::SkillSet set;
  set.skills.push_back({walk, zero});
  set.skills.push_back({run, zero});
  for (const int asked : {10, 50}) {
    game::Session s(flat, fixtures::robotModel(), game::SessionOptions{1, &set});
    s.step(engine::parseKeyScript("0.00 tap 0\n", "k"));  // tick 0: the walk starts its clock (tp 1 after the tick)
    while (s.tick() < asked) s.step({});
    s.step({{s.tick(), engine::KeyAction::kTap, '1'}});
    while (s.activeSkillName() != "run" && s.tick() < asked + 100) s.step({});
    ASSERT_EQ(s.activeSkillName(), "run") << "asked at " << asked;
    // the switch is made before the tick's clock advance: at tick t the walk's clock reads tp = t
    EXPECT_EQ(s.telemetry().switches.back().tick, asked == 10 ? 40 : 50) << "asked at " << asked;
  }
}

TEST(Switching, ASlowerSkillWaitsForThePelvisToSlowToItsTopSpeed) {
  const robot::SkillTree shipped = robot::loadSkillTree(kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  const robot::SkillDef &walk = *shipped.find("walk"), &run = *shipped.find("run");
  robot::SkillCommand brake, target;
  brake.vx = target.vx = 1.2;  // W held: the brake's target is the walk's top
  robot::Sensors moving;
  moving.linearVelocity = Eigen::Vector3d(1.5, 0, 0);  // upright, facing +X: body frame = world frame
  EXPECT_FALSE(robot::readyForSwitch(run, walk, target, brake, moving));  // above the 0-1.2 band + kSlowMargin 0.25
  moving.linearVelocity = Eigen::Vector3d(1.4, 0, 0);
  EXPECT_TRUE(robot::readyForSwitch(run, walk, target, brake, moving));
  brake.vx = 1.3;  // the command has not come down to its target yet
  EXPECT_FALSE(robot::readyForSwitch(run, walk, target, brake, moving));
  brake.vx = target.vx = 0.0;  // no key: the run brakes to a stop, but any speed of the band will do for the walk
  moving.linearVelocity = Eigen::Vector3d(1.0, 0, 0);
  EXPECT_TRUE(robot::readyForSwitch(run, walk, target, brake, moving));
  // walking backward into the run (which never backs up): ready once no faster than kSlowMargin backward
  moving.linearVelocity = Eigen::Vector3d(-0.5, 0, 0);
  EXPECT_FALSE(robot::readyForSwitch(walk, run, target, brake, moving));
  moving.linearVelocity = Eigen::Vector3d(-0.2, 0, 0);
  EXPECT_TRUE(robot::readyForSwitch(walk, run, target, brake, moving));
  moving.linearVelocity = Eigen::Vector3d(0.8, 0, 0);  // the walk at its real pace under a 1.2 m/s command
  brake.vx = target.vx = 1.2;
  EXPECT_TRUE(robot::readyForSwitch(walk, run, target, brake, moving));
  moving.linearVelocity = Eigen::Vector3d(0.2, 0, 0);  // still coming round from backward: not yet (1.2 - 0.5)
  EXPECT_FALSE(robot::readyForSwitch(walk, run, target, brake, moving));
  // the brake aims at the keys' command clamped into the speeds both skills train at: 0-1.2 m/s for run <-> walk
  // (the run never backs up): W held (2.0) -> 1.2; S held (-0.6) -> 0, whichever way the switch goes
  robot::SkillCommand keys;
  keys.vx = 2.0;
  EXPECT_DOUBLE_EQ(robot::switchBrakeTarget(run, walk, keys).vx, 1.2);
  keys.vx = -0.6;
  EXPECT_DOUBLE_EQ(robot::switchBrakeTarget(run, walk, keys).vx, 0.0);
  EXPECT_DOUBLE_EQ(robot::switchBrakeTarget(walk, run, keys).vx, 0.0);
  EXPECT_FALSE(robot::switchWaits(*shipped.find("stairs"), walk));  // 0-0.9 m/s: within the walk's speeds
  // a skill with only a forward range (no turning, so never at vx = 0) is entered at its lowest speed
  robot::SkillDef sprint = run;
  sprint.commands.wz = {0.0, 0.0};
  EXPECT_DOUBLE_EQ(robot::switchBrakeTarget(walk, sprint, keys).vx, 0.8);
  keys.vx = 0, keys.wz = 0.5;  // turning: the interlock would hold vx at 0, so the brake drops the turn
  EXPECT_DOUBLE_EQ(robot::switchBrakeTarget(walk, sprint, keys).vx, 0.8);
  EXPECT_DOUBLE_EQ(robot::switchBrakeTarget(walk, sprint, keys).wz, 0.0);
  EXPECT_DOUBLE_EQ(robot::switchBrakeTarget(walk, run, keys).wz, 0.5);  // the run turns on the spot: kept
}

// the shipped tree's prone and standup with their priors alone (zero network output) and the shipped walk model:
// key 7 lays the robot face down, key 0 while lying runs the stand-up (prone cannot hand a lying robot to the
// walk), and the walk takes over only once the robot stands and has settled, not after the minimum hop time
TEST(Session, KeyZeroWhileLyingStandsUpThenWalks) {
  const robot::SkillTree shipped = robot::loadSkillTree(kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  auto walk = std::make_shared<ai::LoadedPolicy>(ai::loadPolicyOnnx(kSource + "/assets/skills/walk.onnx"));
  robot::SkillSet skills;
  skills.skills.push_back(
      {*shipped.find("walk"), [walk](const Eigen::MatrixXf& o, Eigen::MatrixXf* a) { walk->act(o, a); }});
  for (const char* name : {"prone", "standup"})
    skills.skills.push_back(
        {*shipped.find(name), [](const Eigen::MatrixXf&, Eigen::MatrixXf* a) { a->setZero(robot::kActionSize, 1); }});
  const levels::Level flat = levels::loadLevel(kSource + "/levels/flat");
  game::Session s(flat, fixtures::robotModel(), game::SessionOptions{1, &skills});
  s.step(engine::parseKeyScript("0.00 tap 7\n", "k"));
  double pelvisAtWalk = 0, tiltAtWalk = 0;
  for (int i = 1; i < 1000; ++i) {
    s.step(i == 350 ? std::vector<engine::KeyEvent>{{s.tick(), engine::KeyAction::kTap, '0'}}
                    : std::vector<engine::KeyEvent>{});
    if (s.activeSkillName() == "walk" && pelvisAtWalk == 0)
      pelvisAtWalk = s.sensors().basePosition.z(), tiltAtWalk = s.sensors().tilt;
  }
  const auto& sw = s.telemetry().switches;
  ASSERT_EQ(sw.size(), 3u);
  EXPECT_EQ(sw[0].to, "prone");
  EXPECT_EQ(sw[1].from + ">" + sw[1].to, "prone>standup");
  EXPECT_EQ(sw[1].tick, 350);  // lying, the way up is taken at once
  EXPECT_EQ(sw[2].from + ">" + sw[2].to, "standup>walk");
  EXPECT_GT(sw[2].tick - sw[1].tick,
            440);  // the keyframes stand the robot up 4.64 s after the switch, settled ~0.2 s later
  EXPECT_LT(sw[2].tick - sw[1].tick, 550);
  EXPECT_GE(pelvisAtWalk, robot::kStoodPelvisHeight);
  EXPECT_LT(tiltAtWalk, robot::kStoodTiltDegrees * M_PI / 180);
  EXPECT_FALSE(s.fallen()) << "fell at tick " << s.fallTick() << "; walk from " << sw[2].tick;
}

// a stand-up that does not rise (here its prior is switched off: it holds the lying pose) is down kStandUpTicks
// after it took over, as a fall: no key takes a lying robot anywhere but up
TEST(Session, AStandUpStillLyingAfterTenSecondsCountsAsAFall) {
  const robot::SkillTree shipped = robot::loadSkillTree(kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  const auto zero = [](const Eigen::MatrixXf&, Eigen::MatrixXf* a) { a->setZero(robot::kActionSize, 1); };
  robot::SkillSet skills;
  skills.skills.push_back({*shipped.find("walk"), zero});
  skills.skills.push_back({*shipped.find("prone"), zero});
  robot::SkillDef standup = *shipped.find("standup");
  standup.prior = shipped.find("prone")->prior;  // lies as prone lies: never rises
  skills.skills.push_back({standup, zero});
  const levels::Level flat = levels::loadLevel(kSource + "/levels/flat");
  game::Session s(flat, fixtures::robotModel(), game::SessionOptions{1, &skills});
  s.step(engine::parseKeyScript("0.00 tap 7\n", "k"));
  for (int i = 1; i < 350; ++i) s.step({});
  s.step({{s.tick(), engine::KeyAction::kTap, '0'}});
  ASSERT_EQ(s.activeSkillName(), "standup");
  const int64_t since = s.telemetry().switches.back().tick;
  while (s.telemetry().falls == 0 && s.tick() < since + game::kStandUpTicks + 100) s.step({});
  EXPECT_EQ(s.telemetry().falls, 1);
  EXPECT_EQ(s.fallTick(), since + game::kStandUpTicks);
  EXPECT_EQ(s.telemetry().fallsBySkill, (std::map<std::string, int>{{"standup", 1}}));  // the skill in control
}

TEST(Telemetry, FallsBySkillReadMostFirst) {
  EXPECT_EQ(game::fallsBySkillText({}), "");
  EXPECT_EQ(game::fallsBySkillText({{"jump", 1}, {"stairs", 3}, {"", 1}, {"kick", 1}}),
            "stairs 3, no skill 1, jump 1, kick 1");
}

// a fall on a game level respawns the robot at rest: the root skill takes it (as at the level's start) with the
// velocity commands back at 0, and the skill the keys still ask for is entered from there, as any request is
TEST(Session, ARespawnHandsTheRobotToTheRootAtRest) {
  const levels::Level mario = levels::loadLevel(kSource + "/levels/mario");
  const robot::SkillSet skills =
      tree(4.0f);  // a deep constant crouch: every skill sinks the pelvis below the fall height
  game::Session s(mario, fixtures::robotModel(), game::SessionOptions{1, &skills});
  s.step(engine::parseKeyScript("0.00 tap 1\n0.00 down W\n", "k"));  // the run, forward
  while (s.telemetry().respawns.empty() && s.tick() < 500) s.step({});
  ASSERT_FALSE(s.telemetry().respawns.empty()) << "the crouch did not fall";
  const int64_t r = s.telemetry().respawns.front();
  const auto& sw = s.telemetry().switches;
  ASSERT_GE(sw.size(), 2u);
  EXPECT_EQ(sw[0].from + ">" + sw[0].to, "stand>run");
  EXPECT_EQ(sw[1].from + ">" + sw[1].to, "run>walk");
  EXPECT_TRUE(sw[1].respawn);
  EXPECT_EQ(sw[1].tick, r + 1);
  EXPECT_EQ(s.activeSkillName(), "walk");
  EXPECT_EQ(s.command().vx, 0.0);  // W still held: it ramps up again from 0
  s.step({});
  EXPECT_NEAR(s.command().vx, 0.02, 1e-12);
}

TEST(Session, ASkillFromTheDefaultPoseAskedForAtTheSpawnWaitsAHopsTime) {
  // the standing controller holds the fresh spawn for kMinHopTicks before a key-pose skill (the jump) starts: asked
  // for at the first tick, the jump fell at its second landing in 20 of 20 seeds; the walk starts at once
  const robot::SkillTree shipped = robot::loadSkillTree(kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  robot::SkillSet set;
  for (const char* name : {"walk", "squat", "jump"})
    set.skills.push_back(
        {*shipped.find(name), [](const Eigen::MatrixXf&, Eigen::MatrixXf* a) { a->setZero(robot::kActionSize, 1); }});
  ASSERT_TRUE(robot::startsFromDefaultPose(set.byName("jump")->def));
  ASSERT_FALSE(robot::startsFromDefaultPose(set.byName("walk")->def));
  const levels::Level flat = levels::loadLevel(kSource + "/levels/flat");
  for (const char* key : {"4", "0"}) {
    game::Session s(flat, fixtures::robotModel(), game::SessionOptions{1, &set});
    s.step(engine::parseKeyScript(std::string("0.00 tap ") + key + "\n", "k"));
    while (s.telemetry().switches.empty() && s.tick() < 200) s.step({});
    ASSERT_EQ(s.telemetry().switches.size(), 1u) << key;
    EXPECT_EQ(s.telemetry().switches[0].from, "stand");
    EXPECT_EQ(s.telemetry().switches[0].tick, key[0] == '4' ? robot::kMinHopTicks : 0) << key;
  }
}

// a crawl that trained steered back toward its line ([training] line_steer) is steered so in play while W is held
// and no turn key is (the shipped walk and prone, then the crawl's prior alone): each tick's yaw-rate command is the
// training's law, wz = -k x (heading off the line + 0.5 x offset across it) averaged over a second, from the line
// the crawl began on; with line_steer 0 it stays 0
TEST(Session, ACrawlThatTrainedSteeredIsSteeredBackToItsLineInPlay) {
  const robot::SkillTree shipped = robot::loadSkillTree(kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  auto walk = std::make_shared<ai::LoadedPolicy>(ai::loadPolicyOnnx(kSource + "/assets/skills/walk.onnx"));
  auto prone = std::make_shared<ai::LoadedPolicy>(ai::loadPolicyOnnx(kSource + "/assets/skills/prone.onnx"));
  const levels::Level flat = levels::loadLevel(kSource + "/levels/flat");
  for (double gain : {0.0, 0.5}) {
    robot::SkillDef crawl = *shipped.find("crawl");
    crawl.commands.wz = {-0.05, 0.05};
    crawl.commands.lineSteer = gain;
    double observedWz = 0;
    robot::SkillSet skills;
    skills.skills.push_back(
        {*shipped.find("walk"), [walk](const Eigen::MatrixXf& o, Eigen::MatrixXf* a) { walk->act(o, a); }});
    skills.skills.push_back(
        {*shipped.find("prone"), [prone](const Eigen::MatrixXf& o, Eigen::MatrixXf* a) { prone->act(o, a); }});
    skills.skills.push_back({crawl, [&](const Eigen::MatrixXf& o, Eigen::MatrixXf* a) {
                               observedWz = o(robot::kObsCommand + 2, 0);
                               a->setZero(robot::kActionSize, 1);
                             }});
    game::Session s(flat, fixtures::robotModel(), game::SessionOptions{1, &skills});
    s.step(engine::parseKeyScript("0.00 tap 0\n",
                                  "k"));  // the walk, then key 9: through prone (the crawl once the robot lies still)
    while (s.tick() < 100) s.step({});
    s.step({{s.tick(), engine::KeyAction::kTap, '9'}});
    Eigen::Vector2d start, along;
    double averaged = 0, largest = 0;
    int steered = 0;
    int64_t crawlFrom = -1;
    while (s.tick() < 1600) {
      const robot::Sensors before = s.sensors();  // what this tick's command is made from
      const size_t switches = s.telemetry().switches.size();
      const bool pressW = crawlFrom >= 0 && s.tick() == crawlFrom + 10;  // W held from just after the crawl took over
      s.step(pressW ? std::vector<engine::KeyEvent>{{s.tick(), engine::KeyAction::kDown, 'W'}}
                    : std::vector<engine::KeyEvent>{});
      if (s.telemetry().switches.size() > switches && s.activeSkillName() == "crawl") {
        start = before.basePosition.head<2>(), along = robot::groundHeading(before), averaged = 0;
        crawlFrom = s.tick();
      }
      if (s.activeSkillName() != "crawl" || s.command().vx == 0.0) continue;
      robot::SkillCommand line;
      robot::lineIntoCommand(before, start, along, &line);
      const double expected = gain > 0 ? robot::steerTowardLine(crawl.commands, gain, line, &averaged) : 0.0;
      ASSERT_NEAR(observedWz, expected, 1e-6) << "tick " << s.tick() << ", line_steer " << gain;
      largest = std::max(largest, std::abs(observedWz));
      steered += observedWz != 0.0;
    }
    ASSERT_EQ(s.activeSkillName(), "crawl");
    ASSERT_LT(crawlFrom, 900);  // prone lay down and handed over within 8 s
    if (gain > 0) {
      EXPECT_GT(steered, 600);  // W held for at least 690 ticks
      EXPECT_GT(largest, 0.001);
      EXPECT_LE(largest, 0.05 + 1e-7);  // within the wz range (a float in the observation)
    } else {
      EXPECT_EQ(steered, 0);
    }
    EXPECT_FALSE(s.fallen());
  }
}
