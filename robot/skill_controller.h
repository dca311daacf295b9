// skill_controller.h — turns a skill's policy output into PD targets: default pose + action scale x action
// + the skill's feed-forward prior (paper §3.1), and the switching rules: the pieces robot/skill_runtime.h
// composes into the one control step that play, training and the cards run.
#pragma once

#include <array>

#include "robot/skill_layout.h"
#include "robot/skill_tree.h"

namespace robot {

/// The gait counter tp of the phase prior (counts control ticks 1..2 T1, then wraps) and the share of the
/// stepping amplitude in use (gait, 0..1), which fades with the skill's stand ramp.
struct PhaseClock {
  int tp = 0;
  double gait = 0.0;
  /// Advances the counter one tick.
  void advance(int halfPeriodTicks) { tp = tp >= 2 * halfPeriodTicks ? 1 : tp + 1; }
  /// Advances the counter one tick and moves gait toward 1 (stepping) or 0 (a phase prior that stands still at
  /// a zero command, or a skill without a phase prior) by 1 / standRampTicks (at once when that is 0).
  void advance(const PriorDef& prior, const SkillCommand& command);
};

/// Left/right activation u1, u2 in [0, 1] of the cosine phase prior at counter tp.
void phaseActivation(int tp, int halfPeriodTicks, double* u1, double* u2);

/// sin and cos of the gait phase pi tp / T1 (one cycle = 2 T1 ticks), for the observation.
void phaseSignal(int tp, int halfPeriodTicks, double* s, double* c);

/// After a new draw into *command: *target takes the draw and, when the commands ramp, *command keeps the
/// velocities it had before the draw (`before`) so that the ramp moves them there.
void takeCommandDraw(const SkillCommand& before, bool ramp, SkillCommand* command, SkillCommand* target);

/// True when every motion command is zero (the walk's "stand still" case).
bool commandIsZero(const SkillCommand& c);

/// The action a skill applies this tick: clip the policy output to +-kActionClip, then low-pass it with the
/// skill's filter (the lab's agent smooths its 100 Hz actions the same way). `applied` holds last tick's value.
void filterAction(const SkillDef& skill, const float* policyOutput, std::array<float, kActionSize>* applied);

/// PD command for this tick: target = default + scale * clip(action) + prior; gains from the skill. A phase
/// prior with standStill steps with dh x phase.gait when the skill has a stand ramp, else with dh or 0 (zero
/// command).
void skillPdCommand(const RobotModel& model, const SkillDef& skill, const std::array<float, kActionSize>& action,
                    const PhaseClock& phase, const SkillCommand& command, PdCommand* out);

// --- falls ---

/// The pelvis's forward pitch from its body axes [rad]: 0 upright, +pi/2 face down (nose toward the ground),
/// -pi/2 on its back; well defined at +-pi/2, where the ZYX Euler pitch is not.
double forwardPitch(const Sensors& sensors);
/// The pelvis's sideways lean [rad]: the angle of its left (y) axis above the horizontal; 0 upright and face down.
double sideLean(const Sensors& sensors);
/// Why the skill's termination calls this state a fall (None: it does not). Upright skills
/// (maxForwardPitchDegrees < 0): the pelvis below minHeight (Low), or |roll| or |pitch| above maxTiltDegrees
/// (Tilt). Ground skills: Low, the side lean above maxTiltDegrees (Side), the backward pitch above it (Back), or
/// the forward pitch above maxForwardPitchDegrees (OverHead).
enum class FallCause { None, Low, Tilt, Side, Back, OverHead };
FallCause fallCause(const TerminationDef& termination, const Sensors& sensors);
inline bool hasFallen(const TerminationDef& termination, const Sensors& sensors) {
  return fallCause(termination, sensors) != FallCause::None;
}

// --- switching: the rules robot::route (robot/skill_runtime.h) composes ---

/// A switch fades the old skill's prior into the new one's over this many ticks (0.3 s): without it a switch
/// in mid-step drops a lifted foot's prior (up to 1.1 rad at the knee) in one tick.
constexpr int kSwitchFadeTicks = 30;
/// A skill without a velocity command (squat, jump, one_leg: it stands where it is) is entered from rest: the
/// active skill's velocity command ramps to zero and the switch waits until the pelvis moves slower than
/// kRestSpeed [m/s] and turns slower than kRestYawRate [rad/s] with both feet down, or kMaxRestWaitTicks at most.
constexpr double kRestSpeed = 0.15;
constexpr double kRestYawRate = 0.3;
constexpr int kMaxRestWaitTicks = 150;

/// True for a ground skill (prone, crawl): its termination lets it lie face down (maxForwardPitchDegrees set).
inline bool isGroundSkill(const SkillDef& skill) { return skill.termination.maxForwardPitchDegrees >= 0; }

/// True when `from` may hand the robot over to `to`: always for an upright `from`; a ground skill hands a lying
/// robot only to another ground skill or to its `up` skill (a stand-up), never straight to an upright skill.
bool mayHandOver(const SkillDef& from, const SkillDef& to);

/// The way the robot faces on the ground, a unit vector (world x, y): on all fours or lying face down the pelvis's x
/// axis points at the ground, so it is the pelvis's z axis (toward the head) on the ground, or its x axis while the
/// pelvis is near upright.
Eigen::Vector2d groundHeading(const Sensors& sensors);

/// Standing again after a stand-up: pelvis at least kStoodPelvisHeight [m] up, tilted less than
/// kStoodTiltDegrees. A ground skill hands over to an upright one (standup -> walk) only once the robot stands so:
/// a routed request (key 0 while lying) would otherwise hand a half-risen robot to the walk after kMinHopTicks.
constexpr double kStoodPelvisHeight = 0.70;
constexpr double kStoodTiltDegrees = 10.0;
bool hasStoodUp(const Sensors& sensors);
/// True when the switch from `from` to `to` may happen now as far as posture goes: always, except from a ground
/// skill to an upright one (its stand-up's way up), which waits until the robot stands (hasStoodUp) and has
/// settled there (atRestForSwitch, and rising or sinking slower than kRestSpeed). (The walk taking over at the first
/// tick of the stand, the stand-up prior still rising, fell in 10 of 20 episodes of the standup card.)
/// From a ground skill to one of its ground branches (prone -> pushup, crawl, standup) it waits until the robot lies
/// face down and still (isLyingStill): a request routed walk -> prone -> pushup would otherwise start the push-ups
/// from standing, one tick after prone.
/// Into or out of an upright skill driven by key poses from the default pose (the jump, the kick) it waits until the
/// robot stands settled (isStandingSettled): routed walk -> squat -> jump, the jump began one tick after the squat,
/// the legs still stepping in place, and fell at its first landing; out of it, the squat took over mid-flight. (The
/// session also brings a squat's depth or a one-leg lift back to 0 first: CommandInput::lowerAmplitude.)
/// Out of such a skill, once the switch has waited `waitedTicks` >= kMaxSettleWaitTicks, at rest on both feet and
/// level is enough (atRestForSwitch, rising or sinking slower than kRestSpeed), the leg joints free to move.
bool postureAllowsSwitch(const SkillDef& from, const SkillDef& to, const Sensors& sensors, int waitedTicks);
/// A skill whose prior is a repeating cycle of key poses from the default pose (the jump; not a ground skill's
/// gait). A request out of it is met only in the cycle's closing stand (from closingStandTick on), and while it waits
/// the clock holds in that stand instead of starting the next crouch (holdsClosingStand): the walk asked for after a
/// jump (routed through the squat) took over while the robot was still absorbing the landing, the pelvis 0.13 m low
/// and rising, and fell 0.4 s later (14 of levels/mario's 19 walk falls over autopilot seeds 1-20). A still
/// destination (the squat) also waits until the robot has stopped drifting (`drift`, robot::updateDrift, under
/// kSettleDrift; after kMaxSettleWaitTicks of waiting, the closing stand alone): the squat taking over at the first
/// settled moment after a landing, still drifting back at ~0.2 m/s, turned on the spot and fell. A moving one steps
/// out of the drift (with the drift rule for it too, the jump fell 50 times over seeds 1-60, against 17).
bool isKeyPoseCycle(const SkillDef& skill);
/// The tick of the cycle's key before the last (the last repeats its pose: the stand that closes each cycle).
int closingStandTick(const PriorDef& prior);
/// True unless `from` is a key-pose cycle and the cycle (or, for a still `destination`, the drift) is not there yet
/// (see isKeyPoseCycle). `waitedTicks`: how long the switch has waited.
bool cycleAllowsSwitch(const SkillDef& from, const SkillDef& destination, const PhaseClock& phase, double drift,
                       int waitedTicks);
/// True when the clock of `skill` stays where it is this tick: a request out of it to a still destination waits
/// (`waitsForStill`) and its cycle has reached its closing stand.
bool holdsClosingStand(const SkillDef& skill, const PhaseClock& phase, bool waitsForStill);
/// A kick policy may not stand still after its kick: it turns on the spot and steps (a later
/// fine-tune of it taps its right foot, leg joints at 0.6-3 rad/s, both feet down a third of the time), so waiting for
/// a settled stand, kick -> one_leg never happened (0 of 20, `eval switches`). Rest on both feet and level at once
/// made that 20 of 20, but out of the jump the walk then took over at its first landing and
/// fell (37 falls of the walk right after jump -> squat -> walk over autopilot seeds 1-28 of levels/mario); the jump
/// stands settled within ~1.2 s, so it keeps the full rule. 3 s: as long as a training handover out of a key-pose
/// skill waits (ai/env/skill_env.h) and within `eval switches`' 6 s.
constexpr int kMaxSettleWaitTicks = 300;

/// True when the gait phase allows the switch from `from` to `to` now: always, except into a skill with a
/// switch_in_phase window from a skill with a phase prior, which waits until from's clock `phase` is within that
/// fraction of its cycle. (The run taking over from the walk with W held fell within 3 s in 15 % of switches at
/// random moments, nearly all of them made in the walk's phase 0.85-0.30 or 0.42-0.46; none in 0.50-0.82 over
/// three seeds: docs/skills/run.md.)
bool phaseAllowsSwitch(const SkillDef& from, const SkillDef& to, const PhaseClock& phase);

/// Steering back toward a line as a player would (the crawl card's `steer`, training's `line_steer`): the line
/// error (line.aux0 + 0.5 line.aux1: heading off it [rad] and offset across it [m], robot::lineIntoCommand) is
/// averaged over about a second in `averaged`, and the yaw-rate command is -gain x that, within the wz range.
double steerTowardLine(const CommandDef& commands, double gain, const SkillCommand& line, double* averaged);

/// An upright skill whose prior is key poses from the default pose (the jump, the kick).
bool startsFromDefaultPose(const SkillDef& skill);
/// Leg joints slower than this [rad/s], with atRestForSwitch, is standing settled.
constexpr double kSettledJointSpeed = 0.3;
/// At rest on both feet (atRestForSwitch), not rising or sinking (kRestSpeed), every leg joint slower than
/// kSettledJointSpeed.
bool isStandingSettled(const Sensors& sensors);

/// Lying face down as prone leaves the robot: pelvis below 0.35 m, forward pitch 70-110 deg (as the ground cards
/// count it when the skill begins).
bool isLyingFaceDown(const Sensors& sensors);
/// Lying face down and still (moving and sinking slower than kRestSpeed).
bool isLyingStill(const Sensors& sensors);

/// True for a skill that stands where it is: its commands have no vx, vy or wz range.
bool isStillSkill(const SkillDef& skill);
/// True when a still skill may take over (see kRestSpeed).
bool atRestForSwitch(const Sensors& sensors);
/// A moving skill is entered at a speed it was trained for: the forward speeds both skills train at, [lo, hi] with
/// lo the larger of their lowest speeds (vx.lo, or at most 0 for a skill that also turns or steps sideways: the
/// keyboard's interlock trains it at vx = 0) and hi the smaller of their top speeds. When `from` may move outside
/// that band (run at 2 m/s -> walk, top 1.2 m/s; walking backward -> run, which never backs up), `from`'s command
/// ramps to the keys' command clamped into the band
/// (switchBrakeTarget) and the switch waits until the pelvis's forward speed is within kSlowMargin of the band, or
/// kMaxSlowWaitTicks at most. (Without it the walk took over from a 2 m/s run and fell in 1 of 10 trials of `eval
/// switches`, 4 of 9 with S pressed at the switch; the run took over from a backward walk and fell in 3 of 40.)
constexpr double kSlowMargin = 0.25;
/// ... and no slower than the target less this (a walk commanded 1.2 m/s walks 0.8: it hands over to the run then,
/// but not while it is still turning round from walking backward, where the run fell in 3 of 40 trials).
constexpr double kTargetSlack = 0.5;
/// The longest a switch into a moving skill waits for its speed (a 2 m/s run needs ~1 s to brake to a standstill).
constexpr int kMaxSlowWaitTicks = 250;
/// The longest a switch from `from` to `to` waits: kMaxRestWaitTicks into a still skill (kMaxSettleWaitTicks into
/// one with settle_first), else kMaxSlowWaitTicks.
int maxSwitchWaitTicks(const SkillDef& to);
/// True when a switch from `from` to `to` first waits: for rest (a still `to`) or for `to`'s speeds.
bool switchWaits(const SkillDef& from, const SkillDef& to);
/// The velocity command `from` ramps toward while a switch to `to` waits: zero for a still `to`; else `wanted`
/// (the keys' command) with its forward part clamped into the band both skills command (the run brakes to the
/// walk's 1.2 m/s, not on toward an S key's -0.6, which it never trained for).
SkillCommand switchBrakeTarget(const SkillDef& from, const SkillDef& to, const SkillCommand& wanted);
/// True when the waiting switch may happen: the braking command `brake` has reached `target` (the
/// switchBrakeTarget) and the pelvis has come to rest (still `to`; into one with settle_first, the robot has also
/// stopped drifting: `drift`, its horizontal velocity low-passed over kDriftSeconds, is under kSettleDrift) or moves
/// forward within kSlowMargin of the band both skills train at and no slower than kTargetSlack below the target.
bool readyForSwitch(const SkillDef& from, const SkillDef& to, const SkillCommand& target, const SkillCommand& brake,
                    const Sensors& sensors, double drift = 0.0);
/// Into a settle_first skill (the one-leg stand) the robot has come to a stop: its drift (the pelvis's horizontal
/// velocity low-passed over kDriftSeconds, which averages out the sway of stepping in place: 0-0.22 m/s each step)
/// is under kSettleDrift [m/s]. Taking over at the first moment at rest after W was released, the one-leg stand fell
/// in 4 of 6 seeds on levels/flat (the pelvis passes 0.15 m/s while the walk is still braking); the walk
/// stepping in place never stills its legs, so a settled stand (isStandingSettled) would wait kMaxSettleWaitTicks.
constexpr double kDriftSeconds = 0.4;
constexpr double kSettleDrift = 0.04;
/// One tick of the drift's low-pass: the world horizontal velocity of the pelvis into `drift` [m/s].
void updateDrift(const Sensors& sensors, Eigen::Vector2d* drift);
/// The gait counter at a switch keeps its fraction of the cycle under the new skill's period; a keyframes prior
/// starts its motion from the beginning (tp = 0).
void carryPhase(const PriorDef& from, const PriorDef& to, PhaseClock* phase);
/// The fade after a switch: adds w (from's prior - to's prior) to out's targets (clamped to the joint limits), each
/// prior at its own clock (fromPhase: the old skill's clock as it was at the switch, advanced under from's prior
/// every tick of the fade; phase: the new skill's) and the same command; w runs from 1 down to 0 over
/// kSwitchFadeTicks. (Taking from's prior at the new skill's clock jumped the targets by up to 1.07 rad in the tick
/// of a walk -> run switch, whose cycles differ, and fell back to the walk cycle's start for a keyframes skill.)
void fadePrior(const RobotModel& model, const SkillDef& from, const PhaseClock& fromPhase, const SkillDef& to,
               const PhaseClock& phase, const SkillCommand& command, double w, PdCommand* out);

}  // namespace robot
