// skill_tree.h — the skill tree as data (assets/skills/tree.toml): per skill its parent, key, prior,
// PD gains, action scales, command ranges, reward weights, terminations, randomisation and training budget.
// Names, not indices; validated at load with file:line errors. Format documented in assets/skills/README.md.
#pragma once

#include <algorithm>
#include <array>
#include <map>
#include <string>
#include <vector>

#include "robot/robot.h"

namespace robot {

/// Feed-forward prior (paper §3.1): a cosine phase signal on hip/knee/ankle pitch for periodic skills, a key
/// pose scaled by the amplitude command for aperiodic ones (squat: default pose at 0, the full pose at 1), or none.
struct PriorDef {
  enum class Kind { None, Phase, Pose, Jump, Kick, Keyframes } kind = Kind::None;
  JointArray poseOffset{};   ///< Pose: joint offsets from the default pose at amplitude 1 [rad]; Jump: the crouch
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
  int cycleTicks = 0;  ///< repeating keyframes: the last key's tick, where the clock wraps (0: one shot)
  int cycleStartTick = 0;  ///< repeating keyframes: the tick the clock wraps to (0, or repeat_from's key)
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

struct CommandDef {
  Range vx, vy, wz;              ///< sampling ranges [m/s, m/s, rad/s]
  Range amplitude;               ///< sampling range of the amplitude command (0..1), drawn with every command
  double amplitudeRate = 0;      ///< the amplitude moves toward each new draw at this rate [1/s] (0 = at once);
                                 ///< 1.0 is the R / F keys' rate
  double amplitudeZero = 0;      ///< chance that an amplitude draw is 0 instead (the skill at rest, as play enters it)
  Range pelvisHeight{0.78, 0.78};  ///< pelvis height target at amplitude 0 (lo) and 1 (hi) [m], for height_track
  double zeroProbability = 0.2;  ///< chance that a sampled command is all zero
  /// true: vx / vy / wz reach each new draw at the keyboard's rates with its one-axis interlock
  /// (engine::rampVelocityCommand), as they do in play; false: they jump to it
  bool ramp = false;
  double resampleSeconds = 5.0;  ///< a new command every so often
  /// each interval is resampleSeconds x (1 + U(-jitter, jitter)): without it every change meets the gait at the
  /// same phase (5 s = 6.25 cycles of 0.8 s), and the policy never learns changes at the other phases
  double resampleJitter = 0.0;
  /// In play only (robot::shapeCommand's heading hold, W / S / Q / E with no turn key): 0 keeps the heading the robot
  /// had when it started moving; > 0 also leans that heading back toward the line it started on, by
  /// atan(lineHold x offset) with the offset in metres
  double lineHold = 0.0;
  /// > 0: each forward or sideways draw also turns at U(-steer, steer) rad/s, on top of the ramp's interlock and
  /// unramped, as play's heading hold turns the robot while W is held (robot::shapeCommand); 0: the
  /// interlock alone, so a skill never sees a turn while it moves
  double steer = 0.0;
  /// false: training draws no turn in place (a wz draw), so a skill that must go straight (the stairs) trains on
  /// its forward draws and steer's turns while moving; wz stays the limit of play's heading hold and turn keys
  bool turnInPlace = true;
  /// true: the skill sees the line it began on (where it took over, the way it faced) in its aux command slots
  /// (robot::lineIntoCommand), in training, on its card and in play; a ball skill's aux slots hold its ball
  bool lineCommand = false;
  /// true: the skill sees the next step ahead, its rise and distance, in its aux command slots
  /// (robot::stepIntoCommand), in training, on its card and in play: the stairs
  bool stepCommand = false;
  /// true (with stepCommand): past the last edge ahead, the edge a trailing foot has still to cross is shown
  /// behind the pelvis (robot::stepIntoCommand's lookBack): the last step off a staircase
  bool stepLookBack = false;
};

struct RandomisationDef {
  Range friction{1.0, 1.0};     ///< robot/ground friction coefficient
  Range addedMass{0.0, 0.0};    ///< added pelvis mass [kg]
  double pushEverySeconds = 0;  ///< 0 = no pushes
  Range pushSpeed{0.0, 0.0};    ///< horizontal velocity change of a push [m/s]
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
  /// paid only while the foot is up learned to balance by tapping it down: one_leg.train.md, session 21.)
  double liftedFootTouchSeconds = 0;
};

/// Terrain a skill trains on. Stairs (the level format's, levels::StairsDef): `steps` risers up along +X from
/// start_x, the last tread a landing top_depth deep, and as many risers down; the step height comes from the
/// curriculum's current lesson.
/// Ceiling: a low ceiling (a tunnel's roof) `height` above the ground, put over the robot once it lies down (a
/// ground skill's episodes start standing under the parent, and a standing robot does not fit under it): in
/// training a slab over the whole arena, on the card a tunnel `width` wide along the heading.
struct TerrainDef {
  enum class Kind { Flat, Stairs, Ceiling } kind = Kind::Flat;
  double ceilingHeight = 0.6;   ///< Ceiling: the underside's height above the ground [m]
  int steps = 10;
  double stepDepth = 0.30;      ///< tread [m]
  double startX = 1.0;          ///< flat run-up before the first step [m]
  double topDepth = 1.5;        ///< landing between up and down [m]
  double width = 4.0;           ///< across the robot's path [m]
  std::vector<double> lessons;  ///< step heights of the curriculum's lessons, in order [m]
  double advanceAt = 1.0;       ///< average episode score (SkillEnv::curriculumScore) that moves to the next lesson
  /// Stairs: the probability that a training episode starts on one of the staircase's treads (ai::stairsSpawn:
  /// up, on the landing or on the way down, facing +X) rather than before the first riser. A rollout is 10.24 s,
  /// so from the foot of the stairs no episode reaches the way down. Cards always start at the foot.
  double spawnAlong = 0.0;
};

/// A command curriculum: lesson i caps the forward command at vx_max[i] (run) or the amplitude command at
/// amplitude_max[i] (one-leg lift), and, where given, sets the gait's half period T1[i] and the stride prior's
/// gain stride[i]. The last lesson is the skill's own (the tree checks that they agree), so the shipped model runs
/// as it was last trained. Lessons advance as the terrain's do (advance_at); a skill has either terrain lessons or
/// a command curriculum.
struct CurriculumDef {
  std::vector<double> vxMax;          ///< [m/s], one per lesson (or empty)
  std::vector<double> amplitudeMax;   ///< one per lesson (or empty)
  std::vector<int> halfPeriodTicks;   ///< T1 per lesson (empty: the prior's)
  size_t lessons() const { return std::max(vxMax.size(), amplitudeMax.size()); }
  std::vector<double> stride;         ///< stride gain per lesson (empty: the prior's)
  double advanceAt = 1.0;             ///< average episode score (SkillEnv::curriculumScore) that moves to the next lesson
};

/// A ball placed in front of the robot at every episode start (kick): offset from the pelvis in the heading
/// frame (x forward, y left), plus a uniform jitter; the target direction is the heading at the start.
struct BallTaskDef {
  bool enabled = false;
  double x = 0.3, y = -0.12;  ///< [m]
  double jitter = 0.03;       ///< +- [m] on x and y
  /// Probability that a training episode has no ball (aux0/aux1 stay 0, as in play on a level without one), so
  /// that the skill also learns to stay up after a kick at nothing; cards always place the ball.
  double absent = 0.0;
};

/// A skill's report card (success criteria), measured by `treelearn eval SKILL`. A bar < 0 is not checked.
struct CardDef {
  /// Velocity: tracking of vx / vy / wz commands (walk, run); Height: tracking of the pelvis height that the
  /// amplitude command asks for (squat). Both run randomised episodes on flat ground the same way.
  /// Balance: the right foot lifted (amplitude 1 held), success = lifted >= lift_height for lift_s without a fall.
  /// Stairs: up and down the skill's staircase at step_height; success = past its far end without a fall.
  /// Jump: success = `jumps` flights in a row (both feet off the ground), each with the pelvis apex at least
  /// jump_height above its height at the start, and no fall.
  /// Kick: success = the ball leaves at >= kick_speed within kick_angle of the target direction and the robot
  /// is still up at the end of the episode.
  /// Prone: from standing, success = the torso link below prone_height with the forward pitch within
  /// prone_pitch_deg, reached within prone_s and still so at the end of the episode, without a fall; the peak
  /// pelvis acceleration (the impact) is reported.
  /// StandUp: each episode starts standing under the parent skill's model (prone), which lies down for lie_s;
  /// then the switch to this skill as the runtime makes it; success = standing (robot::hasStoodUp: pelvis >= 0.70 m,
  /// tilt < 10 deg) within rise_s of the switch, then the `up` skill (walk) taking over there and after_s with no fall.
  /// PushUp: each episode lies down under the parent (as StandUp), then the skill runs episode_s; success = at
  /// least push_ups rises of the torso link's origin by >= rise (trough to crest) and no fall.
  /// Crawl: each episode lies down under the parent, then a tunnel (the skill's ceiling terrain, `width` wide) is
  /// put over the robot along its heading and the skill crawls at the vx command; success = crawl_distance along
  /// the tunnel at a mean speed of at least crawl_speed, inside the tunnel and without a fall.
  enum class Kind { None, Velocity, Height, Balance, Stairs, Jump, Kick, Prone, StandUp, PushUp, Crawl } kind = Kind::None;
  int episodes = 50;            ///< randomised episodes (friction, mass, pushes as in training)
  double episodeSeconds = 20;   ///< each episode's length
  double segmentSeconds = 5;    ///< a new command this often
  double settleSeconds = 1;     ///< tracking is not counted this long after a command change
  Range vx, vy, wz;             ///< command ranges
  Range amplitude;              ///< amplitude command range (drawn with every command)
  std::array<double, 4> mix{0.4, 0.2, 0.2, 0.2};  ///< chance of a forward, sideways, turn or zero command
  bool pushes = true;           ///< pushes as in the skill's randomisation
  /// the card's own push strength [m/s] (lo < 0: the randomisation's), so that training can push harder
  /// without changing the card
  Range pushSpeed{-1, -1};
  /// the card's own push interval [s] (< 0: the randomisation's), likewise
  double pushEverySeconds = -1;
  bool ramp = false;            ///< commands ramp at the keyboard's rates (see CommandDef::ramp)
  int standEpisodes = 0;        ///< zero-command episodes without pushes (drift)
  double standSeconds = 10;
  double noFallPercent = -1;    ///< bar: episodes without a fall [%] (>=)
  double successPercent = -1;   ///< bar (Balance): episodes that succeed [%] (>=)
  double speedError = -1;       ///< bar: mean |v - v_cmd| [m/s] (<=)
  double yawError = -1;         ///< bar: mean |wz - wz_cmd| [rad/s] (<=)
  double heightError = -1;      ///< bar: mean |h - h_target(amplitude)| of the pelvis [m] (<=)
  double liftHeight = 0.08;     ///< Balance: the right sole counts as lifted at this height [m], the right foot off the ground and the left on it ...
  double liftSeconds = 5;       ///< ... and an episode succeeds when it stays lifted this long in one go
  double stepHeight = 0.15;     ///< Stairs: the staircase's step height [m]
  double jumpHeight = 0.10;     ///< Jump: apex above the starting pelvis height [m] ...
  int jumps = 3;                ///< ... for this many jumps in a row
  double kickSpeed = 2.5;       ///< Kick: ball speed [m/s] ...
  double kickAngleDegrees = 15; ///< ... within this angle of the target direction
  double standDrift = -1;       ///< bar: max drift of a standing episode [m] (<)
  double proneSeconds = 3;      ///< Prone: lying within this time [s] ...
  double proneHeight = 0.35;    ///< ... with the torso link's origin below this [m] ...
  Range pronePitch{70, 110};    ///< ... and the forward pitch in this range [deg]
  Range lieSeconds{3.0, 5.5};   ///< StandUp: the parent lies down this long (drawn per episode) [s] ...
  double riseSeconds = 5;       ///< ... the skill stands within this time of the switch [s] ...
  double afterSeconds = 3;      ///< ... and the up skill then runs this long without a fall [s]
  int pushUps = 3;              ///< PushUp: this many push-ups within episode_s ...
  double pushUpRise = 0.08;     ///< ... each a rise of the torso link's origin this high, trough to crest [m]
  double crawlDistance = 5.0;   ///< Crawl: this far along the tunnel [m] ...
  double crawlSpeed = 0.25;     ///< ... at this mean speed at least [m/s]
  /// Crawl: the card steers as a player would (0 = never): a yaw-rate command of -steer x (heading off the tunnel's
  /// axis [rad] + 0.5 x offset across it [m]), that error averaged over the last second (the gait's rock swings the
  /// heading within each cycle), within the skill's wz range [rad/s per rad]
  /// Stairs: the card keeps the robot square to the staircase as a player would, with play's heading-hold law
  /// (robot::shapeCommand): wz = -steer x the heading off +X [rad], at most kHeadingMaxRate and the wz range.
  double steer = 0.0;
  /// Velocity-type cards (kick, ...): each episode starts as the skill's training handover episodes do (from
  /// training.handover_from or the parent, through the skills in between, handover_s / handover_via_s /
  /// handover_vx), that is as play enters the skill, rather than from the spawn stance; a lead-in that falls
  /// is drawn again (up to 5 times, then the episode counts as a fall)
  bool leadIn = false;
};

/// One skill of the tree.
struct SkillDef {
  std::string name;
  std::string parent;  ///< "" for the root
  /// The skill a request further up the tree switches to first, when that is not the parent: prone (lying)
  /// cannot switch back to walk, so its way up is standup, and standup's way up is walk. "" = the parent.
  std::string up;
  int key = -1;        ///< 0..9; -1: none (a skill reached only by routing through it, as another's `up`)
  /// A switch into this skill from one with a phase prior waits until that skill's gait phase, as a fraction of
  /// its cycle (tp / 2 T1), is within this range (at most one cycle: robot::phaseAllowsSwitch). [0, 1]: any phase.
  Range switchInPhase{0.0, 1.0};
  /// A still skill that stands on one foot (one_leg): a switch into it waits until the robot has stopped drifting
  /// (robot::kSettleDrift) and is at rest on both feet, up to kMaxSettleWaitTicks instead of kMaxRestWaitTicks
  /// (robot::readyForSwitch, robot::maxSwitchWaitTicks)
  bool settleFirst = false;
  std::string model;   ///< ONNX file name inside assets/skills/
  PriorDef prior;
  JointArray kp{}, kd{};           ///< PD gains per joint
  JointArray actionScale{};        ///< rad per policy unit, per joint
  double actionFilter = 0.0;       ///< low-pass on the policy output: u = f u + (1 - f) a (0 = none)
  CommandDef commands;
  std::map<std::string, double> rewardWeights;  ///< term name -> weight
  std::map<std::string, int> rewardLines;       ///< term name -> line in the file (for errors)
  TerminationDef termination;
  RandomisationDef randomisation;
  int64_t trainingSteps = 10000000;
  int trainingEnvs = 20;
  bool onlyPositiveRewards = true;  ///< clip each step's total reward at 0 (falling early never pays)
  /// handover episodes: this fraction of training episodes starts with the parent skill's policy driving for
  /// handoverSeconds (a random command from the parent's ranges) and then switching to this skill the way the
  /// runtime does (from rest for a still skill, with the prior fade), so the skill learns the states it is
  /// switched into
  double handover = 0;
  Range handoverSeconds{1.0, 3.0};
  /// the ancestor whose policy drives a handover episode (default: the parent): the kick from the walk, as the
  /// autopilot hands it over in play. The episode then routes as play does: each skill between handover_from and
  /// this one (walk -> one_leg -> kick: the one-leg stand) takes over in turn and runs handoverViaSeconds at a
  /// zero command before the next switch (0: on as soon as the switch is allowed, as a routed key request)
  std::string handoverFrom;
  Range handoverViaSeconds{0.0, 0.0};
  /// the parent's drive in a handover episode: forward at a speed drawn from this range (W held, as before the
  /// run's key in play); {0, 0}: one random draw from the parent's command ranges
  Range handoverVx{0.0, 0.0};
  /// handover episodes from a child, the way back up the tree (jump -> squat in play): this fraction of training
  /// episodes starts with the child `handoverBackFrom`'s policy driving from the spawn stance (after the standing
  /// controller's kMinHopTicks, as play enters a key-pose skill) for handoverBackSeconds at a zero command, then
  /// switching to this skill as the runtime does (out of a key-pose skill: once the robot stands settled)
  /// [training] line_jitter = [rad, m], with [commands] line_command: each episode's line is turned by U(-rad, rad)
  /// about where the skill starts and moved across by U(-m, m), so that it starts off its line (0: on it)
  double lineJitterHeading = 0, lineJitterOffset = 0;
  /// [training] line_steer = k: training episodes are steered back toward the line the skill began on as the crawl
  /// card's `steer` steers (a player's steering): each tick wz = -k x (heading off the line + 0.5 rad/m x offset
  /// across it), the error averaged over about a second, within the skill's wz range (which must straddle 0).
  /// The steered yaw rate does not turn the line (heading_hold and crawl_line keep the episode's own). 0: off.
  double lineSteer = 0;
  /// [training] heading_steer = k: training episodes are steered square to the world's +X (the staircase's way,
  /// which the stairs card steers along) as play's heading hold steers: each tick wz = -k x the yaw off +X, within
  /// robot::headingHoldLimit (kHeadingMaxRate and the skill's wz range, which must straddle 0). The drawn wz is
  /// replaced, so training walks the stairs as the card and a player do, not turned by random draws. 0: off.
  double headingSteer = 0;
  /// [training] heading_steer_share = p: the share of training episodes that heading_steer steers (drawn per episode;
  /// the rest keep their drawn turns, so the skill learns to walk the stairs squared up and to recover from a turn
  /// as well). 1: every episode (the default).
  double headingSteerShare = 1.0;
  double handoverBack = 0;
  std::string handoverBackFrom;
  Range handoverBackSeconds{1.0, 3.0};
  CardDef card;
  TerrainDef terrain;
  CurriculumDef curriculum;
  BallTaskDef ball;
  int line = 0;  ///< where it is defined
};

struct SkillTree {
  std::string path;
  std::string directory;
  std::vector<SkillDef> skills;
  /// The raw [ppo] table as TOML text (parsed by ai::loadPpoConfig) and its line.
  std::string ppoToml;

  /// The skill with this name, or nullptr.
  const SkillDef* find(const std::string& name) const;
};

/// Loads and validates the tree. Joint groups in [gains]/[action_scale] are matched against the model's joint names.
SkillTree loadSkillTree(const std::string& path, const RobotModel& model);

/// The tree file the apps use: assets/skills/tree.toml, unless setSkillTreePath chose another.
std::string defaultSkillTreePath();

/// Makes defaultSkillTreePath() return path (e.g. an experiment's copy of the tree; "" = back to the default).
void setSkillTreePath(const std::string& path);

/// Joint-group names usable in the tree file (hip_pitch, knee, ..., wrist_roll) and whether joint j belongs.
bool jointInGroup(const std::string& jointName, const std::string& group);

}  // namespace robot
