// skill_runtime_test.cpp — the one control step and the switch as the runtime makes them, for every caller.
#include "robot/skill_runtime.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "engine/core/error.h"
#include "tests/fixtures.h"

namespace {

const robot::SkillTree& shippedTree() {
  static const robot::SkillTree tree =
      robot::loadSkillTree(fixtures::kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  return tree;
}

// the shipped tree's skills, each with a policy that answers every observation with the same small action
robot::SkillSet shippedSet() {
  robot::SkillSet set;
  for (const robot::SkillDef& def : shippedTree().skills)
    set.skills.push_back({def, [](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) {
                            *a = Eigen::MatrixXf::Constant(robot::kActionSize, obs.cols(), 0.3f);
                            a->row(3) = obs.row(robot::kObsAngularVelocity);  // (the knee follows an input)
                          }});
  return set;
}

// the robot standing on flat ground, its sensors read
struct Stand {
  engine::PhysicsWorld world;
  robot::Robot robot;
  robot::Sensors sensors;
  Stand() : robot((world.addGround(1.0), fixtures::robotModel()), world, 0, 0, 0.4), sensors(robot.sense(world)) {}
};

TEST(SkillRuntime, TheBatchedStepIsTheOneRobotStep) {
  // training and the cards observe every robot, run the policy once on the batch and act; play runs controlStep.
  // Both give the same targets and leave the same state.
  const robot::SkillSet set = shippedSet();
  Stand stand;
  const robot::RobotModel& model = fixtures::robotModel();
  robot::SkillCommand command;
  command.vx = 0.5;
  robot::SkillState one, batched;
  robot::enterSkill(&one, *set.byName("walk"), stand.sensors, 0);
  batched = one;
  for (int t = 0; t < 3; ++t) {
    robot::PdCommand a, b;
    robot::controlStep(model, model, &one, stand.sensors, stand.world, command, false, &a);
    Eigen::MatrixXf obs(robot::kObservationSize, 2), out;
    robot::observe(model, batched, stand.sensors, stand.world, command, obs.col(1).data());
    obs.col(0).setZero();  // another robot of the batch
    batched.active->policy(obs, &out);
    robot::act(model, &batched, out.col(1).data(), command, false, &b);
    for (int j = 0; j < robot::kNumJoints; ++j)
      EXPECT_EQ(a.target[size_t(j)], b.target[size_t(j)]) << "tick " << t << " joint " << j;
    EXPECT_EQ(one.phase.tp, batched.phase.tp);
    EXPECT_EQ(one.action, batched.action);
  }
  EXPECT_EQ(one.phase.tp, 3);  // the walk's clock ticked once per step
}

TEST(SkillRuntime, ASwitchKeepsTheActionCarriesTheClockAndFadesTheOldPrior) {
  const robot::SkillSet set = shippedSet();
  Stand stand;
  const robot::Skill& walk = *set.byName("walk");
  const robot::Skill& run = *set.byName("run");
  robot::SkillState s;
  robot::enterSkill(&s, walk, stand.sensors, 0);
  s.action.fill(0.25f);
  s.phase.tp = 30;
  robot::enterSkill(&s, run, stand.sensors, 77);
  EXPECT_EQ(s.active, &run);
  EXPECT_EQ(s.activeSince, 77);
  for (float a : s.action) EXPECT_EQ(a, 0.25f);  // the new network reads the same previous action
  EXPECT_EQ(s.fadingFrom, &walk);
  EXPECT_EQ(s.fadeTicks, robot::kSwitchFadeTicks);
  EXPECT_EQ(s.fadePhase.tp, 30);  // the walk's prior fades out on its own clock
  // the run's clock is at the same fraction of its cycle: 30 of the walk's 2 T1 ticks
  const int walkT1 = walk.def.prior.halfPeriodTicks, runT1 = run.def.prior.halfPeriodTicks;
  EXPECT_EQ(s.phase.tp, int(std::lround(30.0 * runT1 / walkT1)));
  // the run's own line starts where the robot stands, the way it faces (yaw 0.4)
  EXPECT_NEAR(s.lineAlong.x(), std::cos(0.4), 1e-6);
  EXPECT_NEAR(s.lineAlong.y(), std::sin(0.4), 1e-6);
}

TEST(SkillRuntime, FromTheStandingControllerASkillStartsFromZero) {
  const robot::SkillSet set = shippedSet();
  Stand stand;
  robot::SkillState s;
  s.action.fill(1.0f);
  s.phase.tp = 12;
  robot::enterSkill(&s, *set.byName("walk"), stand.sensors, 5);
  for (float a : s.action) EXPECT_EQ(a, 0.0f);
  EXPECT_EQ(s.phase.tp, 0);
  EXPECT_EQ(s.fadeTicks, 0);  // no prior to fade out
  EXPECT_EQ(s.fadingFrom, nullptr);
}

TEST(SkillRuntime, TheGateRoutesFromTheCrawlToTheWalkThroughTheStandUpAndChangesNothing) {
  const robot::SkillSet set = shippedSet();
  Stand stand;
  robot::SkillState s;
  robot::enterSkill(&s, *set.byName("prone"), stand.sensors, 0);
  robot::enterSkill(&s, *set.byName("crawl"), stand.sensors, 10);
  robot::SwitchRequest request;
  request.wanted = set.byName("walk");
  const robot::SkillState before = s;
  const robot::SwitchGate g = robot::switchGate(set, s, stand.sensors, request, 200);
  ASSERT_NE(g.next, nullptr);
  EXPECT_EQ(g.next->def.name, "standup");  // up the tree by the crawl's `up`, then the stand-up's way up
  EXPECT_EQ(s.postureWaitTicks, before.postureWaitTicks);  // the gate is pure: route() keeps the waits
  EXPECT_EQ(s.restWaitTicks, before.restWaitTicks);
  // the stand-up is a still skill: the crawl first brakes to rest; the robot just placed above the ground is not at
  // rest on both feet, so route() starts the brake, waits and counts the wait
  EXPECT_TRUE(g.brakes);
  const robot::RouteResult r = robot::route(set, &s, stand.sensors, request, 200);
  EXPECT_EQ(r.switchedTo, nullptr);
  EXPECT_EQ(s.active->def.name, "crawl");
  EXPECT_EQ(s.restWaitTicks, 0);
  EXPECT_EQ(s.postureWaitTicks, 1);
}

TEST(SkillRuntime, AReachedOrWithdrawnRequestClearsTheWaits) {
  const robot::SkillSet set = shippedSet();
  Stand stand;
  robot::SkillState s;
  robot::enterSkill(&s, *set.byName("walk"), stand.sensors, 0);
  s.postureWaitTicks = 40, s.restWaitTicks = 12;
  robot::SwitchRequest none;
  EXPECT_EQ(robot::route(set, &s, stand.sensors, none, 100).switchedTo, nullptr);
  EXPECT_EQ(s.postureWaitTicks, 0);
  EXPECT_EQ(s.restWaitTicks, -1);
}

}  // namespace

// a diverged policy or simulation is never a run that "stays up": the runtime stops it with an error, in play,
// training and the cards alike (they all act and observe through it)
TEST(SkillRuntime, ANonFiniteActionOrStateStopsTheStepWithAnError) {
  robot::SkillSet set = shippedSet();
  set.skills[0].policy = [](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) {
    *a = Eigen::MatrixXf::Zero(robot::kActionSize, obs.cols());
    (*a)(5, 0) = std::nanf("");
  };
  Stand stand;
  const robot::RobotModel& model = fixtures::robotModel();
  robot::SkillState state;
  robot::enterSkill(&state, set.skills[0], stand.sensors, 0);
  robot::PdCommand pd;
  try {
    robot::controlStep(model, model, &state, stand.sensors, stand.world, {}, false, &pd);
    ADD_FAILURE() << "a NaN action was taken";
  } catch (const engine::Error& e) {
    EXPECT_NE(std::string(e.what()).find("non-finite action from the policy of skill '" + set.skills[0].def.name +
                                         "' (output 5)"),
              std::string::npos)
        << e.what();
  }
  robot::Sensors diverged = stand.sensors;
  diverged.qd[3] = std::numeric_limits<double>::infinity();
  Eigen::MatrixXf obs(robot::kObservationSize, 1);
  EXPECT_THROW(robot::observe(model, state, diverged, stand.world, {}, obs.data()), engine::Error);
}
