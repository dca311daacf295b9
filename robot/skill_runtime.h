// skill_runtime.h — the one skill runtime: the control step and the switches between skills, which play
// (game::Session), training episodes and their handovers (ai/env), every report card and `eval switches` all run.
//
// MuJoCo's model/data split applied to skills: a const part (SkillSet: the tree's skills with their loaded
// policies, and its routing) and a mutable part per robot (SkillState: the active skill, its clock, the prior fading
// out after a switch, the filtered action, the switch waiting for its moment, and the lines a skill keeps to).
//
//   request (a wanted skill, the keys' command) --route()--> a switch now, or a wait (brake, posture, phase)
//   command (keys or drawn) --shapeCommand()--> what the active skill is commanded (heading hold, line steer, brake)
//   sensors + command --observe()--> observation --policy--> output --act()--> PD joint targets
//
// controlStep() is observe + policy + act for one robot; batched callers (training, cards) call observe() for every
// robot, run the policy once on the batch, then act() for every robot: the same step, split at the policy.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "engine/physics/physics_world.h"
#include "robot/robot.h"
#include "robot/skill_controller.h"
#include "robot/skill_layout.h"
#include "robot/skill_tree.h"

namespace robot {

// --- the control tick ----------------------------------------------------------------------------------------

/// Physics substeps per control tick and their length: 5 x 0.002 s = 0.01 s (DESIGN.md §3).
constexpr int kSubsteps = 5;
constexpr double kSubstepSeconds = 0.002;

/// One control tick of physics for one robot: kSubsteps substeps, the PD torques recomputed before each.
void stepPhysicsTick(Robot& robot, engine::PhysicsWorld& world);

// --- the const part --------------------------------------------------------------------------------------------

/// A deterministic policy: observations (kObservationSize x batch) -> actions (kActionSize x batch). Called from
/// worker threads by the batched callers: it must be thread-safe.
using Policy = std::function<void(const Eigen::MatrixXf& observations, Eigen::MatrixXf* actions)>;

/// A skill of the tree with its loaded policy (empty for a skill whose policy runs outside: training's trainee).
struct Skill {
  SkillDef def;
  Policy policy;
};

/// A skill of the tree whose model file is not there (not trained yet): its key does nothing in play.
struct MissingSkill {
  std::string name;
  int key = -1;
  std::string path;
};

/// The learned skills a runtime can run, loaded once (apps/ builds the policies from ONNX files with ai/).
struct SkillSet {
  std::vector<Skill> skills;
  std::vector<MissingSkill> missing;  ///< the tree's skills without a model file, in tree order
  uint64_t hash = 0;                  ///< content hash of the tree file and every loaded model (0 = no skills)

  /// The skill bound to a key (0-9), or nullptr.
  const Skill* byKey(int key) const;
  /// The loaded skill with this name, or nullptr.
  const Skill* byName(const std::string& name) const;
  /// The root skill (the one without a parent), or nullptr.
  const Skill* root() const;
  /// The key that requests s: its own, or for a keyless skill (the stand-up) the key of the first skill up from
  /// it that has one (walk's 0: from lying, the request routes through the stand-up). -1 if none.
  int requestKey(const Skill& s) const;
  /// The skill a switch up the tree goes to from s: its `up` skill when the tree names one (prone -> standup),
  /// else its parent; nullptr at the root or when that skill has no loaded model.
  const Skill* upFrom(const Skill& s) const;
  /// The first switch on the way from `from` to `to`: up from `from` (parent by parent, or by a skill's `up`)
  /// until reaching `to` or one of its ancestors, then down along the tree's edges toward `to`. `to` itself
  /// when it is one step away, nullptr when from == to or when a skill on the way has no loaded model.
  const Skill* nextHop(const Skill& from, const Skill& to) const;
};

// --- the mutable part ------------------------------------------------------------------------------------------

/// Everything of the runtime that changes while one robot runs its skills.
struct SkillState {
  const Skill* active = nullptr;            ///< nullptr: the standing controller holds the default pose
  PhaseClock phase;                         ///< the active skill's clock
  std::array<float, kActionSize> action{};  ///< the filtered action (the observation's previous action)
  const Skill* fadingFrom = nullptr;        ///< the skill before the latest switch, whose prior fades out ...
  PhaseClock fadePhase;                     ///< ... on its own clock ...
  int fadeTicks = 0;                        ///< ... for this many more ticks
  int64_t activeSince = 0;                  ///< the caller's tick of the latest switch
  int restWaitTicks = -1;                   ///< ticks a switch has braked, waiting (-1: none; robot::switchWaits)
  int postureWaitTicks = 0;  ///< ticks the requested switch (or its next hop) has waited on posture or phase
  SkillCommand brake;        ///< the velocity command ramping to rest or to the next skill's band meanwhile ...
  SkillCommand brakeTarget;  ///< ... and where it ramps to (robot::switchBrakeTarget)
  Eigen::Vector2d drift = Eigen::Vector2d::Zero();  ///< the pelvis's low-passed velocity (robot::updateDrift)
  /// the skill's own line: where it took over and the way it faced then ([commands] line_command observes it,
  /// [commands] line_steer steers back to it); the line error averaged as the steer averages it
  Eigen::Vector2d lineStart = Eigen::Vector2d::Zero(), lineAlong = Eigen::Vector2d::UnitX();
  double lineSteerError = 0;
  /// the heading hold of play's keys (shapeCommand): the heading W holds and a point of the line it keeps to
  double headingRef = 0;
  Eigen::Vector2d headingLineStart = Eigen::Vector2d::Zero();
};

// --- switching -------------------------------------------------------------------------------------------------

/// A routed switch waits until the robot is tilted less than this [rad] ...
constexpr double kSwitchMaxTilt = 0.35;
/// ... and an intermediate skill of a route has run at least this many ticks.
constexpr int kMinHopTicks = 50;

/// What asks for a switch this tick: the wanted skill (nullptr: none) and the keys' raw command, with the rates
/// at which the keys ramp it (a braking switch ramps at the same rates).
struct SwitchRequest {
  const Skill* wanted = nullptr;
  double vx = 0, vy = 0, wz = 0, amplitude = 0;
  double vRate = 0, wzRate = 0;
};

/// The pure part of routing: where the request goes next and whether the switch may happen now as far as the tree,
/// the posture, the gait cycle and the phase go (the brake, which has state, comes after it in route()).
struct SwitchGate {
  const Skill* next = nullptr;  ///< the next hop toward the wanted skill (nullptr: none wanted, or no way there)
  bool ready = false;           ///< tree, posture, tilt, hop time and key-pose cycle allow it
  bool inPhase = false;         ///< the gait phase allows it (robot::phaseAllowsSwitch)
  bool lowerAmplitude = false;  ///< a squat's depth or a lift must come back to 0 first (it then waits)
  bool brakes = false;          ///< the active skill brakes first (robot::switchWaits)
};
SwitchGate switchGate(const SkillSet& set, const SkillState& state, const Sensors& sensors,
                      const SwitchRequest& request, int64_t tick);

/// What route() did this tick.
struct RouteResult {
  const Skill* switchedTo = nullptr;  ///< the skill that took over this tick (nullptr: no switch)
  bool lowerAmplitude = false;        ///< the caller brings the amplitude command back toward 0
};

/// One tick of switching: a request for a skill that is not a parent or child of the active one is routed along
/// the tree one switch at a time, each once the robot is upright and the previous hop has run kMinHopTicks; into a
/// still skill or a slower one (run -> walk) the active skill first brakes (robot::switchWaits). A switch takes
/// effect in the tick it is made (enterSkill): the new network reads the same observation, the filtered action
/// carries over and the gait phase keeps its fraction of the cycle.
/// `tick`: the caller's control tick (hop times count in it).
RouteResult route(const SkillSet& set, SkillState* state, const Sensors& sensors, const SwitchRequest& request,
                  int64_t tick);

/// The switch itself: the old prior fades out on its own clock over kSwitchFadeTicks, the clock is carried over
/// (robot::carryPhase), the new skill's lines start where the robot is. From the standing controller the action
/// and the clock start from zero.
void enterSkill(SkillState* state, const Skill& next, const Sensors& sensors, int64_t tick);

/// The keys' command clamped into a skill's command ranges (and to 0 where a range excludes it).
SkillCommand commandWithin(double vx, double vy, double wz, const CommandDef& range);

/// Heading hold while moving without a turn key (shapeCommand): turn rate per radian of heading error [1/s] and
/// its cap [rad/s] (the walk trained with one of vx / vy / wz at a time; at 0.3 the walk swung 0.4 rad).
constexpr double kHeadingGain = 2.0;
constexpr double kHeadingMaxRate = 0.2;
/// The heading hold's turn-rate cap for a skill: kHeadingMaxRate within its wz range (also the stairs card's steer).
inline double headingHoldLimit(const CommandDef& range) {
  return std::min({kHeadingMaxRate, range.wz.hi, -range.wz.lo});
}
/// The yaw rate that squares a robot up to the world's +X (the staircase's way) with the heading hold's law:
/// -gain x the yaw off +X (wrapped to [-pi, pi]), within headingHoldLimit(range). The stairs card's `steer` and
/// training's `heading_steer`.
inline double squareToPlusX(double yaw, double gain, const CommandDef& range) {
  const double limit = headingHoldLimit(range);
  return std::clamp(-gain * std::remainder(yaw, 2.0 * M_PI), -limit, limit);
}

/// The active skill's command from the keys, as a player steers with them: clamped into its ranges, the heading held
/// while moving with no turn key (an upright skill keeps to the line and heading it started moving on; a ground skill
/// with line_steer steers back to its own line by its training's law), and while a switch brakes, the brake's command
/// instead of the keys' (ramped at the request's rates). Updates the state's heading hold and brake.
SkillCommand shapeCommand(SkillState* state, const Sensors& sensors, const SwitchRequest& keys);
/// While a switch brakes (state->restWaitTicks >= 0): the brake ramps one tick toward its target at the request's
/// rates and replaces the velocity part of *command. (shapeCommand does this last.)
void applyBrake(SkillState* state, const SwitchRequest& rates, SkillCommand* command);

// --- the control step ------------------------------------------------------------------------------------------

/// The command the active skill observes: `command` plus what its [commands] table asks to see in the aux slots
/// (its own line, the next step ahead in `world`). The ball is the caller's: it is in `command` already.
SkillCommand observedCommand(const SkillState& state, const Sensors& sensors, const engine::PhysicsWorld& world,
                             const SkillCommand& command);
/// The active skill's observation (nominal model: the default pose the policy was trained around).
void observe(const RobotModel& nominal, const SkillState& state, const Sensors& sensors,
             const engine::PhysicsWorld& world, const SkillCommand& command, float* out);
/// From the policy's output to PD targets for `model` (the robot as simulated): the action filtered, the clock
/// advanced (held in a key-pose cycle's closing stand while `waitsForStill`), the PD command of action + prior, the
/// previous skill's prior fading out.
void act(const RobotModel& model, SkillState* state, const float* policyOutput, const SkillCommand& command,
         bool waitsForStill, PdCommand* out);
/// observe + the active skill's policy + act, for one robot.
void controlStep(const RobotModel& nominal, const RobotModel& model, SkillState* state, const Sensors& sensors,
                 const engine::PhysicsWorld& world, const SkillCommand& command, bool waitsForStill, PdCommand* out);

/// True while a request waits for a still skill, or to leave a key-pose cycle (its clock holds in the closing stand).
bool waitsForStill(const SkillState& state, const Skill* wanted);

}  // namespace robot
