// training_tree.h — the skill tree as training and the cards read it: each skill as the runtime runs it
// (SkillSpec, parsed by robot::loadSkillTree) plus the tables only training and the cards read: [draws],
// [rewards], [randomisation], [training], [terrain], [curriculum], [ball] and [card]. Both loaders read the same tree
// file (assets/skills/tree.toml, documented in assets/skills/README.md); each checks the tables it owns.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "ai/tree/card_def.h"
#include "robot/robot_model.h"
#include "robot/skill_tree.h"

namespace ai {

/// How training draws a skill's commands within its [commands] ranges ([skill.NAME.draws]).
struct CommandDraws {
  double zeroProbability = 0.2;  ///< chance that a draw is all zero
  double resampleSeconds = 5.0;  ///< a new command every so often
  /// each interval is resampleSeconds x (1 + U(-jitter, jitter)): without it every change meets the gait at the
  /// same phase (5 s = 6.25 cycles of 0.8 s), and the policy never learns changes at the other phases
  double resampleJitter = 0.0;
  /// true: vx / vy / wz reach each new draw at the keyboard's rates with its one-axis interlock
  /// (engine::rampVelocityCommand), as they do in play; false: they jump to it
  bool ramp = false;
  /// > 0: each forward or sideways draw also turns at U(-steer, steer) rad/s, on top of the ramp's interlock and
  /// unramped, as play's heading hold turns the robot while W is held (robot::shapeCommand); 0: the interlock alone,
  /// so a skill never sees a turn while it moves
  double steer = 0.0;
  /// false: no turn in place (a wz draw), so a skill that must go straight (the stairs) trains on its forward draws
  /// and steer's turns while moving; wz stays the limit of play's heading hold and turn keys
  bool turnInPlace = true;
  double amplitudeZero = 0;  ///< chance that an amplitude draw is 0 instead (the skill at rest, as play enters it)
  /// the amplitude moves toward each new draw at this rate [1/s] (0 = at once); 1.0 is the R / F keys' rate
  double amplitudeRate = 0;
};

/// Episode randomisation ([skill.NAME.randomisation]; a branch without one inherits its parent's).
struct RandomisationDef {
  Range friction{1.0, 1.0};     ///< robot/ground friction coefficient
  Range addedMass{0.0, 0.0};    ///< added pelvis mass [kg]
  double pushEverySeconds = 0;  ///< 0 = no pushes
  Range pushSpeed{0.0, 0.0};    ///< horizontal velocity change of a push [m/s]
};

/// Terrain a skill trains on. Stairs (the level format's, levels::StairsDef): `steps` risers up along +X from
/// start_x, the last tread a landing top_depth deep, and as many risers down; the step height comes from the
/// curriculum's current lesson.
/// Ceiling: a low ceiling (a tunnel's roof) `height` above the ground, put over the robot once it lies down (a
/// ground skill's episodes start standing under the parent, and a standing robot does not fit under it): in
/// training a slab over the whole arena, on the card a tunnel `width` wide along the heading.
struct TerrainDef {
  enum class Kind { Flat, Stairs, Ceiling } kind = Kind::Flat;
  double ceilingHeight = 0.6;  ///< Ceiling: the underside's height above the ground [m]
  int steps = 10;
  double stepDepth = 0.30;      ///< tread [m]
  double startX = 1.0;          ///< flat run-up before the first step [m]
  double topDepth = 1.5;        ///< landing between up and down [m]
  double width = 4.0;           ///< across the robot's path [m]
  std::vector<double> lessons;  ///< step heights of the curriculum's lessons, in order [m]
  double advanceAt = 1.0;       ///< average episode score (SkillEnv::curriculumScore) that moves to the next lesson
  StairsDraw draw;              ///< stairs drawn anew for every episode (in place of lessons), when draw.drawn()
  double entryYaw = 0.2;        ///< stairs: an episode starts facing within +- this of square to them [rad]
  /// Stairs: the probability that a training episode starts on one of the staircase's treads (ai::stairsSpawn:
  /// up, on the landing or on the way down, facing +X) rather than before the first riser. A rollout is 10.24 s,
  /// so from the foot of the stairs no episode reaches the way down. Cards always start at the foot.
  double spawnAlong = 0.0;
};

/// A command curriculum: lesson i caps the forward command at vx_max[i] (run) or the amplitude command at
/// amplitude_max[i] (one-leg lift), and, where given, sets the gait's half period T1[i] and the stride prior's
/// gain stride[i]. The last lesson is the skill's own (the loader checks that they agree), so the shipped model runs
/// as it was last trained. Lessons advance as the terrain's do (advance_at); a skill has either terrain lessons or
/// a command curriculum.
struct CurriculumDef {
  std::vector<double> vxMax;         ///< [m/s], one per lesson (or empty)
  std::vector<double> amplitudeMax;  ///< one per lesson (or empty)
  std::vector<int> halfPeriodTicks;  ///< T1 per lesson (empty: the prior's)
  size_t lessons() const { return std::max(vxMax.size(), amplitudeMax.size()); }
  std::vector<double> stride;  ///< stride gain per lesson (empty: the prior's)
  double advanceAt = 1.0;      ///< average episode score (SkillEnv::curriculumScore) that moves to the next lesson
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

/// One skill as training and its card see it: the runtime's definition and the training-only tables.
struct SkillSpec : robot::SkillDef {
  CommandDraws draws;
  std::map<std::string, double> rewardWeights;  ///< term name -> weight
  std::map<std::string, int> rewardLines;       ///< term name -> line in the file (for errors)
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
  double handoverBack = 0;
  std::string handoverBackFrom;
  Range handoverBackSeconds{1.0, 3.0};
  /// line_jitter = [rad, m], with [commands] line_command: each episode's line is turned by U(-rad, rad) about where
  /// the skill starts and moved across by U(-m, m), so that it starts off its line (0: on it)
  double lineJitterHeading = 0, lineJitterOffset = 0;
  /// heading_steer = k: training episodes are steered square to the world's +X (the staircase's way, which the
  /// stairs card steers along) as play's heading hold steers: each tick wz = -k x the yaw off +X, within
  /// robot::headingHoldLimit (kHeadingMaxRate and the skill's wz range, which must straddle 0). The drawn wz is
  /// replaced, so training walks the stairs as the card and a player do, not turned by random draws. 0: off.
  double headingSteer = 0;
  /// heading_steer_share = p: the share of training episodes that heading_steer steers (drawn per episode; the rest
  /// keep their drawn turns, so the skill learns to walk the stairs squared up and to recover from a turn as well)
  double headingSteerShare = 1.0;
  /// play_entries = "FILE" (a file in the tree's folder, written by `treelearn entries record`) and play_share = p:
  /// this share of training episodes starts from one of play's handover states into the skill (robot/entry_state.h),
  /// drawn at random, on the level it was recorded on, with the segment's movement keys shaping the command as play
  /// does (robot::shapeCommand) until the segment ends plus kPlayEpisodeMarginSeconds; no pushes, no drawn commands.
  /// The handover (and handover_back) share is drawn among the other episodes.
  std::string playEntries;
  double playShare = 0;
  CardDef card;
  TerrainDef terrain;
  CurriculumDef curriculum;
  BallTaskDef ball;
};

/// The tree file as training reads it.
struct TrainingTree {
  std::string path;
  std::string directory;  ///< where the models are
  std::vector<SkillSpec> skills;

  /// The skill with this name, or nullptr.
  const SkillSpec* find(const std::string& name) const;
};

/// Loads the runtime's tree (robot::loadSkillTree) and the training tables of the same file, all validated with
/// file:line errors.
TrainingTree loadTrainingTree(const std::string& path, const robot::RobotModel& model);

}  // namespace ai
