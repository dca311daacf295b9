// garden_pilot_test.cpp — the garden pilot's key scheme (stop, turn in place, go with W, back), its target list
// format, the random targets, and what a map level puts into its 2D layer (stairs tags, balls as moving circles).
#include "game/garden_pilot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "engine/core/error.h"
#include "engine/plane/plane_tags.h"
#include "engine/plane/plane_world.h"
#include "game/nav/occupancy_grid.h"
#include "game/session.h"
#include "levels/level.h"
#include "robot/robot_model.h"

namespace {

using game::GardenKeys;
using game::LegCues;

game::SkillKeys keys() {
  game::SkillKeys k;
  k.walk = '0', k.run = '1', k.stairs = '2';
  return k;
}

std::string text(const std::vector<engine::KeyEvent>& events) {
  std::string s;
  for (const engine::KeyEvent& e : events)
    s += std::string(e.action == engine::KeyAction::kDown ? "+"
                     : e.action == engine::KeyAction::kUp ? "-"
                                                          : "*") +
         e.key;
  return s;
}

// the robot at rest, a leg 5 m away at `heading`
LegCues restingLeg(double yaw, double heading) {
  LegCues c;
  c.yaw = c.yawMean = yaw;
  c.haveLeg = true;
  c.legHeading = heading;
  c.legRemaining = 5.0;
  return c;
}

// runs the scheme until it leaves Stop; returns the events of the tick it did
std::string untilTurn(GardenKeys* g, const LegCues& c, int64_t* tick) {
  for (; *tick < 1000; ++*tick) {
    const std::string e = text(g->decide(*tick, c));
    if (g->mode() != GardenKeys::Mode::Stop) return e;
  }
  return "";
}

TEST(GardenKeys, TheWalkKeyComesFirstThenTheRobotSettlesBeforeItTurns) {
  GardenKeys g(keys());
  LegCues c = restingLeg(0.0, 1.0);
  EXPECT_EQ(text(g.decide(0, c)), "*0");  // the standing controller does not turn: the walk first
  EXPECT_EQ(g.mode(), GardenKeys::Mode::Stop);
  int64_t tick = 1;
  untilTurn(&g, c, &tick);
  // settled after settleTicks (30) at rest: seen at rest from tick 0, Turn entered at tick 30
  EXPECT_EQ(tick, 30);
  EXPECT_EQ(g.mode(), GardenKeys::Mode::Turn);
}

TEST(GardenKeys, ALegToTheLeftHoldsAAndLetsGoBeforeTheHeadingSoTheRampEndsTheTurnOnIt) {
  GardenKeys g(keys());
  LegCues c = restingLeg(0.0, 1.0);
  int64_t tick = 0;
  untilTurn(&g, c, &tick);
  ++tick;
  EXPECT_EQ(text(g.decide(tick, c)), "+A");  // 1 rad to the left: turn left
  // turning at 1 rad/s: let go within 1^2 / (2 x 3) + 1 x 0.12 = 0.287 rad (+ half the 0.08 tolerance: 0.327)
  c.commandWz = 1.0;
  c.yaw = 1.0 - 0.34;
  EXPECT_EQ(text(g.decide(++tick, c)), "");
  c.yaw = 1.0 - 0.32;
  EXPECT_EQ(text(g.decide(++tick, c)), "-A");
  EXPECT_NEAR(game::turnRelease(1.0, game::GardenKeyParams{}), 1.0 / 6.0 + 0.12, 1e-12);
}

TEST(GardenKeys, ALegToTheRightHoldsD) {
  GardenKeys g(keys());
  LegCues c = restingLeg(0.5, -0.5);
  int64_t tick = 0;
  untilTurn(&g, c, &tick);
  EXPECT_EQ(text(g.decide(++tick, c)), "+D");
}

TEST(GardenKeys, FacingTheLegWithinTheToleranceGoesWithTheWalkAndW) {
  GardenKeys g(keys());
  LegCues c = restingLeg(0.0, 0.07);  // 0.07 rad off: within the walk's 0.08
  int64_t tick = 0;
  untilTurn(&g, c, &tick);
  std::string e;
  for (int i = 0; i < 40 && g.mode() == GardenKeys::Mode::Turn; ++i) e += text(g.decide(++tick, c));
  EXPECT_EQ(g.mode(), GardenKeys::Mode::Go);
  EXPECT_EQ(e, "+W");  // the walk key was pressed at the start already
}

TEST(GardenKeys, AStairsLegNeedsTheTighterToleranceAndGoesWithKeyTwo) {
  GardenKeys g(keys());
  LegCues c = restingLeg(0.0, 0.065);  // within the walk's 0.08 but not the stairs' 0.05
  c.stairsLeg = true;
  int64_t tick = 0;
  untilTurn(&g, c, &tick);
  EXPECT_EQ(text(g.decide(++tick, c)), "+A");
  c.yaw = c.yawMean = 0.045;  // the pulse turned it 0.045 rad: 0.02 off, within half the 0.05 tolerance
  EXPECT_EQ(text(g.decide(++tick, c)), "-A");
  std::string e;
  for (int i = 0; i < 40 && g.mode() == GardenKeys::Mode::Turn; ++i) e += text(g.decide(++tick, c));
  EXPECT_EQ(e, "*2+W");
  EXPECT_EQ(g.skillKey(), '2');
}

TEST(GardenKeys, WIsLetGoWithinTheBrakingDistanceOfTheLegsEnd) {
  // at 1.2 m/s: 1.2^2 / (2 x 2) + 1.2 x 0.15 = 0.54 m
  EXPECT_NEAR(game::brakeDistance(1.2, game::GardenKeyParams{}), 0.54, 1e-12);
  GardenKeys g(keys());
  LegCues c = restingLeg(0.0, 0.0);
  int64_t tick = 0;
  untilTurn(&g, c, &tick);
  while (g.mode() != GardenKeys::Mode::Go && tick < 200) g.decide(++tick, c);
  ASSERT_EQ(g.mode(), GardenKeys::Mode::Go);
  c.commandVx = 1.2, c.speed = 1.2;
  c.legRemaining = 0.55;
  EXPECT_EQ(text(g.decide(++tick, c)), "");
  c.legRemaining = 0.53;
  EXPECT_EQ(text(g.decide(++tick, c)), "-W");
  EXPECT_EQ(g.mode(), GardenKeys::Mode::Stop);
}

// Go on a walk leg at speed, 10 m to go along +X: with the run allowed, or (`steer`) with steering under W (the walk's
// forward_turn) and at the walk's 0.8 m/s
GardenKeys going(LegCues* c, int64_t* tick, bool steer = false) {
  game::GardenKeyParams p;
  p.useRun = !steer;
  p.steer = steer;
  GardenKeys g(keys(), p);
  *c = restingLeg(0.0, 0.0);
  c->legRemaining = 10.0, c->endStops = !steer;
  untilTurn(&g, *c, tick);
  while (g.mode() != GardenKeys::Mode::Go && *tick < 200) g.decide(++*tick, *c);
  c->commandVx = 1.2, c->speed = steer ? 0.8 : 1.2;
  return g;
}

TEST(GardenKeys, WalkingStopsToTurnAgainWhenTheHeadingHoldDriftedOffTheLegsEnd) {
  LegCues c;
  int64_t tick = 0;
  GardenKeys g = going(&c, &tick);
  c.legHeading = 0.09;  // the bearing to the leg's end turned 0.09 rad from the leg's start: walk on
  EXPECT_EQ(text(g.decide(++tick, c)), "");
  c.legHeading = 0.11;
  EXPECT_EQ(text(g.decide(++tick, c)), "-W");
  // ... but not close to the leg's end (1 m), where a small offset is a large angle
  g = going(&c, &tick);
  c.legHeading = 0.5, c.legRemaining = 0.95;
  EXPECT_EQ(text(g.decide(++tick, c)), "");
}

TEST(GardenKeys, WithSteeringAWalkThatDriftsOffItsWayHoldsATurnKeyUnderW) {
  LegCues c;
  int64_t tick = 0;
  GardenKeys g = going(&c, &tick, true);
  ASSERT_EQ(g.mode(), GardenKeys::Mode::Go);
  c.legHeading = 0.04;  // within steerOn (0.05 rad): W alone
  EXPECT_EQ(text(g.decide(++tick, c)), "");
  c.legHeading = 0.2;  // the path ahead 0.2 rad to the left: A joins W
  EXPECT_EQ(text(g.decide(++tick, c)), "+A");
  c.commandWz = 0.5;  // let go once the ramp down (0.5^2 / 6 + 0.5 x 0.25 = 0.167 rad) would end the turn on it
  c.yaw = 0.02;
  EXPECT_EQ(text(g.decide(++tick, c)), "");
  c.yaw = 0.04;  // 0.16 rad to go
  EXPECT_EQ(text(g.decide(++tick, c)), "-A");
  EXPECT_EQ(g.mode(), GardenKeys::Mode::Go);  // W still held: no stop
  c.commandWz = 0.0, c.yaw = 0.0, c.legHeading = -0.1;
  EXPECT_EQ(text(g.decide(++tick, c)), "+D");
  // a corner sharper than steerCorner (0.35 rad): stop, to turn in place from rest
  c.legHeading = -0.5;
  EXPECT_EQ(text(g.decide(++tick, c)), "-D-W");
  EXPECT_EQ(g.mode(), GardenKeys::Mode::Stop);
}

TEST(GardenKeys, WithSteeringAWallAheadOfOneSideIsSteeredAwayFromAndTheLastStretchToAStopIsWalkedSlowly) {
  LegCues c;
  int64_t tick = 0;
  GardenKeys g = going(&c, &tick, true);
  c.rightAhead = 0.6;  // a house's corner 0.6 m ahead of the right side, the left clear: steer left
  EXPECT_EQ(text(g.decide(++tick, c)), "+A");
  c.rightAhead = c.leftAhead = 1e9;
  c.centreAhead = 0.4;  // a wall right ahead of the pelvis: the leg went wrong, stop
  EXPECT_EQ(text(g.decide(++tick, c)), "-A-W");
  EXPECT_EQ(g.mode(), GardenKeys::Mode::Stop);

  g = going(&c, &tick, true);
  c.endStops = true, c.legRemaining = 1.4;  // within approachDistance (1.5 m) of the path's end: W only below 0.4
  EXPECT_EQ(text(g.decide(++tick, c)), "-W");
  c.commandVx = 0.38;
  EXPECT_EQ(text(g.decide(++tick, c)), "+W");
  c.legRemaining = 0.08;  // within the braking distance at 0.38 m/s (0.38^2 / 4 + 0.38 x 0.15 = 0.093 m): stop
  EXPECT_EQ(text(g.decide(++tick, c)), "-W");
  EXPECT_EQ(g.mode(), GardenKeys::Mode::Stop);
}

TEST(GardenKeys, WithStairsSteeringAStairsLegIsSteeredUnderWAndLeftForTheWalkOncePassed) {
  game::GardenKeyParams p;
  p.steerStairs = true;
  GardenKeys g(keys(), p);
  LegCues c = restingLeg(0.0, 0.0);
  c.stairsLeg = true;
  int64_t tick = 0;
  untilTurn(&g, c, &tick);
  std::string go;
  while (g.mode() != GardenKeys::Mode::Go && tick < 200) go = text(g.decide(++tick, c));
  EXPECT_EQ(go, "*2+W");
  c.commandVx = 0.5, c.speed = 0.5;
  c.legHeading = -0.1;  // the staircase's middle line ahead lies to the right: D under W
  EXPECT_EQ(text(g.decide(++tick, c)), "+D");
  c.commandWz = -0.2, c.yaw = -0.06;  // within the ramp-down's 0.2^2 / 6 + 0.2 x 0.25 = 0.057 rad: let go
  EXPECT_EQ(text(g.decide(++tick, c)), "-D");
  c.stairsLeg = false;  // the staircase passed: W up, the walk's key, and a stop
  EXPECT_EQ(text(g.decide(++tick, c)), "-W*0");
  EXPECT_EQ(g.mode(), GardenKeys::Mode::Stop);
}

TEST(GardenKeys, ARunOnALongLegAndTheWalkAgainBeforeItsEnd) {
  LegCues c;
  int64_t tick = 0;
  GardenKeys g = going(&c, &tick);
  c.runAllowed = true;
  c.legRemaining = 5.9;  // under runMinLeg (6 m): walk on
  EXPECT_EQ(text(g.decide(++tick, c)), "");
  c.legRemaining = 8.0, c.speed = 0.8;  // not yet at the walk's speed (0.9 m/s)
  EXPECT_EQ(text(g.decide(++tick, c)), "");
  c.speed = 1.0;
  EXPECT_EQ(text(g.decide(++tick, c)), "*1");
  c.legRemaining = 3.6;
  EXPECT_EQ(text(g.decide(++tick, c)), "");
  c.legRemaining = 3.4;  // under runLeaveLeg (3.5 m)
  EXPECT_EQ(text(g.decide(++tick, c)), "*0");
  EXPECT_EQ(g.mode(), GardenKeys::Mode::Go);
}

TEST(GardenKeys, WithSteeringARunHandsBackToTheWalkWithWHeldUntilTheWalkHasSettled) {
  game::GardenKeyParams p;
  p.steer = true, p.useRun = true;
  GardenKeys g(keys(), p);
  LegCues c = restingLeg(0.0, 0.0);
  c.legRemaining = 10.0, c.endStops = false;
  int64_t tick = 0;
  untilTurn(&g, c, &tick);
  while (g.mode() != GardenKeys::Mode::Go && tick < 200) g.decide(++tick, c);
  ASSERT_EQ(g.mode(), GardenKeys::Mode::Go);
  c.commandVx = 1.2, c.speed = 1.0, c.runAllowed = true;
  c.yaw = -0.12;  // the path 0.12 rad off the heading (over runHeading, 0.1): steered first, no run
  EXPECT_EQ(text(g.decide(++tick, c)), "+A");
  c.yaw = 0.0;  // squared up: A let go, then the run
  EXPECT_EQ(text(g.decide(++tick, c)), "-A");
  EXPECT_EQ(text(g.decide(++tick, c)), "*1");
  c.running = true, c.speed = 1.9;
  c.legRemaining = 3.4;  // under runLeaveLeg: the walk asked for, W kept down
  EXPECT_EQ(text(g.decide(++tick, c)), "*0");
  c.yaw = 0.6;  // a corner beyond steerCorner while the run is still in control: no stop, W held, no steering
  EXPECT_EQ(text(g.decide(++tick, c)), "");
  c.running = false, c.speed = 1.5;  // the walk has taken over, still fast
  EXPECT_EQ(text(g.decide(++tick, c)), "");
  c.speed = 1.0;
  for (int i = 1; i < p.walkSettleTicks; ++i) ASSERT_EQ(text(g.decide(++tick, c)), "") << i;
  EXPECT_EQ(g.mode(), GardenKeys::Mode::Go);
  EXPECT_EQ(text(g.decide(++tick, c)), "-W");  // settled: the corner is turned from rest
  EXPECT_EQ(g.mode(), GardenKeys::Mode::Stop);
}

TEST(GardenKeys, AReplanABallOrAWallAheadStopsAWalkButNotAStairsLeg) {
  LegCues c;
  int64_t tick = 0;
  GardenKeys g = going(&c, &tick);
  c.pathChanged = true;
  EXPECT_EQ(text(g.decide(++tick, c)), "-W");
  g = going(&c, &tick);
  c.movableAhead = true;
  EXPECT_EQ(text(g.decide(++tick, c)), "-W");
  g = going(&c, &tick);
  c.obstacleFactor = 0.09;  // a wall 0.45 m ahead
  EXPECT_EQ(text(g.decide(++tick, c)), "-W");

  GardenKeys s(keys());
  LegCues st = restingLeg(0.0, 0.0);
  st.stairsLeg = true;
  untilTurn(&s, st, &tick);
  while (s.mode() != GardenKeys::Mode::Go && tick < 400) s.decide(++tick, st);
  ASSERT_EQ(s.skillKey(), '2');
  st.commandVx = 0.5, st.speed = 0.5, st.pathChanged = true, st.legHeading = 0.5;
  EXPECT_EQ(text(s.decide(++tick, st)), "");  // on the stairs: walked to their end
  st.legRemaining = 0.1;
  EXPECT_EQ(text(s.decide(++tick, st)), "-W*0");  // the end: W up, the walk again
}

TEST(GardenKeys, TheNavigationsBackOffHoldsSAndStopsAfter) {
  LegCues c;
  int64_t tick = 0;
  GardenKeys g = going(&c, &tick);
  c.backOff = true;
  EXPECT_EQ(text(g.decide(++tick, c)), "-W+S");  // S drives the same axis: vx ramps down through 0 to backward
  EXPECT_EQ(g.mode(), GardenKeys::Mode::Back);
  EXPECT_EQ(text(g.decide(++tick, c)), "");
  c.backOff = false;
  EXPECT_EQ(text(g.decide(++tick, c)), "-S");
  EXPECT_EQ(g.mode(), GardenKeys::Mode::Stop);
}

TEST(GardenTargets, AListIsXAndYPerLineWithCommentsAndCommas) {
  const auto t = game::parseTargets("# garden targets\n\n1.5 2\n  -3, 4.25  # the bridge\n", "t.txt");
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0], Eigen::Vector2d(1.5, 2.0));
  EXPECT_EQ(t[1], Eigen::Vector2d(-3.0, 4.25));
}

std::string targetError(const std::string& text) {
  try {
    game::parseTargets(text, "t.txt");
  } catch (const engine::Error& e) {
    return e.what();
  }
  return "";
}

TEST(GardenTargets, BadLinesAreNamedWithTheirFileAndLine) {
  EXPECT_NE(targetError("1 2\n3\n").find("t.txt:2: a target is two numbers"), std::string::npos);
  EXPECT_NE(targetError("1 2\n\n3 x\n").find("t.txt:3: 'x' is not a coordinate"), std::string::npos);
  EXPECT_NE(targetError("1 2 3\n").find("t.txt:1:"), std::string::npos);
  EXPECT_NE(targetError("# none\n").find("t.txt:1: no targets"), std::string::npos);
  EXPECT_NE(targetError("1e9 0\n").find("t.txt:1:"), std::string::npos);
}

// a map: a 10 m x 6 m walled yard with a staircase along +X across its middle band
const char* kYard = R"(name = "yard"
plane = "top"
[spawn]
position = [1.0, 1.0]
[[box]]
centre = [5.0, -0.1, 0.5]
size = [10.0, 0.2, 1.0]
[[box]]
centre = [5.0, 6.1, 0.5]
size = [10.0, 0.2, 1.0]
[[stairs]]
start = [4.0, 3.0]
steps = 2
rise = 0.1
run = 0.6
width = 1.0
down = true
[[coin]]
centre = [8.0, 1.0, 0.6]
[[ball]]
position = [2.0, 5.0]
)";

TEST(GardenLevel, AMapsStaircaseStepsCarryTheStairsTagAndItsBallIsAMovingCircle) {
  const levels::Level level = levels::parseLevel(kYard, "yard.toml");
  EXPECT_EQ(level.coins.size(), 1u);  // a map without rules may hold coins and balls
  const robot::RobotModel model = robot::loadRobotModel(robot::defaultRobotConfigPath());
  game::Session session(level, model, game::SessionOptions{});
  const engine::PlaneWorld& plane = session.plane();
  // the middle of the first step (x 4.0..4.6, y 2.5..3.5)
  const std::vector<int> step = plane.queryCircle({4.3, 3.0}, 0.01);
  ASSERT_EQ(step.size(), 1u);
  EXPECT_EQ(step[0], engine::stairTag(0.0));
  const std::vector<int> wall = plane.queryCircle({5.0, -0.1}, 0.01);
  ASSERT_EQ(wall.size(), 1u);
  EXPECT_TRUE(engine::isWallTag(wall[0]));
  const std::vector<int> ball = plane.queryCircle({2.0, 5.0}, 0.01);
  ASSERT_EQ(ball.size(), 1u);
  EXPECT_EQ(ball[0], engine::kMovableTagBase);
  // the layer's static bounds: the walls' outer faces (x 0..10, y -0.2..6.2)
  Eigen::Vector2d lo, hi;
  ASSERT_TRUE(plane.staticBounds(&lo, &hi));
  EXPECT_NEAR(lo.x(), 0.0, 0.02);
  EXPECT_NEAR(lo.y(), -0.2, 0.02);
  EXPECT_NEAR(hi.x(), 10.0, 0.02);
  EXPECT_NEAR(hi.y(), 6.2, 0.02);
}

TEST(GardenLevel, ASideLevelsStepsKeepTheirBoxIndexAsTag) {
  const std::string side = std::string(kYard).replace(std::string(kYard).find("\"top\""), 5, "\"side\"");
  const std::string noEntities = side.substr(0, side.find("[[coin]]"));
  const levels::Level level = levels::parseLevel(noEntities, "yard.toml");
  const robot::RobotModel model = robot::loadRobotModel(robot::defaultRobotConfigPath());
  game::Session session(level, model, game::SessionOptions{});
  // the side plane is world (x, z): the two walls (boxes 0 and 1, 1 m high along all of x) and the first step (the
  // third box, index 2, 0.1 m high) are all there at x = 4.3, z = 0.05, each by its index
  const std::vector<int> step = session.plane().queryCircle({4.3, 0.05}, 0.01);
  EXPECT_EQ(step, (std::vector<int>{0, 1, 2}));
}

TEST(GardenTargets, RandomTargetsAreFreeReachableAndTheSameForTheSameSeed) {
  const levels::Level level = levels::parseLevel(kYard, "yard.toml");
  const robot::RobotModel model = robot::loadRobotModel(robot::defaultRobotConfigPath());
  game::Session session(level, model, game::SessionOptions{});
  game::GardenPilot a(session.plane(), keys(), 7, {}), b(session.plane(), keys(), 7, {});
  std::mt19937_64 r1(3), r2(3);
  game::TargetDraw draw;
  draw.minPath = 3.0;
  const Eigen::Vector2d from(1.0, 1.0);
  const Eigen::Vector2d t1 = game::GardenPilot::drawTarget(a.navigator().grid(), from, true, draw, &r1);
  const Eigen::Vector2d t2 = game::GardenPilot::drawTarget(b.navigator().grid(), from, true, draw, &r2);
  EXPECT_EQ(t1, t2);
  const game::nav::OccupancyGrid& grid = a.navigator().grid();
  const Eigen::Vector2i cell = grid.cellAt(t1);
  EXPECT_EQ(grid.kind(cell.x(), cell.y()), game::nav::CellKind::Free);
  // "across": the path crosses the staircase band (y 2.5..3.5 spans the yard's middle only from x 4.0 to 6.4,
  // so a target beyond it is reached either across the steps or around them; the draw asks for the steps)
  const game::nav::Path path = game::nav::planPath(grid, from, t1);
  EXPECT_TRUE(path.found);
  EXPECT_GE(path.length(), 3.0);
  EXPECT_FALSE(path.stairs.empty());
}

}  // namespace
