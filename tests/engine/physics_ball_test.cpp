// physics_ball_test.cpp — balls (dynamic spheres): free fall, resting on the ground, rolling, and state hashing.
#include <gtest/gtest.h>

#include "engine/physics/physics_world.h"

TEST(PhysicsBall, FallsHalfGTSquaredThenRestsOnItsRadius) {
  engine::PhysicsWorld world;
  world.addGround(1.0);
  engine::BallDef def;
  const engine::BallId ball = world.addBall(def, Eigen::Vector3d(0, 0, 1.0));
  for (int i = 0; i < 100; ++i) world.step(0.002);  // 0.2 s: 0.5 * 9.81 * 0.04 = 0.1962 m
  EXPECT_NEAR(world.ballState(ball).position.z(), 1.0 - 0.1962, 0.003);
  for (int i = 0; i < 2500; ++i) world.step(0.002);  // 5 s: bounces die out
  const engine::BallState s = world.ballState(ball);
  EXPECT_NEAR(s.position.z(), def.radius, 0.005);
  EXPECT_LT(s.velocity.norm(), 0.02);
}

TEST(PhysicsBall, AKickedBallRollsForwardAndSlowsDown) {
  engine::PhysicsWorld world;
  world.addGround(1.0);
  engine::BallDef def;
  const engine::BallId ball = world.addBall(def, Eigen::Vector3d(0, 0, def.radius));
  engine::BallState s = world.ballState(ball);
  s.velocity = Eigen::Vector3d(3.0, 0, 0);
  world.setBallState(ball, s);
  for (int i = 0; i < 500; ++i) world.step(0.002);  // 1 s
  s = world.ballState(ball);
  EXPECT_GT(s.position.x(), 1.5);  // it rolled on (sliding friction turns some speed into spin)
  EXPECT_LT(s.position.x(), 3.0);  // but never faster than it was kicked
  EXPECT_LT(s.velocity.x(), 3.0);
  EXPECT_GT(s.velocity.x(), 0.5);
  EXPECT_NEAR(s.position.y(), 0.0, 1e-6);
}

TEST(PhysicsBall, BallStateIsPartOfTheWorldHash) {
  engine::PhysicsWorld a, b;
  a.addGround(1.0);
  b.addGround(1.0);
  a.addBall({}, Eigen::Vector3d(0, 0, 0.5));
  b.addBall({}, Eigen::Vector3d(0, 0, 0.5));
  EXPECT_EQ(a.stateHash(), b.stateHash());
  engine::BallState s = b.ballState(0);
  s.velocity.x() = 0.1;
  b.setBallState(0, s);
  EXPECT_NE(a.stateHash(), b.stateHash());
}
