// session.h — one play-through of a level: the ECS registry, the 3D and 2D worlds, the robot, the
// command input and the rules, advanced one fixed control tick at a time by step(). The tick is a
// pipeline of systems: input -> control -> physics -> rules -> telemetry (render reads snapshot()).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "engine/ecs/registry.h"
#include "engine/input/command.h"
#include "engine/physics/physics_world.h"
#include "engine/plane/plane_world.h"
#include "engine/render/scene_snapshot.h"
#include "game/course.h"
#include "game/skill_set.h"
#include "levels/level.h"
#include "robot/robot.h"
#include "robot/skill_controller.h"

namespace game {

/// Physics substeps per control tick and their length: 5 x 0.002 s = 0.01 s (DESIGN.md §3).
constexpr int kSubsteps = 5;
constexpr double kSubstepSeconds = 0.002;

/// The fall rule: the robot has fallen when the pelvis is lower than this [m] ... (while a ground skill such as
/// prone is active, its own termination decides instead: robot::hasFallen) ...
constexpr double kFallPelvisHeight = 0.45;
/// ... or the pelvis is tilted more than this from upright [rad] (about 46 degrees).
constexpr double kFallTilt = 0.8;

/// ... or it has been stuck this many ticks in an upright skill tilted more than kSwitchMaxTilt or with the pelvis
/// below kStuckPelvisHeight [m] (no switch can take it out of there).
constexpr int kStuckTicks = 300;
/// A stand-up (a ground skill whose way up is an upright skill) with the pelvis still below kStuckPelvisHeight this
/// long after it took over counts as down: it slumped back and holds its last pose, and no key can take a lying
/// robot anywhere but up (levels/mario's autopilot lay 190 s so; the stand-up's card rises within 5 s).
constexpr int kStandUpTicks = 1000;
constexpr double kStuckPelvisHeight = 0.5;
/// A routed switch waits until the robot is tilted less than this [rad] ...
constexpr double kSwitchMaxTilt = 0.35;
/// ... and an intermediate skill of a route has run at least this many ticks.
constexpr int kMinHopTicks = 50;
// the switch fade and the rest rule for still skills: robot/skill_controller.h (kSwitchFadeTicks, kRestSpeed)
using robot::kSwitchFadeTicks;
/// Heading hold while moving without a turn key (Session::holdHeading): turn rate per radian of heading error
/// [1/s] and its cap [rad/s] (the walk trained with one of vx / vy / wz at a time; at 0.3 the walk swung 0.4 rad)
constexpr double kHeadingGain = 2.0;
constexpr double kHeadingMaxRate = 0.2;
/// The heading hold's turn-rate cap for a skill: kHeadingMaxRate within its wz range (also the stairs card's steer).
inline double headingHoldLimit(const robot::CommandDef& range) { return std::min({kHeadingMaxRate, range.wz.hi, -range.wz.lo}); }
/// The yaw rate that squares a robot up to the world's +X (the staircase's way) with the heading hold's law:
/// -gain x the yaw off +X (wrapped to [-pi, pi]), within headingHoldLimit(range). The stairs card's `steer` and
/// training's `heading_steer`.
inline double squareToPlusX(double yaw, double gain, const robot::CommandDef& range) {
  const double limit = headingHoldLimit(range);
  return std::clamp(-gain * std::remainder(yaw, 2.0 * M_PI), -limit, limit);
}

struct SessionOptions {
  uint64_t seed = 1;                ///< drives every random choice (today: the initial joint jitter)
  const SkillSet* skills = nullptr;  ///< learned skills (keys 0-9); without them the standing controller runs
};

/// One skill switch.
struct SwitchEvent {
  int64_t tick = 0;  ///< the tick whose control step the new skill made
  std::string from, to;
  bool respawn = false;  ///< the root taking a respawned robot, not a switch in motion
};

/// "stairs 2, jump 1": falls by skill, the most first (names alphabetical among equals; "" reads "no skill").
std::string fallsBySkillText(const std::map<std::string, int>& falls);

/// Running statistics for the summary.
struct Telemetry {
  std::vector<SwitchEvent> switches;
  double minPelvisHeight = 1e9, maxPelvisHeight = 0;
  double sumPelvisHeight = 0;
  double maxTilt = 0;
  double distance = 0;  ///< horizontal path length of the pelvis [m]
  int falls = 0;        ///< times the robot went down (a game level may put it back up)
  std::map<std::string, int> fallsBySkill;  ///< the same, by the skill in control when it went down ("" = none)
  std::vector<int64_t> respawns;  ///< ticks the robot was put back at a checkpoint (a teleport)
  int64_t ticks = 0;
  std::set<int> skillsRequested;
  std::set<std::string> skillsUsed;
};

class Session {
 public:
  Session(const levels::Level& level, const robot::RobotModel& model, const SessionOptions& options);

  /// Advances one control tick (0.01 s) after applying this tick's key events.
  void step(const std::vector<engine::KeyEvent>& events);

  int64_t tick() const { return tick_; }
  double seconds() const;
  bool fallen() const { return fallen_; }
  int64_t fallTick() const { return fallTick_; }

  /// Hash of everything that evolves: physics state, tick, command state.
  uint64_t stateHash() const;

  /// What the renderer should draw now; hud is left for the caller to fill.
  engine::SceneSnapshot snapshot(engine::CameraMode camera) const;

  /// The HUD text: time, skill, keys held and the command; on a game level a second line with score, coins and
  /// the ghost's distance.
  std::string hudLine() const;

  /// Name of the skill driving the robot ("stand" for the standing controller).
  std::string activeSkillName() const;

  const robot::Sensors& sensors() const { return sensors_; }
  const engine::CommandState& command() const { return input_.state(); }
  const Telemetry& telemetry() const { return telemetry_; }
  const engine::PlaneWorld& plane() const { return plane_; }
  const engine::PhysicsWorld& physics() const { return physics_; }
  const levels::Level& level() const { return level_; }
  const robot::Robot& robot() const { return *robot_; }
  /// True if skill key 0-9 has a loaded model (a key without one leaves the robot to the standing controller).
  bool hasSkill(int key) const { return skills_ && skills_->byKey(key) != nullptr; }
  /// The game rules of a game level (nullptr for other levels).
  const Course* course() const { return course_.get(); }
  /// Playing, or won / lost (game levels only).
  Outcome outcome() const { return course_ ? course_->outcome() : Outcome::Playing; }
  /// The robot as spheres (collider centres), world frame.
  std::vector<BodyPoint> bodyPoints() const;

 private:
  void inputSystem(const std::vector<engine::KeyEvent>& events);
  void controlSystem();
  void physicsSystem();
  void rulesSystem();
  void telemetrySystem();
  void switchTo(const SkillRuntime* next);
  void holdHeading(robot::SkillCommand* command);
  void steerToLine(bool moving, robot::SkillCommand* command);
  /// The skill's own line from where the robot is, the way it faces (groundHeading), its averaged error zeroed.
  void restartSkillLine();
  void respawn(double x);
  /// The default pose with every joint jittered by kInitialJitter from the seed's generator (the start, a respawn).
  robot::JointArray jitteredStandingPose();

  const levels::Level& level_;
  const robot::RobotModel& model_;
  std::mt19937_64 rng_;
  engine::Registry registry_;
  engine::PhysicsWorld physics_;
  engine::PlaneWorld plane_;
  std::unique_ptr<robot::Robot> robot_;
  engine::CommandInput input_;
  robot::Sensors sensors_;
  Telemetry telemetry_;
  const SkillSet* skills_ = nullptr;
  const SkillRuntime* active_ = nullptr;  // nullptr: standing controller
  int64_t activeSince_ = 0;               // tick of the latest switch
  const SkillRuntime* fadingFrom_ = nullptr;  // the previous skill, whose prior is fading out
  int fadeTicks_ = 0;                     // ticks of that fade left
  robot::PhaseClock fadePhase_;           // the previous skill's clock, going on under its prior during the fade
  int restWaitTicks_ = -1;                // ticks a waiting switch has waited (-1: none waiting; robot::switchWaits)
  int postureWaitTicks_ = 0;              // ticks the requested switch (or its next hop) has waited on the posture
  robot::SkillCommand brake_;             // the velocity command ramping to rest or the next skill's top meanwhile
  robot::SkillCommand brakeTarget_;       // where brake_ ramps to (robot::switchBrakeTarget)
  std::array<float, robot::kActionSize> action_{};
  robot::PhaseClock phase_;
  Eigen::MatrixXf observation_, policyOutput_;
  std::unique_ptr<Course> course_;
  int64_t tick_ = 0;
  bool fallen_ = false, down_ = false;
  int64_t fallTick_ = -1;
  int stuckTicks_ = 0;     // ticks slumped in an upright skill (kStuckTicks)
  Eigen::Vector2d drift_ = Eigen::Vector2d::Zero();  // the pelvis's low-passed velocity (robot::updateDrift)
  double headingRef_ = 0;  // the heading W holds (holdHeading) ...
  Eigen::Vector2d lineStart_ = Eigen::Vector2d::Zero();  // ... and a point of the line it keeps to
  // a skill's own line (the observed line of [commands] line_command, the line [training] line_steer steers to): where
  // it took over, the way it faced then
  Eigen::Vector2d skillLineStart_ = Eigen::Vector2d::Zero(), skillLineAlong_ = Eigen::Vector2d::UnitX();
  double lineSteerError_ = 0;  // a ground skill's line error, averaged as its line_steer averages it (steerToLine)
};

}  // namespace game
