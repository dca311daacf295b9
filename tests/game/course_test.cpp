// course_test.cpp — the game rules of a level, driven directly with a synthetic robot (sensors and body
// spheres), so each rule is checked with hand-placed positions.
#include "game/course.h"

#include <gtest/gtest.h>

#include "engine/loop/clock.h"

namespace {

const char* kCourse = R"(name = "c"
time_limit = 60.0
[rules]
falls = "respawn"
fall_penalty = 50
coin_value = 10
gift_value = 50
win_bonus = 100
checkpoints = [10.0]
[[coin]]
centre = [2.0, 0.0, 0.9]
[[question_box]]
centre = [5.0, 0.0, 1.53]
content = "gift"
[[ghost]]
appear_x = 3.0
behind = 2.0
height = 0.8
radius = 0.4
speed = 1.0
acceleration = 0.0
max_speed = 1.0
catch_distance = 0.3
vanish_x = 20.0
[[ball]]
position = [30.0, 0.0]
[[goal]]
centre = [33.0, 0.0, 0.5]
size = [1.0, 2.0, 1.0]
)";

struct World {
  levels::Level level = levels::parseLevel(kCourse, "c.toml");
  engine::PhysicsWorld physics;
  engine::PlaneWorld plane;
  game::Course course{level, physics, plane};
  robot::Sensors sensors;
  int64_t tick = 0;

  World() { physics.addGround(1.0); }
  // one tick with the pelvis at (x, 0, z) moving up at vz, and the given body spheres
  void step(double x, double z, double vz, const std::vector<game::BodyPoint>& body) {
    sensors.basePosition = Eigen::Vector3d(x, 0, z);
    sensors.linearVelocity = Eigen::Vector3d(0, 0, vz);
    physics.step(0.01);
    plane.step(0.01);
    course.update(tick++, sensors, body, physics, plane);
  }
};

}  // namespace

TEST(Course, TouchingACoinCollectsItOnce) {
  World w;
  w.step(0, 0.78, 0, {{Eigen::Vector3d(1.5, 0, 0.9), 0.05}});  // 0.5 m away: no
  EXPECT_EQ(w.course.coins(), 0);
  w.step(0, 0.78, 0, {{Eigen::Vector3d(1.9, 0, 0.9), 0.05}});  // 0.1 m <= 0.15 + 0.05
  EXPECT_EQ(w.course.coins(), 1);
  EXPECT_EQ(w.course.score(), 10);
  w.step(0, 0.78, 0, {{Eigen::Vector3d(2.0, 0, 0.9), 0.05}});
  EXPECT_EQ(w.course.score(), 10);  // already gone
}

TEST(Course, AHeadGoingUpUnderAQuestionBoxReleasesItsGift) {
  World w;  // the pelvis stays past the ghost's vanish_x: only the head and hands matter here
  const double bottom = 1.53 - 0.2;
  // a head under the box but not moving up: nothing
  w.step(25.0, 0.78, 0.0, {{Eigen::Vector3d(5.0, 0, bottom - 0.05), 0.04, true}});
  ASSERT_TRUE(w.course.events().empty() || w.course.events().back().what.find("hit") == std::string::npos);
  // a hand (not head) moving up, but too far below: nothing
  w.step(25.0, 0.78, 0.5, {{Eigen::Vector3d(5.0, 0, bottom - 0.2), 0.04, false, true}});
  // the head touching it from below while rising: the box releases a gift
  w.step(25.0, 0.80, 0.5, {{Eigen::Vector3d(5.0, 0, bottom - 0.05), 0.04, true}});
  bool hit = false;
  for (const auto& e : w.course.events()) hit = hit || e.what.find("hit: a gift") != std::string::npos;
  ASSERT_TRUE(hit);
  // it rises, then floats down to 0.9 m, 0.6 m past the box, where the robot picks it up
  for (int i = 0; i < 150; ++i) w.step(25.0, 0.78, 0, {});
  EXPECT_EQ(w.course.gifts(), 0);
  w.step(25.0, 0.78, 0, {{Eigen::Vector3d(5.6, 0, 0.9), 0.05}});
  EXPECT_EQ(w.course.gifts(), 1);
  EXPECT_EQ(w.course.score(), 50);
}

TEST(Course, AGhostAppearsBehindChasesAndCatchesAStandingRobot) {
  World w;
  w.step(2.9, 0.78, 0, {});
  EXPECT_LT(w.course.ghostDistance(), 0);  // not yet
  w.step(3.0, 0.78, 0, {});                // wakes 2 m behind, at 0.8 m height
  for (int i = 0; i < 10; ++i) w.step(3.0, 0.78, 0, {});
  // 1 m/s for 0.1 s (the first tick only placed it): about 1.6 m - 0.4 m radius - 0.1 m left
  EXPECT_NEAR(w.course.ghostDistance(), 2.0 - 0.4 - 0.1, 0.02);
  for (int i = 0; i < 200 && w.course.outcome() == game::Outcome::Playing; ++i) w.step(3.0, 0.78, 0, {});
  EXPECT_EQ(w.course.outcome(), game::Outcome::Lost);
  EXPECT_EQ(w.course.outcomeReason(), "caught by the ghost");
}

TEST(Course, AGhostGivesUpWhenTheRobotGetsAway) {
  World w;
  w.step(3.0, 0.78, 0, {});
  w.step(20.0, 0.78, 0, {});  // past vanish_x
  for (int i = 0; i < 300; ++i) w.step(20.0, 0.78, 0, {});
  EXPECT_EQ(w.course.outcome(), game::Outcome::Playing);
  EXPECT_LT(w.course.ghostDistance(), 0);
}

TEST(Course, AFallBackBeforeWhereTheGhostWokePutsItToSleepUntilThenAgain) {
  World w;
  w.step(3.0, 0.78, 0, {});  // wakes 2 m behind
  for (int i = 0; i < 100; ++i) w.step(3.0, 0.78, 0, {});
  ASSERT_GT(w.course.ghostDistance(), 0);
  ASSERT_TRUE(w.course.onFall(w.tick));  // back to x = 0 (no checkpoint passed), before appear_x = 3
  w.step(0.0, 0.78, 0, {});
  EXPECT_LT(w.course.ghostDistance(), 0);  // asleep: no ghost ...
  const engine::RayHit h = w.plane.rayCast({-5.0, 0.8}, {3.0, 0.8});
  EXPECT_FALSE(h.hit);  // ... and nothing left where it was for the autopilot's rays to meet
  for (int i = 0; i < 300; ++i) w.step(2.0, 0.78, 0, {});
  EXPECT_EQ(w.course.outcome(), game::Outcome::Playing);
  w.step(3.0, 0.78, 0, {});  // past appear_x again: 2 m behind, at its first speed
  w.step(3.0, 0.78, 0, {});
  EXPECT_NEAR(w.course.ghostDistance(), 2.0 - 0.4, 0.03);
}

TEST(Course, BallInTheGoalWinsWithTheBonusAndTheTimeLeft) {
  World w;
  engine::BallState s = w.physics.ballState(w.course.firstBall());
  s.position = Eigen::Vector3d(33.0, 0.0, 0.11);
  w.physics.setBallState(w.course.firstBall(), s);
  w.step(29.0, 0.78, 0, {});  // at 0.00 s: 60 s left
  EXPECT_EQ(w.course.outcome(), game::Outcome::Won);
  EXPECT_EQ(w.course.score(), 100 + 60);
}

TEST(Course, FallsRespawnAtTheLastCheckpointWithAPenaltyAndTimeRunsOut) {
  World w;
  EXPECT_TRUE(w.course.onFall(0));
  EXPECT_EQ(w.course.score(), -50);
  EXPECT_DOUBLE_EQ(w.course.respawnX(), 0.0);
  w.step(10.5, 0.78, 0, {});  // passes the checkpoint
  EXPECT_DOUBLE_EQ(w.course.respawnX(), 10.0);
  w.tick = engine::secondsToTicks(60.0);
  w.step(20.0, 0.78, 0, {});
  EXPECT_EQ(w.course.outcome(), game::Outcome::Lost);
  EXPECT_EQ(w.course.outcomeReason(), "time is up");
}

TEST(Course, UnderTheLoseRuleAFallEndsTheLevel) {
  std::string text = kCourse;
  text.replace(text.find("\"respawn\""), 9, "\"lose\"");
  const levels::Level level = levels::parseLevel(text, "c.toml");
  engine::PhysicsWorld physics;
  engine::PlaneWorld plane;
  game::Course course(level, physics, plane);
  EXPECT_FALSE(course.onFall(5));
  EXPECT_EQ(course.outcome(), game::Outcome::Lost);
  EXPECT_EQ(course.outcomeReason(), "fell");
}
