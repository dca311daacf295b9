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
#include "levels/level.h"
#include "robot/entry_state.h"
#include "robot/robot.h"
#include "robot/skill_runtime.h"

namespace game {

/// The fall rule: the robot has fallen when the pelvis is lower than this [m] ... (while a ground skill such as
/// prone is active, its own termination decides instead: robot::hasFallen) ...
constexpr double kFallPelvisHeight = 0.45;
/// ... or the pelvis is tilted more than this from upright [rad] (about 46 degrees).
constexpr double kFallTilt = 0.8;

/// ... or it has been stuck this many ticks in an upright skill tilted more than robot::kSwitchMaxTilt or with the
/// pelvis below kStuckPelvisHeight [m] (no switch can take it out of there).
constexpr int kStuckTicks = 300;
/// A stand-up (a ground skill whose way up is an upright skill) with the pelvis still below kStuckPelvisHeight this
/// long after it took over counts as down: it slumped back and holds its last pose, and no key can take a lying
/// robot anywhere but up (levels/mario's autopilot lay 190 s so; the stand-up's card rises within 5 s).
constexpr int kStandUpTicks = 1000;
constexpr double kStuckPelvisHeight = 0.5;

struct SessionOptions {
  uint64_t seed = 1;                        ///< drives every random choice (today: the initial joint jitter)
  const robot::SkillSet* skills = nullptr;  ///< learned skills (keys 0-9); without them the standing controller runs
};

/// A tunnel in sight in a side layer (plane = side: world x, z): its roof over the pelvis (0.3-1.0 m above the feet),
/// or ahead within kTunnelSight the way the robot faces along the course (something 0.7 m up with open space at
/// 0.3 m under it). Then *along is the tunnel's axis as the side layer sees it: the course's direction (+X or -X, the
/// way the robot's ground heading points), and the result is true.
constexpr double kTunnelSight = 3.0;  ///< [m]
bool tunnelAxisInSight(const engine::PlaneWorld& plane, const robot::Sensors& sensors, Eigen::Vector2d* along);

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
  double distance = 0;                      ///< horizontal path length of the pelvis [m]
  int falls = 0;                            ///< times the robot went down (a game level may put it back up)
  std::map<std::string, int> fallsBySkill;  ///< the same, by the skill in control when it went down ("" = none)
  std::vector<int64_t> respawns;            ///< ticks the robot was put back at a checkpoint (a teleport)
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
  /// The learned skills (nullptr: none, the standing controller).
  const robot::SkillSet* skills() const { return skills_; }
  /// The runtime's state (the active skill, its clock, a waiting switch).
  const robot::SkillState& runtime() const { return runtime_; }
  /// This tick's state as a play-entry state (robot/entry_state.h): the robot, the balls, the runtime and the keys;
  /// the caller fills the rest (level, source, seed, the segment and its events). Needs an active skill.
  robot::EntryState captureEntry() const;
  /// Continues from a play-entry state recorded on this session's level: the robot, the balls, the runtime (its
  /// skills looked up by name in the loaded set) and the keys as the entry left them, the session's clock at the tick
  /// after the entry's. Throws engine::Error if no skills are loaded or the entry's skill is not among them, or the
  /// entry holds another number of balls than the level.
  void restoreEntry(const robot::EntryState& entry);
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
  /// Telemetry and the keys' ranges after the runtime switched to `next` (a respawn's too).
  void onSwitch(const robot::Skill* from, const robot::Skill& next);
  void respawn(double x);
  /// A line-keeping skill just took over: its line along a tunnel's axis when one is in sight (session.cpp).
  void keepToTunnelAxis();
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
  const robot::SkillSet* skills_ = nullptr;
  robot::SkillState runtime_;  // the skill runtime's state: active skill (nullptr: standing controller), clocks, waits
  std::unique_ptr<Course> course_;
  int64_t tick_ = 0;
  bool fallen_ = false, down_ = false;
  int64_t fallTick_ = -1;
  int stuckTicks_ = 0;  // ticks slumped in an upright skill (kStuckTicks)
};

}  // namespace game
