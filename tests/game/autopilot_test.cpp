// autopilot_test.cpp — the autopilot's decisions from hand-made cues: which skill key it presses when, and
// that it holds W only while the skill should move forward.
#include "game/autopilot.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/fixtures.h"

namespace {

// the keys of the shipped tree's skills, found by name as play finds them
game::SkillKeys shippedKeys() {
  robot::SkillSet set;
  for (const robot::SkillDef& def : robot::loadSkillTree(robot::defaultSkillTreePath(), fixtures::robotModel()).skills)
    set.skills.push_back({def, {}});
  return game::skillKeys(set);
}

std::string keys(const std::vector<engine::KeyEvent>& ev) {
  std::string s;
  for (const engine::KeyEvent& e : ev)
    s += std::string(e.action == engine::KeyAction::kTap    ? "tap "
                     : e.action == engine::KeyAction::kDown ? "down "
                                                            : "up ") +
         e.key + ";";
  return s;
}

// Align mode, already at rest and facing +X: it settles, then steps left (Q) to `y` and lets go there
void settlesThenStepsLeftTo(game::Autopilot& a, game::Cues& c, double y) {
  c.speed = 0, c.commandVx = 0;
  EXPECT_EQ(keys(a.decide(2, c)), "");    // at rest ...
  EXPECT_EQ(keys(a.decide(50, c)), "");   // ... settled
  EXPECT_EQ(keys(a.decide(100, c)), "");  // facing +X already
  EXPECT_EQ(keys(a.decide(101, c)), "down Q;");
  c.y = y, c.commandVy = 0.1;
  EXPECT_EQ(keys(a.decide(130, c)), "up Q;");
  c.commandVy = 0;
}

// decides tick after tick (at rest) from tick *t until the mode is m (at most 2000 ticks); the keys pressed
std::string decideUntil(game::Autopilot& a, const game::Cues& c, int64_t* t, game::Autopilot::Mode m) {
  std::string pressed;
  for (const int64_t end = *t + 2000; a.mode() != m && *t < end; ++*t) pressed += keys(a.decide(*t, c));
  return pressed;
}

}  // namespace

TEST(Autopilot, FindsItsSkillsKeysInTheTreeByName) {
  const game::SkillKeys k = shippedKeys();
  EXPECT_EQ(k.walk, '0');
  EXPECT_EQ(k.run, '1');
  EXPECT_EQ(k.jump, '4');
  EXPECT_EQ(k.crawl, '9');
  robot::SkillSet withoutJump;  // a skill that is not loaded has no key: the autopilot does without it
  for (const robot::SkillDef& def : robot::loadSkillTree(robot::defaultSkillTreePath(), fixtures::robotModel()).skills)
    if (def.name != "jump") withoutJump.skills.push_back({def, {}});
  EXPECT_EQ(game::skillKeys(withoutJump).jump, '\0');
  EXPECT_EQ(game::skillKeys(withoutJump).walk, '0');
}

TEST(Autopilot, StartsWalkingForward) {
  game::Autopilot a(shippedKeys());
  EXPECT_EQ(keys(a.decide(0, {})), "tap 0;down W;");
  EXPECT_EQ(keys(a.decide(1, {})), "");
}

TEST(Autopilot, RunsFromAGhostAndSlowsBeforeTheStairs) {
  game::Autopilot a(shippedKeys());
  a.decide(0, {});
  game::Cues c;
  c.ghost = 3.0;
  EXPECT_EQ(keys(a.decide(1, c)), "tap 1;");  // W stays held
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Run);
  c.stepAhead = 2.5;  // stairs coming: back to walk first
  EXPECT_EQ(keys(a.decide(2, c)), "tap 0;");
  c.stepAhead = 1.9;  // stop, then the stairs from rest
  c.speed = 0.5, c.commandVx = 0.5;
  EXPECT_EQ(keys(a.decide(3, c)), "up W;");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Stairs);
  EXPECT_EQ(keys(a.decide(100, c)), "");  // still moving
  c.speed = 0.0, c.commandVx = 0.0;
  EXPECT_EQ(keys(a.decide(101, c)), "tap 2;down W;");
  // up a step, then on flat ground again for half a metre: walk
  c = {};
  c.x = 9.0, c.pelvisHeight = 0.9;
  EXPECT_EQ(keys(a.decide(102, c)), "");
  c.x = 10.0, c.pelvisHeight = 0.78;
  EXPECT_EQ(keys(a.decide(103, c)), "");
  c.x = 10.6;
  EXPECT_EQ(keys(a.decide(104, c)), "tap 0;");
}

TEST(Autopilot, StopsForTheStairsOnlyAtTheWalksSpeedsAndFacingThem) {
  game::Autopilot a(shippedKeys());
  a.decide(0, {});
  game::Cues c;
  c.stepAhead = 1.9, c.speed = 1.7, c.commandVx = 1.2;  // the walk just took over from the run: keys stay
  EXPECT_EQ(keys(a.decide(1, c)), "");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Walk);
  c.speed = 1.2;  // at the walk's own speed: stop
  EXPECT_EQ(keys(a.decide(2, c)), "up W;");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Stairs);
  c.speed = 0.0, c.commandVx = 0.0, c.yaw = 2.0;  // the stop spun it round: face +X before the stairs
  a.decide(100, c);
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Align);
  game::Autopilot b(shippedKeys());  // started square, then turned round before it climbed: stop and start again
  b.decide(0, {});
  c = {};
  c.stepAhead = 1.9;
  b.decide(1, c);
  EXPECT_EQ(keys(b.decide(100, c)), "tap 2;down W;");
  c.yaw = 1.3;
  EXPECT_EQ(keys(b.decide(101, c)), "tap 0;up W;");
  EXPECT_EQ(b.mode(), game::Autopilot::Mode::Stairs);
}

TEST(Autopilot, FlatGroundBeforeTheFirstStepDoesNotEndTheStairs) {
  game::Autopilot a(shippedKeys());
  a.decide(0, {});
  game::Cues c;
  c.stepAhead = 1.9;
  a.decide(1, c);
  EXPECT_EQ(keys(a.decide(100, c)), "tap 2;down W;");
  c.stepAhead = 1e9;  // (a ray between steps) the pelvis at standing height on flat ground, not yet up a step
  c.x = 0.0;
  a.decide(101, c);
  c.x = 1.0;
  EXPECT_EQ(keys(a.decide(102, c)), "");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Stairs);
}

TEST(Autopilot, LinesUpLiesDownCrawlsThroughATunnelAndStandsUpWellPastIt) {
  game::Autopilot a(shippedKeys());
  a.decide(0, {});
  game::Cues c;
  c.ceilingAhead = 1.5;
  c.speed = 0.5, c.commandVx = 0.5;
  EXPECT_EQ(keys(a.decide(1, c)), "up W;");  // stop: square to the course, 0.3 m left of its middle first
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Align);
  settlesThenStepsLeftTo(a, c, 0.3);
  EXPECT_EQ(keys(a.decide(200, c)), "tap 7;");  // lined up: lie down
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Prone);
  c.pelvisHeight = 0.3;  // lying, but not yet for the 3 s the crawl's card lies first
  EXPECT_EQ(keys(a.decide(400, c)), "");
  EXPECT_EQ(keys(a.decide(501, c)), "tap 9;down W;");
  c.ceilingAhead = 1e9;
  c.underCeiling = true;
  c.x = 20.0;
  EXPECT_EQ(keys(a.decide(502, c)), "");
  c.underCeiling = false;
  c.x = 21.0;  // not yet clear by 1.2 m (the stand-up kneels back ~0.8 m)
  EXPECT_EQ(keys(a.decide(503, c)), "");
  c.x = 21.3;
  EXPECT_EQ(keys(a.decide(504, c)), "tap 0;up W;");  // key 0 from crawl is routed through standup
  c.pelvisHeight = 0.75;
  EXPECT_EQ(keys(a.decide(700, c)), "down W;");
}

namespace {
// an autopilot walking under a box: it asks for the jump
game::Autopilot jumpingUnderABox(game::Cues* c) {
  game::Autopilot a(shippedKeys());
  a.decide(0, {});
  c->boxOverhead = true;
  EXPECT_EQ(keys(a.decide(1, *c)), "tap 4;up W;");
  return a;
}
}  // namespace

TEST(Autopilot, JumpsUnderABoxUntilItIsHitThenWalksOn) {
  game::Cues c;
  game::Autopilot a = jumpingUnderABox(&c);
  c.boxJustHit = true;
  EXPECT_EQ(keys(a.decide(50, c)), "tap 0;down W;");
  c.boxJustHit = false;
  EXPECT_EQ(keys(a.decide(51, c)), "");  // one jump per box
}

TEST(Autopilot, JumpsOnceUnderABoxThenWalksOnEvenWithoutAHit) {
  // the jump's later landings were where it fell: the walk is asked for once the pelvis has been up
  game::Cues c;
  game::Autopilot a = jumpingUnderABox(&c);
  c.pelvisHeight = 0.70;  // the crouch
  EXPECT_EQ(keys(a.decide(40, c)), "");
  c.pelvisHeight = 0.92;  // in the air, the box missed
  EXPECT_EQ(keys(a.decide(60, c)), "tap 0;down W;");
  c.pelvisHeight = 0.78;
  EXPECT_EQ(keys(a.decide(61, c)), "");  // still under the box: one jump per box
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Walk);
}

TEST(Autopilot, WalksUnderABoxWhenNoJumpIsLoaded) {
  game::Autopilot a(shippedKeys());
  a.decide(0, {});
  game::Cues c;
  c.boxOverhead = true;
  c.canJump = false;
  EXPECT_EQ(keys(a.decide(1, c)), "");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Walk);
}

TEST(Autopilot, LinesUpWithTheBallThenStepsUpToItAndKicks) {
  game::Autopilot a(shippedKeys());
  a.decide(0, {});
  game::Cues c;
  c.ballAhead = 0.75, c.ballY = -0.12;  // the kick wants the ball 0.12 m right of the pelvis: pelvis y 0
  c.y = -0.2, c.yaw = 0.3, c.speed = 0.5, c.commandVx = 0.5;
  EXPECT_EQ(keys(a.decide(1, c)), "up W;");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Align);
  c.speed = 0, c.commandVx = 0;
  EXPECT_EQ(keys(a.decide(2, c)), "");           // at rest ...
  EXPECT_EQ(keys(a.decide(50, c)), "");          // ... settled
  EXPECT_EQ(keys(a.decide(100, c)), "down D;");  // facing left of +X: turn right
  c.yaw = 0.01, c.commandWz = -0.1;
  EXPECT_EQ(keys(a.decide(110, c)), "up D;");
  c.commandWz = 0;
  EXPECT_EQ(keys(a.decide(200, c)), "");         // facing +X: on to the side step
  EXPECT_EQ(keys(a.decide(201, c)), "down Q;");  // 0.2 m right of where it should be: step left
  c.y = 0.0, c.commandVy = 0.1;
  EXPECT_EQ(keys(a.decide(230, c)), "up Q;");
  c.commandVy = 0;
  EXPECT_EQ(keys(a.decide(300, c)), "");  // lined up: the approach starts (nothing held)
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Approach);
  EXPECT_EQ(keys(a.decide(301, c)), "down W;");  // 0.45 m short of 0.30 m from the ball: a short step
  EXPECT_EQ(keys(a.decide(316, c)), "up W;");
  c.ballAhead = 0.32;
  EXPECT_EQ(keys(a.decide(400, c)), "tap 5;");  // close enough: the one-leg stand
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Balance);
  c.skill = "walk";  // the switch waits until the robot has stopped (up to 3 s)
  EXPECT_EQ(keys(a.decide(600, c)), "");
  c.skill = "one_leg";  // it took over at 6.5 s
  EXPECT_EQ(keys(a.decide(650, c)), "");
  EXPECT_EQ(keys(a.decide(1049, c)), "");  // on one leg for 4 s first
  EXPECT_EQ(keys(a.decide(1050, c)), "tap 6;");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Kick);
}

TEST(Autopilot, KicksAfterSevenSecondsIfTheOneLegStandNeverTookOver) {
  game::Autopilot a(shippedKeys());
  a.decide(0, {});
  game::Cues c;
  c.ballAhead = 0.32, c.ballY = -0.12, c.skill = "walk";  // at the spot, facing +X
  int64_t t = 1;
  decideUntil(a, c, &t, game::Autopilot::Mode::Balance);
  ASSERT_EQ(a.mode(), game::Autopilot::Mode::Balance);
  const int64_t start = t;
  for (; a.mode() == game::Autopilot::Mode::Balance && t < start + 1000; ++t) a.decide(t, c);
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Kick);
  EXPECT_EQ(t - start,
            701);  // the kick at the first tick more than 700 ticks (7 s) after the key (t stops one past it)
}

TEST(Autopilot, KicksOnlyFromTheCardsSpot) {
  // at the ball after the approach, but 0.1 m left of the line-up (the card's spot: 0.12 m right of the pelvis,
  // within 6 cm): no one-leg stand but a new line-up; and a ball nudged during the stand: no kick, the walk again
  game::Autopilot a(shippedKeys());
  a.decide(0, {});
  game::Cues c;
  c.ballAhead = 0.75, c.ballY = -0.12;  // pelvis at y 0 already: lined up
  int64_t t = 1;
  auto until = [&](game::Autopilot::Mode m) { return decideUntil(a, c, &t, m); };
  a.decide(t++, c);
  EXPECT_EQ(until(game::Autopilot::Mode::Approach), "");  // nothing to turn or step
  c.ballAhead = 0.32,
  c.y = 0.1;  // there, but 0.1 m left of the line-up (a side step that overshot, a ball that rolled)
  EXPECT_EQ(keys(a.decide(t++, c)), "");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Align);
  c.y = 0.0;  // back on the line
  until(game::Autopilot::Mode::Approach);
  EXPECT_EQ(keys(a.decide(t++, c)), "tap 5;");
  ASSERT_EQ(a.mode(), game::Autopilot::Mode::Balance);
  c.ballAhead = 0.42;  // nudged 0.1 m on during the stand
  EXPECT_EQ(until(game::Autopilot::Mode::Walk), "tap 0;");
}

TEST(Autopilot, AfterTheStandItKicksTurnedUpTo0p25RadWithTheBallWhereTheCardPutsItInItsFrame) {
  // the one-leg stand turned the robot 0.2 rad left: the ball, 0.30 m ahead and 0.12 m right of the pelvis in its
  // heading frame, is at (0.30 cos 0.2 + 0.12 sin 0.2, 0.30 sin 0.2 - 0.12 cos 0.2) = (0.318, -0.058) in the world's
  game::Autopilot a(shippedKeys());
  a.decide(0, {});
  game::Cues c;
  c.ballAhead = 0.32, c.ballY = -0.12;  // at the spot, facing +X
  int64_t t = 1;
  decideUntil(a, c, &t, game::Autopilot::Mode::Balance);
  ASSERT_EQ(a.mode(), game::Autopilot::Mode::Balance);
  const auto turnedBy = [&](double yaw) {
    c.yaw = yaw, c.y = 0.0;
    c.ballAhead = 0.30 * std::cos(yaw) + 0.12 * std::sin(yaw);
    c.ballY = 0.30 * std::sin(yaw) - 0.12 * std::cos(yaw);
  };
  turnedBy(0.2);
  game::Autopilot b = a;  // the same stand, turned further: 0.3 rad
  const int64_t start = t;
  for (; a.mode() == game::Autopilot::Mode::Balance && t < start + 1000; ++t) a.decide(t, c);
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Kick);
  turnedBy(0.3);
  for (t = start; b.mode() == game::Autopilot::Mode::Balance && t < start + 1000; ++t) b.decide(t, c);
  EXPECT_EQ(b.mode(), game::Autopilot::Mode::Walk);  // lines up again
}

TEST(Autopilot, ABallLeftBesideItIsReachedAgainFromBehind) {
  // a kick that stays up and sends the ball sideways: the ball lies beside the pelvis, 0.3 m to the right
  game::Autopilot a(shippedKeys());
  a.decide(0, {});
  game::Cues c;
  c.ballAhead = 0.0, c.ballY = -0.3;
  EXPECT_EQ(keys(a.decide(1, c)), "up W;");  // stop, and step clear of it (0.45 m: to y = +0.15) ...
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Align);
  settlesThenStepsLeftTo(a, c, 0.15);
  EXPECT_EQ(keys(a.decide(200, c)), "down S;");  // ... then back up
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::BackUp);
  c.ballAhead = 0.5;
  EXPECT_EQ(keys(a.decide(300, c)), "");
  c.ballAhead = 0.75;  // ahead again: line up with it as before a first kick
  EXPECT_EQ(keys(a.decide(301, c)), "up S;");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Align);
}

TEST(Autopilot, ALineUpThatWalkedPastTheBallBacksOffInsteadOfStepping) {
  // the side steps of a line-up drift forward: lined up, the ball is 0.4 m behind the pelvis. Short steps back
  // (the approach's) cannot get behind it; it steps clear and backs up as for a ball left beside it
  game::Autopilot a(shippedKeys());
  a.decide(0, {});
  game::Cues c;
  c.ballAhead = 0.75, c.ballY = -0.12;  // pelvis at y 0 already: lined up
  int64_t t = 1;
  decideUntil(a, c, &t, game::Autopilot::Mode::Approach);
  ASSERT_EQ(a.mode(), game::Autopilot::Mode::Approach);
  c.ballAhead = -0.4;
  EXPECT_EQ(keys(a.decide(t++, c)), "");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Align);  // to y = +0.33 (0.45 m left of the ball), then S
  settlesThenStepsLeftTo(a, c, 0.33);
  EXPECT_EQ(keys(a.decide(200, c)), "down S;");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::BackUp);
}

TEST(Autopilot, ABallAgainstTheLeftWallIsPushedOnWithTheLeftFootInsteadOfKicked) {
  // the ball rests against the left wall (its inner face at y = 1.0, the ball's radius 0.11 m): the kick's spot, the
  // pelvis 0.12 m left of the ball, is beyond the kick's line (at most 0.65 m left of the middle); it lines up with
  // the ball in front of the left foot instead, facing 0.1 rad toward the wall, and walks into it
  game::Autopilot a(shippedKeys());
  a.decide(0, {});
  game::Cues c;
  c.ballAhead = 0.75, c.ballY = 0.89;
  EXPECT_EQ(keys(a.decide(1, c)), "up W;");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Align);
  c.y = 0.75, c.yaw = 0.1;  // lined up (0.89 - 0.12 = 0.77, as near the wall as the line-up goes)
  int64_t t = 2;
  EXPECT_EQ(decideUntil(a, c, &t, game::Autopilot::Mode::Dribble), "down W;");
  c.ballAhead = -0.1;  // beside the left foot, still against the wall: walk on into it
  EXPECT_EQ(keys(a.decide(t++, c)), "");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Dribble);
  c.ballAhead = 0.4, c.ballY = 0.48;  // off the wall, but its kick line 0.60 m out: within 0.1 m of the limit
  a.decide(t++, c);
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Dribble);
  c.ballY = 0.40;  // rolled well off the wall: the kick's line 0.52 m out
  a.decide(t++, c);
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Walk);

  game::Autopilot b(shippedKeys());  // 0.39 m nearer the middle: the kick's line-up, the pelvis at 0.62
  b.decide(0, {});
  c = {};
  c.ballAhead = 0.75, c.ballY = 0.50, c.y = 0.62;
  t = 1;
  decideUntil(b, c, &t, game::Autopilot::Mode::Approach);
  EXPECT_EQ(b.mode(), game::Autopilot::Mode::Approach);
}

TEST(Autopilot, ABallAgainstTheRightWallIsPushedOnWithTheRightFoot) {
  // the mirror of the left wall: the kick's spot (the pelvis 0.12 m left of the ball, at -0.77) is within 0.35 m of
  // the right wall; it lines up with the ball in front of the right foot, facing 0.1 rad toward the wall
  game::Autopilot a(shippedKeys());
  a.decide(0, {});
  game::Cues c;
  c.ballAhead = 0.75, c.ballY = -0.89;
  a.decide(1, c);
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Align);
  c.y = -0.75, c.yaw = -0.1;  // lined up (-0.89 + 0.12 = -0.77, as near the wall as the line-up goes)
  int64_t t = 2;
  EXPECT_EQ(decideUntil(a, c, &t, game::Autopilot::Mode::Dribble), "down W;");
}

TEST(Autopilot, AfterARespawnItReleasesEveryKeyAndWalksOn) {
  game::Autopilot a(shippedKeys());
  a.decide(0, {});
  game::Cues c;
  c.ghost = 3.0;
  EXPECT_EQ(keys(a.decide(1, c)), "tap 1;");  // running, W held
  c = {};
  c.respawns = 1;
  EXPECT_EQ(keys(a.decide(3, c)), "up W;tap 0;down W;");
  EXPECT_EQ(a.mode(), game::Autopilot::Mode::Walk);
}
