// nav_navigator_test.cpp — the garden's path follower and navigator (game/nav/): the interlock, the obstacle factor,
// the skill choice, squaring up to stairs, replanning and stuck detection in the navigator, closed loop with a
// unicycle.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/plane/plane_tags.h"
#include "engine/plane/plane_world.h"
#include "game/nav/follower.h"
#include "game/nav/navigator.h"
#include "tests/game/nav_maps.h"

namespace {

using game::nav::NavSkill;
using namespace nav_maps;

TEST_F(NavCorridor, TheNavigatorReplansWhenABallAppearsOnItsPath) {
  game::nav::NavigatorParams params;
  params.grid = coarseRoom();
  game::nav::Navigator nav(plane, params);
  nav.setTarget(goal);
  game::nav::NavInput in;
  in.position = start;
  game::nav::NavOutput out = nav.step(plane, in, 0.01);
  EXPECT_TRUE(out.events.replanned);
  EXPECT_FALSE(out.events.blocked);
  EXPECT_NEAR(nav.path().gridCost, bottom, 1e-9);
  out = nav.step(plane, in, 0.01);
  EXPECT_FALSE(out.events.replanned);

  plane.addKinematicCircle(V2(5.0, 0.4), 0.2, engine::kMovableTagBase);
  out = nav.step(plane, in, 0.01);
  EXPECT_TRUE(out.events.blocked);
  EXPECT_TRUE(out.events.replanned);
  EXPECT_EQ(out.state, game::nav::NavState::Following);
  EXPECT_NEAR(nav.path().gridCost, top, 1e-9);
  // the new path is clear: no more replans while the ball stays
  for (int i = 0; i < 200; ++i) EXPECT_FALSE(nav.step(plane, in, 0.01).events.replanned) << "tick " << i;
}

TEST_F(NavCorridor, WithBothGapsBlockedTheNavigatorStandsAndRetries) {
  plane.addKinematicCircle(V2(5.0, 0.4), 0.2, engine::kMovableTagBase);
  plane.addKinematicCircle(V2(5.0, 5.6), 0.2, engine::kMovableTagBase + 1);
  game::nav::NavigatorParams params;
  params.grid = coarseRoom();
  params.movableWindow = 6.0;
  game::nav::Navigator nav(plane, params);
  nav.setTarget(goal);
  game::nav::NavInput in;
  in.position = start;
  game::nav::NavOutput out = nav.step(plane, in, 0.01);
  EXPECT_TRUE(out.events.noPath);
  EXPECT_EQ(out.state, game::nav::NavState::NoPath);
  EXPECT_EQ(out.command.vr, 0.0);
  EXPECT_EQ(out.command.wr, 0.0);
  int retries = 0;
  for (int i = 0; i < 250; ++i) retries += nav.step(plane, in, 0.01).events.replanned;
  EXPECT_EQ(retries, 2);  // after 1 s and 2 s (retrySeconds)
}

// ---- the follower -------------------------------------------------------------------------------------------------

TEST(NavFollower, TheInterlockBoundaryRunsFromFullSpeedToTheMinimumAtFullTurn) {
  const game::nav::FollowerParams p;
  // walk: (0, 1.0) - (0.2, 1.0) - (1.0, 0.0)
  EXPECT_DOUBLE_EQ(game::nav::interlockLimit(p.walk, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(game::nav::interlockLimit(p.walk, 0.2), 1.0);
  EXPECT_NEAR(game::nav::interlockLimit(p.walk, 0.6), 0.5, 1e-12);   // half way from 0.2 to 1.0
  EXPECT_NEAR(game::nav::interlockLimit(p.walk, -0.6), 0.5, 1e-12);  // both ways
  EXPECT_DOUBLE_EQ(game::nav::interlockLimit(p.walk, 1.0), p.walk.vMin);
  EXPECT_DOUBLE_EQ(game::nav::interlockLimit(p.walk, 1.0), 0.0);
  // run: (0, 1.5) - (0.2, 1.5) - (0.5, 0.8)
  EXPECT_NEAR(game::nav::interlockLimit(p.run, 0.35), 1.15, 1e-12);
  EXPECT_DOUBLE_EQ(game::nav::interlockLimit(p.run, 0.5), 0.8);
}

TEST(NavFollower, AtFullTurnTheForwardSpeedIsTheMinimum) {
  engine::PlaneWorld plane;
  game::nav::PathFollower f;
  // the path goes off to the left at 90 degrees: a full turn (1 rad/s) and the walk's vMin, 0
  const game::nav::Path left = handMadePath({V2(0, 0), V2(0, 4)});
  game::nav::NavCommand c = f.follow(left, plane, V2(0, 0), 0.0, 0.0);
  EXPECT_EQ(c.skill, NavSkill::Walk);
  EXPECT_DOUBLE_EQ(c.wr, 1.0);
  EXPECT_DOUBLE_EQ(c.vr, 0.0);
  // 0.4 rad off: wr = 1.0 x 0.4 = 0.4, vr = 1 - (0.4 - 0.2) / 0.8 = 0.75
  f = game::nav::PathFollower();
  const game::nav::Path ahead = handMadePath({V2(0, 0), V2(4, 0)});  // too short to run
  c = f.follow(ahead, plane, V2(0, 0), -0.4, 0.0);
  EXPECT_NEAR(c.wr, 0.4, 1e-12);
  EXPECT_NEAR(c.vr, 0.75, 1e-12);
  // straight on: full speed
  c = f.follow(ahead, plane, V2(0, 0), 0.0, 0.0);
  EXPECT_DOUBLE_EQ(c.wr, 0.0);
  EXPECT_DOUBLE_EQ(c.vr, 1.0);
  // 0.4 m before the end: vr = 1.0 x 0.4 (arrival)
  c = f.follow(ahead, plane, V2(3.6, 0), 0.0, 0.0);
  EXPECT_NEAR(c.vr, 0.4, 1e-9);
}

TEST(NavFollower, ObstacleFactorIsOneWhenClearAndZeroAtContact) {
  engine::PlaneWorld plane;
  addRect(plane, 3.0, -2.0, 4.0, 2.0);  // a wall face at x = 3
  const game::nav::FollowerParams p;    // 0 at 0.35 m from the pelvis, 1 from 1.5 m
  double nearest = 0;
  EXPECT_DOUBLE_EQ(game::nav::obstacleFactor(plane, V2(0, 0), 0.0, p, &nearest), 1.0);  // 3 m away
  EXPECT_NEAR(nearest, 1e9, 1);                                                         // beyond the rays
  EXPECT_DOUBLE_EQ(game::nav::obstacleFactor(plane, V2(1.4, 0), 0.0, p), 1.0);          // 1.6 m
  // 0.925 m: (0.925 - 0.35) / (1.5 - 0.35) = 0.5
  EXPECT_NEAR(game::nav::obstacleFactor(plane, V2(3.0 - 0.925, 0), 0.0, p, &nearest), 0.5, 1e-5);
  EXPECT_NEAR(nearest, 0.925, 1e-5);
  EXPECT_NEAR(game::nav::obstacleFactor(plane, V2(3.0 - 0.35, 0), 0.0, p), 0.0, 1e-5);  // touching
  EXPECT_DOUBLE_EQ(game::nav::obstacleFactor(plane, V2(3.0 - 0.2, 0), 0.0, p), 0.0);
  // facing away it is clear
  EXPECT_DOUBLE_EQ(game::nav::obstacleFactor(plane, V2(3.0 - 0.35, 0), M_PI, p), 1.0);
  // a wall beside the way, 0.3 m from the pelvis's line, is outside the rays (0.25 m): clear
  engine::PlaneWorld corridor;
  addRect(corridor, 0.0, 0.3, 5.0, 1.0);
  EXPECT_DOUBLE_EQ(game::nav::obstacleFactor(corridor, V2(0, 0), 0.0, p), 1.0);
}

TEST(NavFollower, ObstacleFactorSeesBallsAndLooksThroughStairs) {
  const game::nav::FollowerParams p;
  engine::PlaneWorld stairs;
  addRect(stairs, 1.0, -1.0, 1.3, 1.0, engine::stairTag(0.0));  // two steps, right ahead
  addRect(stairs, 1.3, -1.0, 1.6, 1.0, engine::stairTag(0.0));
  EXPECT_DOUBLE_EQ(game::nav::obstacleFactor(stairs, V2(0, 0), 0.0, p), 1.0);
  addRect(stairs, 1.6, -1.0, 2.0, 1.0);  // a wall at the top, 1.6 m: still clear
  EXPECT_DOUBLE_EQ(game::nav::obstacleFactor(stairs, V2(0, 0), 0.0, p), 1.0);
  // from on the first step the wall is 1.1 m ahead: (1.1 - 0.35) / 1.15
  EXPECT_NEAR(game::nav::obstacleFactor(stairs, V2(0.5, 0), 0.0, p), 0.75 / 1.15, 1e-5);

  engine::PlaneWorld ball;
  ball.addKinematicCircle(V2(1.0, 0.1), 0.11, engine::kMovableTagBase);
  const double f = game::nav::obstacleFactor(ball, V2(0, 0), 0.0, p);
  EXPECT_GT(f, 0.4);
  EXPECT_LT(f, 0.6);  // its near side at ~0.9 m: about 0.48
}

// ---- the skill choice ---------------------------------------------------------------------------------------------

TEST(NavSkillChoice, RunsOnlyOnALongStraightFacingAlongIt) {
  const game::nav::FollowerParams p;
  game::nav::SkillCues c;
  c.straightAhead = 6.0;
  EXPECT_EQ(game::nav::chooseSkill(c, p), NavSkill::Run);  // >= 5 m, facing it, nothing ahead
  c.straightAhead = 4.9;
  EXPECT_EQ(game::nav::chooseSkill(c, p), NavSkill::Walk);
  c.straightAhead = 6.0, c.headingError = 0.2;
  EXPECT_EQ(game::nav::chooseSkill(c, p), NavSkill::Walk);  // > 0.15 rad off
  c.headingError = 0.0, c.obstacleFactor = 0.9;
  EXPECT_EQ(game::nav::chooseSkill(c, p), NavSkill::Walk);  // something ahead
}

TEST(NavSkillChoice, ARunKeepsGoingUntilTheStraightRunsOut) {
  const game::nav::FollowerParams p;
  game::nav::SkillCues c;
  c.current = NavSkill::Run;
  c.straightAhead = 3.0, c.headingError = 0.25, c.obstacleFactor = 0.85;
  EXPECT_EQ(game::nav::chooseSkill(c, p), NavSkill::Run);  // within every leave threshold
  c.straightAhead = 2.4;
  EXPECT_EQ(game::nav::chooseSkill(c, p), NavSkill::Walk);  // < 2.5 m left
  c.straightAhead = 3.0, c.headingError = 0.35;
  EXPECT_EQ(game::nav::chooseSkill(c, p), NavSkill::Walk);
  c.headingError = 0.0, c.obstacleFactor = 0.7;
  EXPECT_EQ(game::nav::chooseSkill(c, p), NavSkill::Walk);
}

TEST(NavSkillChoice, StairsOnlyOnceSquaredUpAndSlow) {
  const game::nav::FollowerParams p;
  game::nav::SkillCues c;
  c.straightAhead = 20.0;  // a long straight does not matter at stairs
  c.stairsZone = true;
  c.squaredUp = false;
  EXPECT_EQ(game::nav::chooseSkill(c, p), NavSkill::Walk);
  c.squaredUp = true, c.speed = 0.8;
  EXPECT_EQ(game::nav::chooseSkill(c, p), NavSkill::Walk);  // slowing first (> 0.4 m/s)
  c.speed = 0.3;
  EXPECT_EQ(game::nav::chooseSkill(c, p), NavSkill::Stairs);
  c.current = NavSkill::Stairs, c.squaredUp = false, c.speed = 0.5;
  EXPECT_EQ(game::nav::chooseSkill(c, p), NavSkill::Stairs);  // once on them, kept to the zone's end
  c.stairsZone = false, c.straightAhead = 1.0;
  EXPECT_EQ(game::nav::chooseSkill(c, p), NavSkill::Walk);
}

TEST(NavFollower, SquaresUpToTheStairsBeforeTakingThem) {
  engine::PlaneWorld plane;
  addRect(plane, 4.0, 2.0, 6.0, 4.0, engine::stairTag(0.0));  // stairs 2 m wide along +X, x 4-6
  addRect(plane, 4.0, 0.0, 6.0, 1.2);                         // walls either side
  addRect(plane, 4.0, 4.8, 6.0, 6.0);
  const game::nav::OccupancyGrid g = game::nav::buildOccupancyGrid(plane, coarseRoom());
  const game::nav::Path path = game::nav::planPath(g, V2(1.25, 2.75), V2(8.75, 3.25));
  ASSERT_TRUE(path.found);
  ASSERT_EQ(path.stairs.size(), 1u);
  const double s0 = path.stairs[0].from;  // 3.5 m of x from the start, give or take a sample
  EXPECT_NEAR(path.pointAt(s0).x(), 3.5, 0.15);

  game::nav::PathFollower f;
  game::nav::FollowInfo info;
  // well before the zone (2.0 m before the span), turned 0.5 rad off: ordinary heading control, walk
  game::nav::NavCommand c = f.follow(path, plane, path.pointAt(s0 - 2.0), 0.5, 0.0, &info);
  EXPECT_FALSE(info.stairsZone);
  EXPECT_EQ(c.skill, NavSkill::Walk);
  EXPECT_GT(c.vr, 0.0);
  // in the zone (0.5 m before the span), turned 0.5 rad left of its heading: stop and turn right in place
  const V2 inZone = path.pointAt(s0 - 0.5);
  c = f.follow(path, plane, inZone, 0.5, 0.6, &info);
  EXPECT_TRUE(info.stairsZone);
  EXPECT_TRUE(info.squaringUp);
  EXPECT_EQ(c.skill, NavSkill::Walk);
  EXPECT_DOUBLE_EQ(c.vr, 0.0);
  EXPECT_DOUBLE_EQ(c.wr, -0.5);  // 1.0 x 0.5 rad
  // square (0.05 rad, within 0.1) but still at 0.6 m/s: the walk, slowed to 0.3 m/s
  c = f.follow(path, plane, inZone, 0.05, 0.6, &info);
  EXPECT_FALSE(info.squaringUp);
  EXPECT_EQ(c.skill, NavSkill::Walk);
  EXPECT_LE(c.vr, 0.3 + 1e-12);
  // square and slow: the stairs at their speed
  c = f.follow(path, plane, inZone, 0.05, 0.3, &info);
  EXPECT_EQ(c.skill, NavSkill::Stairs);
  EXPECT_NEAR(c.vr, 0.5, 1e-12);
  EXPECT_LE(std::abs(c.wr), 0.3 + 1e-12);
  // and they stay until 0.2 m past the span, then the walk again
  c = f.follow(path, plane, path.pointAt(path.stairs[0].to + 0.1), 0.0, 0.5, &info);
  EXPECT_EQ(c.skill, NavSkill::Stairs);
  c = f.follow(path, plane, path.pointAt(path.stairs[0].to + 0.3), 0.0, 0.5, &info);
  EXPECT_EQ(c.skill, NavSkill::Walk);
}

// ---- the navigator ----------------------------------------------------------------------------------------------

TEST(NavNavigator, StuckAfterFiveSecondsWithoutProgressAndNotBefore) {
  engine::PlaneWorld plane;
  game::nav::NavigatorParams params;
  params.grid = coarseRoom();
  game::nav::Navigator nav(plane, params);
  nav.setTarget(V2(8.75, 1.25));
  game::nav::NavInput in;  // the robot does not move: asked forward, it makes no progress
  in.position = V2(1.25, 1.25);
  for (int tick = 1; tick < 500; ++tick) {
    const game::nav::NavOutput out = nav.step(plane, in, 0.01);
    ASSERT_FALSE(out.events.stuck) << "at " << tick * 0.01 << " s";
    ASSERT_GT(out.command.vr, 0.0);
  }
  game::nav::NavOutput out = nav.step(plane, in, 0.01);  // 5.00 s of no progress
  EXPECT_TRUE(out.events.stuck);
  EXPECT_EQ(out.state, game::nav::NavState::BackingOff);
  EXPECT_DOUBLE_EQ(out.command.vr, -0.3);
  EXPECT_DOUBLE_EQ(out.command.wr, 0.0);
  // backing off for 1 s, then a replan (around the spot ahead, marked blocked) and on again
  for (int tick = 1; tick < 100; ++tick) {
    out = nav.step(plane, in, 0.01);
    ASSERT_EQ(out.state, game::nav::NavState::BackingOff) << tick;
    ASSERT_DOUBLE_EQ(out.command.vr, -0.3);
  }
  out = nav.step(plane, in, 0.01);
  EXPECT_TRUE(out.events.replanned);
  EXPECT_EQ(out.state, game::nav::NavState::Following);
  EXPECT_TRUE(nav.grid().temporary(3, 2));  // (1.75, 1.25): 0.5 m ahead of where it stuck
}

TEST(NavNavigator, TurningInPlaceIsNotBeingStuck) {
  engine::PlaneWorld plane;
  game::nav::NavigatorParams params;
  params.grid = coarseRoom();
  game::nav::Navigator nav(plane, params);
  nav.setTarget(V2(8.75, 1.25));
  game::nav::NavInput in;
  in.position = V2(1.25, 1.25);
  in.yaw = M_PI;  // facing away: the follower turns in place (and this robot never manages to)
  for (int tick = 0; tick < 1000; ++tick) {
    const game::nav::NavOutput out = nav.step(plane, in, 0.01);
    ASSERT_FALSE(out.events.stuck) << tick;
    ASSERT_DOUBLE_EQ(out.command.vr, 0.0);
    ASSERT_DOUBLE_EQ(std::abs(out.command.wr), 1.0);
  }
}

// the robot as a unicycle that does what it is told, at once
void integrate(game::nav::NavInput* in, const game::nav::NavCommand& c, double dt) {
  in->position += c.vr * dt * V2(std::cos(in->yaw), std::sin(in->yaw));
  in->yaw += c.wr * dt;
  in->speed = c.vr;
}

TEST(NavNavigator, AUnicycleFollowingItsCommandsReachesTheTargetAroundAWall) {
  engine::PlaneWorld plane;
  addRect(plane, 4.5, 0.0, 5.5, 4.0);
  game::nav::NavigatorParams params;
  params.grid.size = V2(10, 6);  // 0.1 m cells, radius 0.35 m
  game::nav::Navigator nav(plane, params);
  nav.setTarget(V2(8.75, 1.25));
  game::nav::NavInput in;
  in.position = V2(1.25, 1.25);
  int reachedAt = -1, replans = 0;
  for (int tick = 0; tick < 6000 && reachedAt < 0; ++tick) {
    const game::nav::NavOutput out = nav.step(plane, in, 0.01);
    ASSERT_FALSE(out.events.stuck) << tick;
    ASSERT_EQ(out.command.skill, NavSkill::Walk);  // no straight is 5 m long
    ASSERT_LE(out.command.vr, game::nav::interlockLimit(params.follower.walk, out.command.wr) + 1e-12);
    replans += out.events.replanned;
    if (out.events.reached) reachedAt = tick;
    integrate(&in, out.command, 0.01);
    // the pelvis keeps clear of the wall: pure pursuit cuts the path's corners a little, by less than 0.15 m
    const double dx = std::max({4.5 - in.position.x(), 0.0, in.position.x() - 5.5});
    const double dy = std::max(0.0, in.position.y() - 4.0);
    ASSERT_GT(std::hypot(dx, dy), 0.36 - 0.15) << in.position.transpose();
  }
  EXPECT_GT(reachedAt, 0);
  EXPECT_EQ(replans, 1);  // the first plan only
  EXPECT_LT((in.position - V2(8.75, 1.25)).norm(), 0.3);
  EXPECT_EQ(nav.state(), game::nav::NavState::Idle);
}

TEST(NavNavigator, TheSameInputsGiveTheSameCommands) {
  engine::PlaneWorld plane;
  addRect(plane, 4.5, 0.0, 5.5, 4.0);
  game::nav::NavigatorParams params;
  params.grid.size = V2(10, 6);
  game::nav::Navigator a(plane, params), b(plane, params);
  a.setTarget(V2(8.75, 1.25));
  b.setTarget(V2(8.75, 1.25));
  game::nav::NavInput ia, ib;
  ia.position = ib.position = V2(1.25, 1.25);
  for (int tick = 0; tick < 1500; ++tick) {
    const game::nav::NavOutput oa = a.step(plane, ia, 0.01), ob = b.step(plane, ib, 0.01);
    ASSERT_EQ(oa.command.vr, ob.command.vr) << tick;
    ASSERT_EQ(oa.command.wr, ob.command.wr) << tick;
    ASSERT_EQ(oa.command.skill, ob.command.skill) << tick;
    integrate(&ia, oa.command, 0.01);
    integrate(&ib, ob.command, 0.01);
  }
}

TEST(NavNavigator, RunsOnALongStraightAndWalksForTheLastStretch) {
  engine::PlaneWorld plane;
  game::nav::NavigatorParams params;
  params.grid.size = V2(20, 4);
  game::nav::Navigator nav(plane, params);
  nav.setTarget(V2(18.0, 2.0));
  game::nav::NavInput in;
  in.position = V2(1.0, 2.0);
  bool ran = false;
  double walkAgainAt = -1;
  for (int tick = 0; tick < 4000; ++tick) {
    const game::nav::NavOutput out = nav.step(plane, in, 0.01);
    if (out.events.reached) break;
    if (out.command.skill == NavSkill::Run) ran = true;
    if (ran && walkAgainAt < 0 && out.command.skill == NavSkill::Walk) walkAgainAt = in.position.x();
    integrate(&in, out.command, 0.01);
  }
  EXPECT_TRUE(ran);
  // the run ends when less than 2.5 m of straight is left: at x = 15.5 (within a tick's travel)
  EXPECT_NEAR(walkAgainAt, 18.0 - 2.5, 0.05);
}

}  // namespace
