// command_test.cpp — CommandInput: ramps, the one-axis interlock at exact ticks, release, taps,
// skill requests and the amplitude clamp. Expected values are worked out by hand in the comments.
#include "engine/input/command.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace engine {
namespace {

void press(CommandInput& input, char key) { input.apply(KeyEvent{0, KeyAction::kDown, key}); }
void release(CommandInput& input, char key) { input.apply(KeyEvent{0, KeyAction::kUp, key}); }
void tap(CommandInput& input, char key) { input.apply(KeyEvent{0, KeyAction::kTap, key}); }
void run(CommandInput& input, int ticks) {
  for (int i = 0; i < ticks; ++i) input.tick();
}

TEST(CommandInput, StartsAtRest) {
  CommandInput input;
  EXPECT_EQ(input.state().skillRequest, -1);
  EXPECT_EQ(input.state().vx, 0.0);
  EXPECT_EQ(input.state().vy, 0.0);
  EXPECT_EQ(input.state().wz, 0.0);
  EXPECT_EQ(input.state().amplitude, 0.0);
  EXPECT_EQ(input.state().keysHeld, 0u);
}

TEST(CommandInput, HoldingWRampsVxBy0_02PerTickAndSaturatesAt1_2AfterSixtyTicks) {
  CommandInput input;
  press(input, 'W');
  input.tick();
  EXPECT_EQ(input.state().vx, 0.02);  // one step from 0 is exact
  run(input, 9);
  // 10 x 0.02 = 0.2; ten repeated additions of 0.02 land within an ulp of 0.2 (0.19999999999999998).
  EXPECT_DOUBLE_EQ(input.state().vx, 0.2);
  run(input, 49);  // 59 ticks: 1.18, still below the target
  EXPECT_LT(input.state().vx, 1.2);
  EXPECT_NEAR(input.state().vx, 1.18, 1e-12);
  input.tick();  // 60 ticks: 1.2 / 0.02 = 60, lands exactly on the target
  EXPECT_EQ(input.state().vx, 1.2);
  run(input, 40);
  EXPECT_EQ(input.state().vx, 1.2);
  EXPECT_EQ(input.state().vy, 0.0);
  EXPECT_EQ(input.state().wz, 0.0);
}

TEST(CommandInput, SwitchingFromWToARampsVxToZeroBeforeWzRises) {
  CommandInput input;
  press(input, 'W');
  run(input, 60);
  ASSERT_EQ(input.state().vx, 1.2);
  release(input, 'W');
  press(input, 'A');
  // vx falls 0.02 per tick: 1.2 / 0.02 = 60 ticks to 0. wz is blocked while vx != 0.
  run(input, 59);
  EXPECT_NEAR(input.state().vx, 0.02, 1e-12);
  EXPECT_EQ(input.state().wz, 0.0);
  // Tick 60: vx reaches exactly 0 first (vx updates before wz), so wz takes its first 0.03 step in the same tick.
  input.tick();
  EXPECT_EQ(input.state().vx, 0.0);
  EXPECT_EQ(input.state().wz, 0.03);
  // wz reaches 1.0 after ceil(1.0 / 0.03) = 34 steps: 33 steps give 0.99, the 34th snaps to 1.0.
  run(input, 32);
  EXPECT_NEAR(input.state().wz, 0.99, 1e-12);
  input.tick();
  EXPECT_EQ(input.state().wz, 1.0);
  EXPECT_EQ(input.state().vx, 0.0);
}

TEST(CommandRamp, AChangeOfAxisRampsTheOldAxisDownBeforeTheNewOneRises) {
  // what training and report cards do with a new draw: vx 1.2 -> wz -1.0 at the keys' rates
  double vx = 1.2, vy = 0.0, wz = 0.0;
  for (int i = 0; i < 59; ++i) rampVelocityCommand(0.0, 0.0, -1.0, 0.02, 0.03, &vx, &vy, &wz);
  EXPECT_NEAR(vx, 0.02, 1e-9);  // 59 ticks of 0.02 m/s
  EXPECT_EQ(wz, 0.0);           // still blocked by vx
  rampVelocityCommand(0.0, 0.0, -1.0, 0.02, 0.03, &vx, &vy, &wz);
  EXPECT_EQ(vx, 0.0);
  EXPECT_NEAR(wz, -0.03, 1e-12);  // rises in the tick vx reaches 0
  for (int i = 0; i < 33; ++i) rampVelocityCommand(0.0, 0.0, -1.0, 0.02, 0.03, &vx, &vy, &wz);
  EXPECT_NEAR(wz, -1.0, 1e-9);  // 34 ticks: 33 x 0.03 = 0.99, the last snaps
  EXPECT_EQ(vy, 0.0);
}

TEST(CommandInput, AxisKeyIsIgnoredWhileAnotherAxisIsMoving) {
  CommandInput walking;
  press(walking, 'W');
  run(walking, 60);
  press(walking, 'A');  // W still held: vx keeps its target, A stays blocked
  press(walking, 'Q');
  run(walking, 20);
  EXPECT_EQ(walking.state().vx, 1.2);
  EXPECT_EQ(walking.state().vy, 0.0);
  EXPECT_EQ(walking.state().wz, 0.0);

  CommandInput turning;
  press(turning, 'A');
  run(turning, 34);
  press(turning, 'W');  // A held first: wz keeps priority
  run(turning, 10);
  EXPECT_EQ(turning.state().wz, 1.0);
  EXPECT_EQ(turning.state().vx, 0.0);
}

CommandLimits steerLimits() {
  CommandLimits l;
  l.steerVx = 0.6;  // the walk's forward_turn
  l.steerWz = 0.5;
  return l;
}

TEST(CommandInput, WithSteerLimitsWAndAWalkForwardAndTurnTogether) {
  CommandInput input(steerLimits());
  press(input, 'W');
  run(input, 60);
  ASSERT_EQ(input.state().vx, 1.2);
  press(input, 'A');
  input.tick();  // both move in the same tick: vx down toward 0.6, wz up toward 0.5
  EXPECT_NEAR(input.state().vx, 1.18, 1e-12);
  EXPECT_EQ(input.state().wz, 0.03);
  run(input, 16);  // 17 ticks: 16 x 0.03 = 0.48, the 17th snaps to 0.5; vx 1.2 - 17 x 0.02 = 0.86
  EXPECT_EQ(input.state().wz, 0.5);
  EXPECT_NEAR(input.state().vx, 0.86, 1e-12);
  run(input, 13);  // 30 ticks: vx 1.2 - 30 x 0.02 = 0.6
  EXPECT_NEAR(input.state().vx, 0.6, 1e-12);
  run(input, 20);
  EXPECT_EQ(input.state().vx, 0.6);
  EXPECT_EQ(input.state().wz, 0.5);
  EXPECT_EQ(input.state().vy, 0.0);

  // A let go under W: straightens out at speed (vx never drops below the steer's 0.6)
  release(input, 'A');
  double lowest = 1e9;
  for (int i = 0; i < 30; ++i) input.tick(), lowest = std::min(lowest, input.state().vx);
  EXPECT_NEAR(lowest, 0.62, 1e-12);
  EXPECT_NEAR(input.state().vx, 1.2, 1e-12);  // 30 x 0.02 = 0.6 up
  EXPECT_EQ(input.state().wz, 0.0);           // 17 ticks down
}

TEST(CommandInput, WithSteerLimitsLettingWGoUnderATurnsOnInPlace) {
  CommandInput input(steerLimits());
  press(input, 'W');
  press(input, 'D');  // from rest, together: forward and right at once
  input.tick();
  EXPECT_EQ(input.state().vx, 0.02);
  EXPECT_EQ(input.state().wz, -0.03);
  run(input, 40);
  EXPECT_NEAR(input.state().vx, 0.6, 1e-12);
  EXPECT_EQ(input.state().wz, -0.5);
  release(input, 'W');
  run(input, 17);  // vx 0.6 - 17 x 0.02 = 0.26 while wz goes on to -1.0 (17 x 0.03 = 0.51: it snaps at 0.5 more)
  EXPECT_NEAR(input.state().vx, 0.26, 1e-12);
  EXPECT_EQ(input.state().wz, -1.0);
  run(input, 13);
  EXPECT_EQ(input.state().vx, 0.0);
  EXPECT_EQ(input.state().wz, -1.0);
}

TEST(CommandInput, SteerLimitsLeaveSidewaysAndBackwardKeysUnderTheInterlock) {
  CommandInput input(steerLimits());
  press(input, 'W');
  run(input, 60);
  press(input, 'Q');  // a sideways key: no steering, and the interlock blocks Q while vx moves
  press(input, 'A');
  run(input, 20);
  EXPECT_EQ(input.state().vx, 1.2);
  EXPECT_EQ(input.state().wz, 0.0);
  EXPECT_EQ(input.state().vy, 0.0);

  CommandInput back(steerLimits());
  press(back, 'S');
  press(back, 'A');
  run(back, 10);  // S first in the interlock's order, A blocked
  EXPECT_NEAR(back.state().vx, -0.2, 1e-12);
  EXPECT_EQ(back.state().wz, 0.0);
}

TEST(CommandInput, PressingTwoAxesTogetherFromRestMovesTheFirstInOrderVxVyWz) {
  CommandInput input;
  press(input, 'W');
  press(input, 'D');
  input.tick();
  EXPECT_EQ(input.state().vx, 0.02);
  EXPECT_EQ(input.state().wz, 0.0);

  CommandInput sideAndTurn;
  press(sideAndTurn, 'E');
  press(sideAndTurn, 'A');
  sideAndTurn.tick();
  EXPECT_EQ(sideAndTurn.state().vy, -0.02);
  EXPECT_EQ(sideAndTurn.state().wz, 0.0);
}

TEST(CommandInput, ReleasingRampsBackToZero) {
  CommandInput input;
  press(input, 'W');
  run(input, 60);
  release(input, 'W');
  run(input, 30);  // 1.2 - 30 x 0.02 = 0.6
  EXPECT_NEAR(input.state().vx, 0.6, 1e-12);
  run(input, 30);  // 60 ticks down: exactly 0
  EXPECT_EQ(input.state().vx, 0.0);
}

TEST(CommandInput, OtherKeysHaveTheirTargetsAndSigns) {
  CommandInput back;
  press(back, 'S');
  run(back, 30);  // -0.6 / -0.02 = 30 ticks
  EXPECT_EQ(back.state().vx, -0.6);

  CommandInput left;
  press(left, 'Q');
  run(left, 20);  // 0.4 / 0.02 = 20 ticks
  EXPECT_EQ(left.state().vy, 0.4);

  CommandInput right;
  press(right, 'E');
  run(right, 20);
  EXPECT_EQ(right.state().vy, -0.4);

  CommandInput turnRight;
  press(turnRight, 'D');
  run(turnRight, 34);
  EXPECT_EQ(turnRight.state().wz, -1.0);

  CommandInput both;
  press(both, 'W');
  press(both, 'S');  // opposing keys cancel
  run(both, 5);
  EXPECT_EQ(both.state().vx, 0.0);
}

TEST(CommandInput, DigitTapSetsSkillRequestAndReleasesAfterOneTick) {
  CommandInput input;
  tap(input, '3');
  EXPECT_EQ(input.state().skillRequest, 3);
  input.tick();
  EXPECT_EQ(input.state().skillRequest, 3);  // stays until another skill key
  EXPECT_EQ(input.state().keysHeld, 0u);
  press(input, '0');
  EXPECT_EQ(input.state().skillRequest, 0);
}

TEST(CommandInput, LetterTapActsForExactlyOneTick) {
  CommandInput input;
  tap(input, 'W');
  EXPECT_EQ(keysHeldString(input.state()), "W");
  input.tick();
  EXPECT_EQ(input.state().vx, 0.02);
  EXPECT_EQ(input.state().keysHeld, 0u);
  input.tick();
  EXPECT_EQ(input.state().vx, 0.0);

  CommandInput tapThenHold;  // "0 tap W" then "0 down W": held from then on
  tap(tapThenHold, 'W');
  press(tapThenHold, 'W');
  run(tapThenHold, 2);
  EXPECT_EQ(tapThenHold.state().vx, 0.04);
}

TEST(CommandInput, AmplitudeRampsWithRAndFAndClampsToZeroOne) {
  CommandInput input;
  press(input, 'F');
  run(input, 10);
  EXPECT_EQ(input.state().amplitude, 0.0);  // already at the lower bound
  release(input, 'F');
  press(input, 'R');
  run(input, 50);
  EXPECT_NEAR(input.state().amplitude, 0.5, 1e-12);  // 50 x 0.01
  run(input, 50);
  EXPECT_EQ(input.state().amplitude, 1.0);  // 100 x 0.01, snapped exactly
  run(input, 50);
  EXPECT_EQ(input.state().amplitude, 1.0);
  press(input, 'F');  // R and F together: no change
  run(input, 10);
  EXPECT_EQ(input.state().amplitude, 1.0);
  release(input, 'R');
  run(input, 25);
  EXPECT_NEAR(input.state().amplitude, 0.75, 1e-12);
  release(input, 'F');
  run(input, 10);  // no key: amplitude holds
  EXPECT_NEAR(input.state().amplitude, 0.75, 1e-12);
}

TEST(CommandInput, LowerAmplitudeStepsDownAtTheKeysRateToZero) {
  // the session lowers a squat's depth this way before a skill that starts from the default pose (the jump)
  CommandInput input;
  press(input, 'R');
  run(input, 30);
  release(input, 'R');
  run(input, 1);
  ASSERT_NEAR(input.state().amplitude, 0.3, 1e-12);
  for (int i = 0; i < 10; ++i) input.lowerAmplitude();
  EXPECT_NEAR(input.state().amplitude, 0.2, 1e-12);  // 10 x 0.01
  for (int i = 0; i < 50; ++i) input.lowerAmplitude();
  EXPECT_EQ(input.state().amplitude, 0.0);  // clamped
  run(input, 5);
  EXPECT_EQ(input.state().amplitude, 0.0);  // and it stays there with no key held
}

TEST(CommandInput, SetLimitsRampsToTheNewTargetAtTheRate) {
  CommandInput input;
  press(input, 'W');
  run(input, 60);
  CommandLimits slow;
  slow.vxForward = 0.5;
  input.setLimits(slow);
  run(input, 34);  // (1.2 - 0.5) / 0.02 = 35 ticks
  EXPECT_NEAR(input.state().vx, 0.52, 1e-12);
  input.tick();
  EXPECT_EQ(input.state().vx, 0.5);
}

TEST(CommandInput, KeysHeldStringListsLettersThenDigits) {
  CommandInput input;
  EXPECT_EQ(keysHeldString(input.state()), "");
  press(input, 'A');
  press(input, 'W');
  EXPECT_EQ(keysHeldString(input.state()), "W+A");
  press(input, '3');
  press(input, 'F');
  EXPECT_EQ(keysHeldString(input.state()), "W+A+F+3");
  release(input, 'W');
  EXPECT_EQ(keysHeldString(input.state()), "A+F+3");
  EXPECT_EQ(keyMask('W'), 1u << 10);
  EXPECT_EQ(keyMask('0'), 1u);
  EXPECT_EQ(keyMask('x'), 0u);
}

TEST(CommandInput, IgnoresUnknownKeysAndStrayReleases) {
  CommandInput input;
  input.apply(KeyEvent{0, KeyAction::kDown, 'x'});
  release(input, 'W');
  input.tick();
  EXPECT_EQ(input.state().keysHeld, 0u);
  EXPECT_EQ(input.state().vx, 0.0);
}

}  // namespace
}  // namespace engine
