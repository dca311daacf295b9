// command.h — turns key events into the command the robot follows: a requested skill, a body
// velocity (vx, vy, wz) and an amplitude (e.g. squat depth), ramped once per control tick.
// The one-axis-at-a-time interlock comes from the lab's Unity G1 agent (G1moeAgent.cs, moe 0;
// see research/gewu-g1-facts.md §1.9), mapped to our Z-up, X-forward frame.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>

#include "engine/input/key_script.h"

namespace engine {

/// Bit for a canonical key in CommandState::keysHeld: '0'..'9' are bits 0..9, then W A S D Q E R F are
/// bits 10..17. Returns 0 for any other character.
uint32_t keyMask(char key);

/// What the keys ask for after the latest tick.
struct CommandState {
  int skillRequest = -1;   ///< -1: none yet; 0..9: the last skill key pressed (it stays until another one)
  double vx = 0.0;         ///< forward velocity command (m/s, +X forward)
  double vy = 0.0;         ///< sideways velocity command (m/s, +Y left)
  double wz = 0.0;         ///< yaw rate command (rad/s, + counter-clockwise about Z up, i.e. turn left)
  double amplitude = 0.0;  ///< skill amplitude, e.g. squat depth (0..1)
  uint32_t keysHeld = 0;   ///< keys currently down, bits as keyMask()
};

/// "W+A"-style list of the held keys, letters first (in W A S D Q E R F order), then digits; "" when none.
std::string keysHeldString(const CommandState& state);

/// Targets and ramp rates. Values are per control tick (0.01 s); rates must be > 0.
struct CommandLimits {
  double vxForward = 1.2;       ///< W target (m/s)
  double vxBackward = -0.6;     ///< S target (m/s, negative)
  double vyMax = 0.4;           ///< Q target +vyMax, E target -vyMax (m/s)
  double wzMax = 1.0;           ///< A target +wzMax, D target -wzMax (rad/s)
  double vRate = 0.02;          ///< largest change of vx and vy per tick (m/s per tick)
  double wzRate = 0.03;         ///< largest change of wz per tick (rad/s per tick)
  double amplitudeRate = 0.01;  ///< change of amplitude per tick while R (up) or F (down) is held
  /// W with A or D held: forward at steerVx (m/s) turning at +-steerWz (rad/s) together, as a driver steers; both
  /// > 0 to enable (a skill's [commands] forward_turn), 0: the strict interlock below (W blocks A and D)
  double steerVx = 0.0;
  double steerWz = 0.0;
};

/// One tick of the keyboard's velocity ramp with its interlock (below): vx, vy, wz move, in that order, toward
/// their targets by at most vRate, vRate, wzRate; an axis whose two others are not both zero (as already
/// updated in this tick) moves toward 0 instead. With targets that have one non-zero axis this gives what a
/// player's keys give: the old axis ramps down first, then the new one up. Training and report cards use it
/// so that a skill meets the command changes it meets in play.
void rampVelocityCommand(double targetVx, double targetVy, double targetWz, double vRate, double wzRate, double* vx,
                         double* vy, double* wz);

/// Key events in, one CommandState per control tick out.
///
/// Interlock (the paper's agent): at most one of vx, vy, wz is non-zero at a time.
///   W / S   : vx target vxForward / vxBackward, only while vy == 0 and wz == 0
///   Q / E   : vy target +vyMax (left) / -vyMax (right), only while vx == 0 and wz == 0
///   A / D   : wz target +wzMax (turn left) / -wzMax (turn right), only while vx == 0 and vy == 0
/// A blocked axis, an axis with no key, or an axis with both of its keys held has target 0. Each tick
/// the axes update in the order vx, vy, wz, each moving toward its target by at most its rate and each
/// checking the others' values as already updated in this tick. So: releasing W and pressing A while
/// walking ramps vx down to 0 first, and wz starts rising in the tick vx reaches 0; holding W and A
/// together from rest walks forward (vx is updated first and then blocks wz); holding A and then also W
/// keeps turning (wz blocks vx) until A is released and wz is back at 0.
/// Steering (limits with steerVx and steerWz > 0: the walk's forward_turn): W held with A or D (and no Q / E) targets
/// vx = steerVx and wz = +-steerWz at once, and while the command mixes a forward vx with a turn (vy 0) vx and wz move
/// toward their targets together rather than one after the other, so that letting A go under W straightens out at
/// speed and letting W go under A turns on in place. Once the command is back to one axis the interlock above holds.
/// R / F held raise / lower amplitude by amplitudeRate per tick, clamped to [0, 1] (both: no change).
/// Digit keys (down or tap) set skillRequest.
class CommandInput {
 public:
  /// Starts at rest: no keys, zero velocities, amplitude 0, no skill request.
  explicit CommandInput(CommandLimits limits = CommandLimits{});

  /// Applies one key event (call before tick() for the events of that tick). down/up press/release;
  /// tap presses now and releases at the end of the next tick(), so a letter tap acts for one tick.
  /// Events for keys that are not canonical are ignored; "up" of a key not held does nothing.
  void apply(const KeyEvent& event);

  /// Advances one control tick: computes targets from the held keys and ramps toward them.
  void tick();

  /// The command after the latest tick() (keysHeld and skillRequest also reflect later apply() calls).
  const CommandState& state() const { return state_; }

  /// Sets vx, vy and wz to 0 (a robot put back at rest, e.g. a respawn): held keys ramp them up again from there.
  void stopMotion() { state_.vx = state_.vy = state_.wz = 0.0; }
  /// Puts the command where `state` says (a play-entry state restored): held keys as its keysHeld, no taps pending.
  void restore(const CommandState& state) { state_ = state, tapped_ = 0; }

  /// Lowers the amplitude by one tick of its rate toward 0 (a skill that starts from the default pose waits for a
  /// squat's depth or a one-leg lift to come back); R held raises it again.
  void lowerAmplitude() { state_.amplitude = std::max(0.0, state_.amplitude - limits_.amplitudeRate); }

  /// Replaces targets and rates (e.g. when the active skill changes); values keep ramping from where they are.
  void setLimits(const CommandLimits& limits) { limits_ = limits; }

  /// The current targets and rates.
  const CommandLimits& limits() const { return limits_; }

 private:
  CommandLimits limits_;
  CommandState state_;
  uint32_t tapped_ = 0;  // keys pressed by a tap, released at the end of the next tick()
};

}  // namespace engine
