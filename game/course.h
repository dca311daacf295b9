// course.h — the rules and entities of a game level (a level with [rules]; also a map's coins and balls): coins,
// question boxes and what
// they release, ghosts, balls, goals, checkpoints, the time limit, score, and winning or losing. The Session
// owns one and calls it once per tick after physics; it never moves the robot itself (a respawn is the
// Session's, on the Course's word).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/hash.h"
#include "engine/physics/physics_world.h"
#include "engine/plane/plane_world.h"
#include "engine/render/scene_snapshot.h"
#include "levels/level.h"
#include "robot/robot.h"

namespace game {

/// A sphere standing in for a part of the robot (collider centres), for touching coins and boxes.
struct BodyPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double radius = 0;
  bool head = false, hand = false;  ///< can hit a question box
};

enum class Outcome { Playing, Won, Lost };

/// What kind of thing happened on the course.
/// RespawnLoop: the robot fell kRespawnLoopFalls times within kRespawnLoopSeconds back to one checkpoint, and the run
/// is lost (a Lost event follows it).
enum class CourseEventKind { Won, Lost, Checkpoint, BoxHit, Collected, GhostAppears, GhostGivesUp, Fell, RespawnLoop };

/// A respawn loop ends the run: the kRespawnLoopFalls-th fall back to the same checkpoint within kRespawnLoopSeconds
/// of the first of them loses the level instead of putting the robot back once more. A robot that cannot stand
/// where it is put back falls again within a second or so (levels/mario, with a checkpoint under the tunnel's exit,
/// fell there every 0.55 s, 390 times in one run); a real retry of a stage (walk up to it, try it) takes longer
/// than kRespawnLoopSeconds / kRespawnLoopFalls = 2 s per fall.
constexpr int kRespawnLoopFalls = 5;
constexpr double kRespawnLoopSeconds = 10.0;

/// Something that happened: its kind (for code that reacts to it) and its text (for the summary and the log).
struct CourseEvent {
  int64_t tick = 0;
  CourseEventKind kind = CourseEventKind::Checkpoint;
  std::string what;
};

class Course {
 public:
  Course(const levels::Level& level, engine::PhysicsWorld& physics, engine::PlaneWorld& plane);

  /// Advances the rules by one tick (after physics): ghosts move, coins and releases are collected, boxes are
  /// hit, goals and the time limit are checked.
  void update(int64_t tick, const robot::Sensors& sensors, const std::vector<BodyPoint>& body,
              engine::PhysicsWorld& physics, engine::PlaneWorld& plane);

  /// The robot fell at `tick`: under "respawn" the penalty is taken and true is returned (the Session puts the
  /// robot back at respawnX()), unless it is a respawn loop (kRespawnLoopFalls), which loses the level; under
  /// "lose" the level is lost. Both return false.
  bool onFall(int64_t tick);
  double respawnX() const { return checkpointX_; }

  Outcome outcome() const { return outcome_; }
  const std::string& outcomeReason() const { return reason_; }
  int score() const { return score_; }
  int coins() const { return coins_; }
  int gifts() const { return gifts_; }
  int falls() const { return falls_; }
  /// Distance from the nearest awake ghost's edge to the pelvis [m]; negative when no ghost is chasing.
  double ghostDistance() const { return ghostDistance_; }
  /// Ball id of the level's first ball, -1 if none (the kick's target).
  engine::BallId firstBall() const { return balls_.empty() ? -1 : balls_.front().id; }
  /// The level's balls' ids, in level order.
  std::vector<engine::BallId> ballIds() const {
    std::vector<engine::BallId> ids;
    for (const Ball& b : balls_) ids.push_back(b.id);
    return ids;
  }
  const std::vector<CourseEvent>& events() const { return events_; }

  /// Adds the course's moving and collectable things to a snapshot (static boxes are drawn by the Session).
  void draw(const engine::PhysicsWorld& physics, const engine::PlaneWorld& plane, engine::SceneSnapshot* out) const;
  /// Feeds everything that evolves into a state hash.
  void hash(const engine::PhysicsWorld& physics, const engine::PlaneWorld& plane, engine::Hasher* h) const;

 private:
  struct Collectable {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    double radius = 0.15;
    bool gift = false, collected = false;
    int64_t releasedTick = -1;  // released by a question box at this tick (-1: placed in the level)
    Eigen::Vector3d from = Eigen::Vector3d::Zero();  // where a release starts
  };
  struct Box {
    levels::QuestionBoxDef def;
    bool used = false;
  };
  struct Ghost {
    levels::GhostDef def;
    int body = -1;  // PlaneWorld kinematic circle, once awake
    bool awake = false, gone = false;
    double speed = 0;
    bool park = false;  // put to sleep by a fall: move the body out of the way at the next update
  };
  struct Ball {
    engine::BallId id = -1;
    double radius = 0.11;
    int mirror = -1;  // its kinematic circle in a top plane's 2D layer (-1: none)
  };

  void finish(int64_t tick, Outcome outcome, const std::string& reason);
  void log(int64_t tick, CourseEventKind kind, const std::string& what) { events_.push_back({tick, kind, what}); }

  levels::RulesDef rules_;
  double timeLimit_ = 0;
  std::vector<Collectable> items_;
  std::vector<Box> boxes_;
  std::vector<Ghost> ghosts_;
  std::vector<Ball> balls_;
  std::vector<levels::GoalDef> goals_;
  double checkpointX_ = 0;
  std::vector<int64_t> fallsHere_;  // ticks of the falls back to checkpointX_ (the latest kRespawnLoopFalls)
  Outcome outcome_ = Outcome::Playing;
  std::string reason_;
  int score_ = 0, coins_ = 0, gifts_ = 0, falls_ = 0;
  double ghostDistance_ = -1;
  std::vector<CourseEvent> events_;
};

}  // namespace game
