// pose_prior_test.cpp — the squat's key-pose prior alone (zero policy output) is a feasible, balanced pose:
// the G1 lowers into it and holds it, with the pelvis at the height the skill tree documents for depth 1.
#include <gtest/gtest.h>

#include "engine/loop/clock.h"
#include "engine/physics/physics_world.h"
#include "game/session.h"
#include "robot/robot.h"
#include "robot/skill_controller.h"
#include "tests/fixtures.h"

TEST(PosePrior, FullSquatPoseHoldsThePelvisAtTheDocumentedHeight) {
  const robot::RobotModel& model = fixtures::robotModel();
  const robot::SkillTree tree = robot::loadSkillTree(fixtures::kSource + "/assets/skills/tree.toml", model);
  const robot::SkillDef& squat = *tree.find("squat");
  engine::PhysicsWorld world;
  world.addGround(1.0);
  robot::Robot r(model, world, 0, 0, 0);
  const std::array<float, robot::kActionSize> zero{};
  robot::SkillCommand command;
  double minHeight = 1e9, maxTilt = 0;
  for (int tick = 0; tick < 500; ++tick) {
    command.amplitude = std::min(1.0, tick / 200.0);  // 2 s down, then 3 s held
    robot::PdCommand pd;
    robot::skillPdCommand(model, squat, zero, 0, command, &pd);
    r.setCommand(pd);
    for (int k = 0; k < game::kSubsteps; ++k) {
      r.applyPd(world);
      world.step(game::kSubstepSeconds);
    }
    const robot::Sensors s = r.sense(world);
    minHeight = std::min(minHeight, s.basePosition.z());
    maxTilt = std::max(maxTilt, s.tilt);
  }
  const robot::Sensors s = r.sense(world);
  std::printf("full squat: pelvis %.4f m, min %.4f, max tilt %.3f rad, drift %.3f m\n", s.basePosition.z(), minHeight,
              maxTilt, s.basePosition.head<2>().norm());
  EXPECT_NEAR(s.basePosition.z(), squat.commands.pelvisHeight.hi, 0.02);
  EXPECT_LT(maxTilt, 0.3);
}

TEST(PosePrior, OneLegPoseLiftsTheRightSoleAboveTheCardHeight) {
  // kinematics only (no physics): with the pelvis where it stands, the folded right leg's sole is >= 0.1 m up
  const robot::RobotModel& model = fixtures::robotModel();
  const robot::SkillTree tree = robot::loadSkillTree(fixtures::kSource + "/assets/skills/tree.toml", model);
  const robot::SkillDef& oneLeg = *tree.find("one_leg");
  engine::PhysicsWorld world;  // no ground: the robot is only posed, never stepped
  robot::Robot r(model, world, 0, 0, 0);
  const std::array<float, robot::kActionSize> zero{};
  robot::SkillCommand command;
  command.amplitude = 1.0;
  robot::PdCommand pd;
  robot::skillPdCommand(model, oneLeg, zero, 0, command, &pd);
  r.teleport(world, r.linkPose(world, -1), pd.target);
  const robot::Sensors s = r.sense(world);
  EXPECT_NEAR(s.footHeight[0], 0.0, 0.01);  // the left leg is untouched
  EXPECT_GT(s.footHeight[1], 0.10);
  EXPECT_LT(s.footHeight[1], 0.20);
}
