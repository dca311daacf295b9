// robot_test.cpp — the G1 in Bullet: frames agree with forward kinematics, gravity is right, PD clamps
// torque, and the standing controller holds the robot up.
#include "robot/robot.h"

#include <gtest/gtest.h>

#include <cmath>

#include "game/play.h"
#include "levels/level.h"
#include "robot/kinematics.h"
#include "tests/fixtures.h"

namespace {

using fixtures::kSource;

const robot::RobotModel& model() { return fixtures::robotModel(); }

}  // namespace

TEST(PhysicsWorld, LinkPosesMatchForwardKinematics) {
  // the btMultiBody built from link frames must put every link where pure-Eigen FK says (float precision)
  engine::PhysicsWorld world;
  robot::Robot r(model(), world, 0.3, -0.2, 0.5);
  const robot::JointArray q = r.command().target;
  const std::vector<Eigen::Isometry3d> fk = robot::forwardKinematics(model().articulation, {q.begin(), q.end()});
  const Eigen::Isometry3d base = r.linkPose(world, -1);
  for (int link = 0; link < robot::kNumJoints; ++link) {
    const Eigen::Isometry3d expected = base * fk[size_t(link) + 1];
    const Eigen::Isometry3d actual = r.linkPose(world, link);
    EXPECT_LT((expected.translation() - actual.translation()).norm(), 1e-5) << model().joints[size_t(link)].name;
    EXPECT_LT((expected.linear() - actual.linear()).norm(), 1e-5) << model().joints[size_t(link)].name;
  }
}

TEST(PhysicsWorld, FreeFallDropsHalfGTSquared) {
  // no ground, no torques: after 0.2 s the pelvis falls 0.5 * 9.81 * 0.2^2 = 0.1962 m
  engine::PhysicsWorld world;
  robot::Robot r(model(), world, 0, 0, 0);
  const double z0 = r.sense(world).basePosition.z();
  for (int i = 0; i < 100; ++i) world.step(0.002);
  EXPECT_NEAR(z0 - r.sense(world).basePosition.z(), 0.1962, 0.002);
}

TEST(PdController, TorqueIsClampedToTheEffortLimit) {
  engine::PhysicsWorld world;
  robot::Robot r(model(), world, 0, 0, 0);
  robot::PdCommand c = r.command();
  c.target[3] += 1.0;  // knee: kp 750 * 1 rad = 750 N m wanted, limit 139 N m
  c.target[4] -= 0.1;  // ankle: 400 * 0.1 = 40 N m wanted, under the 50 N m limit
  r.setCommand(c);
  r.applyPd(world);
  EXPECT_DOUBLE_EQ(r.lastTorques()[3], 139.0);
  EXPECT_NEAR(r.lastTorques()[4], -40.0, 1e-4);
}

TEST(StandingController, HoldsTheG1UprightForSixtySeconds) {
  const levels::Level flat = levels::parseLevel("name = \"flat\"\n", "flat.toml");
  game::PlayOptions o;
  o.ticks = 6000;
  o.seed = 3;
  const game::PlayResult r = game::play(flat, model(), o);
  EXPECT_FALSE(r.fallen);
  EXPECT_NEAR(r.finalSensors.basePosition.z(), 0.783, 0.01);
  EXPECT_LT(r.finalSensors.basePosition.head<2>().norm(), 0.05);  // drift under 5 cm
  EXPECT_LT(r.telemetry.maxTilt, 0.1);
}

TEST(Sensors, FeetCarryTheWholeWeightWhenStanding) {
  engine::PhysicsWorld world;
  world.addGround(1.0);
  robot::Robot r(model(), world, 0, 0, 0);
  for (int i = 0; i < 500; ++i) {
    r.applyPd(world);
    world.step(0.002);
  }
  const robot::Sensors s = r.sense(world);
  // m g = 32.106 kg * 9.81 m/s^2 = 314.96 N, shared by both feet
  EXPECT_NEAR(s.footForce[0] + s.footForce[1], 314.96, 0.03 * 314.96);
  EXPECT_TRUE(s.footContact[0]);
  EXPECT_TRUE(s.footContact[1]);
  EXPECT_NEAR(s.projectedGravity.z(), -1.0, 0.01);
  EXPECT_LT(s.linearVelocity.norm(), 0.05);
  // whole-body CoM about 0.69 m up (FACTS §1: 0.691 m in the default pose)
  EXPECT_NEAR(s.centreOfMass.z(), 0.691, 0.01);
  // soles on the ground (within the contact margin)
  EXPECT_NEAR(s.footHeight[0], 0.0, 0.005);
  EXPECT_NEAR(s.footHeight[1], 0.0, 0.005);
}

TEST(Sensors, YawAndBodyFrameVelocityFollowTheBase) {
  engine::PhysicsWorld world;
  robot::Robot r(model(), world, 0, 0, 0.7);
  const robot::Sensors s = r.sense(world);
  EXPECT_NEAR(s.yaw, 0.7, 1e-5);
  EXPECT_NEAR(s.roll, 0.0, 1e-5);
  EXPECT_NEAR(s.pitch, 0.0, 1e-5);
}
