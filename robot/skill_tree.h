// skill_tree.h — the skill tree as the runtime needs it (assets/skills/tree.toml): per skill its parent, key, prior,
// PD gains, action scales, command ranges and what counts as a fall. Training's tables of the same file (draws,
// rewards, randomisation, training, terrain, curriculum, ball, card) are ai::loadTrainingTree's. Names, not indices;
// validated at load with file:line errors. Format documented in assets/skills/README.md.
#pragma once

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "robot/robot.h"

namespace robot {

/// Feed-forward prior (paper §3.1): a cosine phase signal on hip/knee/ankle pitch for periodic skills, a key
/// pose scaled by the amplitude command for aperiodic ones (squat: default pose at 0, the full pose at 1), or none.
struct PriorDef {
  enum class Kind { None, Phase, Pose, Jump, Kick, Keyframes } kind = Kind::None;
  JointArray poseOffset{};  ///< Pose: joint offsets from the default pose at amplitude 1 [rad]; Jump: the crouch
  /// Jump: a 2 T1-tick cycle that sinks into `crouch` x poseOffset and back over its first 60 % (cosine), then
  /// leaves the legs at the default pose for the flight and landing; the push itself is the policy's.
  double crouch = 0.0;
  /// Kick: a 2 T1-tick cycle that lifts into poseOffset over its first 35 % (cosine), adds swingOffset as a
  /// cosine bump over 40-60 % (the kick), holds the lift and lowers the leg over the last 20 %.
  JointArray swingOffset{};
  /// Pose with a second stage (hasLate): offset x min(1, 2 a) + lateOffset x max(0, 2 a - 1) for amplitude a,
  /// so that the first half of the amplitude moves into the offset pose (e.g. the weight over one foot) and the
  /// second half adds the late pose (e.g. lifts the other foot). Without one: offset x a.
  JointArray lateOffset{};
  bool hasLate = false;
  /// Keyframes: joint offsets from the default pose at given ticks after the skill starts (the first key is
  /// the default pose at tick 0, implicitly), eased between keys with a half cosine and held after the last one.
  /// The clock counts up to the last key's tick and stops there (halfPeriodTicks = that tick, so the phase
  /// observation's cosine runs from 1 to -1 over the motion): a one-shot motion such as lying down. With
  /// `repeat` the motion is a cycle instead (jumps in a row): the clock wraps to 0 at the last key's tick
  /// (cycleTicks), so the last key should be near the default pose, and halfPeriodTicks is half the cycle, so
  /// the phase observation goes once round the circle per cycle. With `repeat_from = t` (a key's time) the motion
  /// is a lead-in and a cycle: the clock runs up to the last key once, then wraps back to that key's tick
  /// (cycleStartTick) instead of 0, so the last key should repeat that key's pose (a crawl's gait after the move
  /// onto hands and knees); halfPeriodTicks is then half of the cycle from that key to the last.
  struct Keyframe {
    int tick = 0;
    JointArray offset{};
  };
  std::vector<Keyframe> keyframes;
  int cycleTicks = 0;        ///< repeating keyframes: the last key's tick, where the clock wraps (0: one shot)
  int cycleStartTick = 0;    ///< repeating keyframes: the tick the clock wraps to (0, or repeat_from's key)
  int halfPeriodTicks = 40;  ///< T1: ticks per leg phase (gait period = 2 T1 ticks of 0.01 s)
  double dh = 0.0;           ///< stepping amplitude [rad]: hip -= A, knee += 2A, ankle -= A with A = dh u + d0
  double d0 = 0.0;           ///< base offset [rad] added to A
  bool standStill = true;    ///< dh = 0 while the command is zero (the lab's walk stands still)
  /// Ticks over which the stepping amplitude fades out when the command becomes zero and back in when it stops
  /// being zero (PhaseClock::gait); 0 = at once, as in the lab's agent.
  int standRampTicks = 0;
  /// Hip swing per forward command [rad per m/s]: the left hip pitch gets + stride vx cos(pi tp / T1) (the
  /// right one the opposite, ankles compensate so the feet stay level): backward at lift-off, forward at
  /// touch-down, so a leg's stance sweeps it back at about the commanded speed. 0 = stepping in place.
  double stride = 0.0;
  /// Arm swing per forward command [rad per m/s], as the lab's agent does: each shoulder pitch swings against its
  /// own leg's hip (left shoulder - armSwing vx cos(pi tp / T1)), which cancels part of the legs' yaw torque.
  double armSwing = 0.0;
  /// Turn per yaw-rate command [rad per rad/s]: joint offsets scaled by the command's wz and added to the prior of
  /// any kind (a crawl turns by twisting its waist: the gait alone has no way to steer). Zero: no turn term.
  JointArray turn{};
};

/// The two stage weights of a pose prior at amplitude a: first (offset) and late (lateOffset); see PriorDef.
void poseStages(const PriorDef& prior, double amplitude, double* first, double* late);

/// A [lo, hi] range.
struct Range {
  double lo = 0, hi = 0;
};

/// The commands a skill takes ([skill.NAME.commands]): their ranges, which play's keys and heading hold stay within
/// and training draws from (ai::CommandDraws says how), and what the aux command slots show.
struct CommandDef {
  Range vx, vy, wz;                ///< [m/s, m/s, rad/s]
  Range amplitude;                 ///< the amplitude command (0..1: R / F in play)
  Range pelvisHeight{0.78, 0.78};  ///< pelvis height the amplitude asks for at 0 (lo) and at 1 (hi) [m]
  /// In play only (robot::shapeCommand's heading hold, W / S / Q / E with no turn key): 0 keeps the heading the robot
  /// had when it started moving; > 0 also leans that heading back toward the line it started on, by
  /// atan(lineHold x offset) with the offset in metres
  double lineHold = 0.0;
  /// In play only: W held with A or D drives forward at steerVx [m/s] turning at +-steerWz [rad/s] together (the keys'
  /// engine::CommandLimits::steerVx / steerWz), as a driver steers; 0 (the default): the keyboard's strict interlock,
  /// W blocks A and D
  double steerVx = 0.0, steerWz = 0.0;
  /// > 0: a ground skill is steered back toward the line it began on, in play (robot::shapeCommand, with no turn
  /// key), in training and on its card, as a player steers: each tick wz = -lineSteer x (heading off the line +
  /// 0.5 rad/m x offset across it), the error averaged over about a second, within the wz range (which must straddle
  /// 0); the steered yaw rate does not turn the line. 0: off.
  double lineSteer = 0.0;
  /// true: the skill sees the line it began on (where it took over, the way it faced) in its aux command slots
  /// (robot::lineIntoCommand), in training, on its card and in play
  bool lineCommand = false;
  /// true: the skill sees the next step ahead, its rise and distance, in its aux command slots
  /// (robot::stepIntoCommand), in training, on its card and in play: the stairs
  bool stepCommand = false;
  /// true: the skill sees a ball, where it is and where it should go, in its aux command slots
  /// (robot::ballIntoCommand), in training (the [ball] table places it), on its card and in play: the kick
  bool ballCommand = false;
  /// true (with stepCommand): past the last edge ahead, the edge a trailing foot has still to cross is shown
  /// behind the pelvis (robot::stepIntoCommand's lookBack): the last step off a staircase
  bool stepLookBack = false;
};

struct TerminationDef {
  double maxTiltDegrees = 30;  ///< |roll| or |pitch| beyond this ends the episode as a fall
  /// A ground skill (lying, crawling) sets this: the pelvis may pitch forward (nose down) up to this angle
  /// [deg], and maxTiltDegrees bounds only the side lean and the backward pitch, both measured from the body
  /// axes (robot::forwardPitch, robot::sideLean), which stay well defined face down where Euler angles do not.
  /// < 0: the upright check above.
  double maxForwardPitchDegrees = -1;
  double minHeight = 0.5;      ///< pelvis below this [m] is a fall
  double episodeSeconds = 10;  ///< time limit (a truncation, not a fall)
  /// One-leg skills: > 0 ends the episode as a fall when the lifted (right) foot touches the ground after a lift
  /// of at least half the full one (ai::kFootLiftHeight / 2) has been asked for this long [s]; 0: off. (A policy
  /// paid only while the foot is up learns to balance by tapping it down.)
  double liftedFootTouchSeconds = 0;
};

/// One skill of the tree.
struct SkillDef {
  std::string name;
  std::string parent;  ///< "" for the root
  /// The skill a request further up the tree switches to first, when that is not the parent: prone (lying)
  /// cannot switch back to walk, so its way up is standup, and standup's way up is walk. "" = the parent.
  std::string up;
  int key = -1;  ///< 0..9; -1: none (a skill reached only by routing through it, as another's `up`)
  /// A switch into this skill from one with a phase prior waits until that skill's gait phase, as a fraction of
  /// its cycle (tp / 2 T1), is within this range (at most one cycle: robot::phaseAllowsSwitch). [0, 1]: any phase.
  Range switchInPhase{0.0, 1.0};
  /// A still skill that stands on one foot (one_leg): a switch into it waits until the robot has stopped drifting
  /// (robot::kSettleDrift) and is at rest on both feet, up to kMaxSettleWaitTicks instead of kMaxRestWaitTicks
  /// (robot::readyForSwitch, robot::maxSwitchWaitTicks)
  bool settleFirst = false;
  std::string model;  ///< ONNX file name inside assets/skills/
  PriorDef prior;
  JointArray kp{}, kd{};      ///< PD gains per joint
  JointArray actionScale{};   ///< rad per policy unit, per joint
  double actionFilter = 0.0;  ///< low-pass on the policy output: u = f u + (1 - f) a (0 = none)
  CommandDef commands;
  TerminationDef termination;
  int line = 0;  ///< where it is defined
};

struct SkillTree {
  std::string path;
  std::string directory;
  std::vector<SkillDef> skills;

  /// The skill with this name, or nullptr.
  const SkillDef* find(const std::string& name) const;
};

/// Loads and validates the runtime's part of the tree: each skill's own keys, [prior], [gains], [action_scale],
/// [commands] and [termination]; the tables training reads are left to ai::loadTrainingTree. Joint groups in
/// [gains] and [action_scale] are matched against the model's joint names.
SkillTree loadSkillTree(const std::string& path, const RobotModel& model);

/// The tree file the apps use: assets/skills/tree.toml, unless setSkillTreePath chose another.
std::string defaultSkillTreePath();

/// Makes defaultSkillTreePath() return path (e.g. an experiment's copy of the tree; "" = back to the default).
void setSkillTreePath(const std::string& path);

/// Joint-group names usable in the tree file (hip_pitch, knee, ..., wrist_roll) and whether joint j belongs.
bool jointInGroup(const std::string& jointName, const std::string& group);

}  // namespace robot
