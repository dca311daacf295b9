// navigator.h — the garden's navigation as one state machine a game autopilot calls every control tick: a target
// in, a command (vr, wr), the skill to move with and what happened (target reached, stuck, replanned) out.
// It knows the world only through the level's top-down 2D layer (engine::PlaneWorld): the map is built from it
// once, and movable bodies are seen in it while moving. No clock of its own: time is the sum of the step()s' dt,
// and the same inputs give the same outputs.
//
//   Idle ──setTarget──► Following ──within reachRadius of the path's end──► Idle (event reached)
//                        │  ▲   │ a movable body on the path ahead, off the path, or a new target: replan
//                        │  │   └─no way there──► NoPath (stands still, tries again every retrySeconds)
//        no progress for │  │
//        stuckSeconds    ▼  │ after backOffSeconds: replan (the spot ahead marked blocked for a while)
//                      BackingOff (a short backward command; event stuck)
#pragma once

#include <Eigen/Core>

#include "game/nav/follower.h"
#include "game/nav/occupancy_grid.h"
#include "game/nav/planner.h"

namespace engine {
class PlaneWorld;
}

namespace game::nav {

struct NavigatorParams {
  GridDef grid;  ///< the mapped rectangle, cell size and robot radius
  PlannerParams planner;
  FollowerParams follower;

  double reachRadius = 0.3;  ///< the target is reached within this of the path's end [m]
  /// look for movable bodies on this much of the path ahead [m], with circle queries every half cell of radius
  /// max(r / 2, r - 0.71 cell) (r the robot's: a path replanned around a body passes cell centres a full r from it,
  /// and may come closer by half a cell's diagonal between them)
  double blockLookahead = 3.0;
  double movableWindow = 4.0;    ///< a replan marks the movable bodies within this of the robot [m] (a square;
                                 ///< blockLookahead + 1 m, so a body seen on the path is marked whole)
  double replanCooldown = 0.5;   ///< at most one replan for a movable body per this [s] (a moving ghost)
  double offPathDistance = 1.0;  ///< replan when the robot is this far from its path [m]
  double retrySeconds = 1.0;     ///< with no way to the target, try again after this [s]

  // stuck: no progress means the path left has not shrunk by stuckProgress for stuckSeconds, counting only the time
  // the robot was asked to move forward (turning in place, squaring up to stairs and backing off do not count)
  double stuckSeconds = 5.0;       ///< [s] (a walk at 1 m/s covers 5 m)
  double stuckProgress = 0.2;      ///< [m]
  double backOffSpeed = -0.3;      ///< the walk's backward command while backing off [m/s] ...
  double backOffSeconds = 1.0;     ///< ... for this long [s] (about 0.2 m, counting the ramp)
  double backOffClearance = 0.15;  ///< ... cut short when something is this close behind the body [m]
  double stuckMarkAhead = 0.5;     ///< the replan after it blocks a disc this far ahead of where it stuck [m] ...
  double stuckMarkRadius = 0.3;    ///< ... of this radius [m] (the obstacle the 2D layer did not show)
};

/// The robot as a player sees it (plain inputs: odometry).
struct NavInput {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< pelvis (x, y) [m]
  double yaw = 0;                                      ///< heading [rad], 0 = +X
  double speed = 0;                                    ///< forward speed along the heading [m/s]
  /// the robot is being driven forward; a pilot that stops and turns in place between legs (the garden's keys)
  /// passes false meanwhile, and the stuck clock counts only the time it is true
  bool forward = true;
};

/// What happened in one step.
struct NavEvents {
  bool reached = false;    ///< the target was reached (now Idle)
  bool stuck = false;      ///< no progress: backing off
  bool replanned = false;  ///< a new path (after a new target, a block, leaving the path, a back-off or a retry)
  bool blocked = false;    ///< a movable body was seen on the path ahead (a replan follows)
  bool noPath = false;     ///< a plan found no way to the target
};

enum class NavState { Idle, Following, BackingOff, NoPath };
const char* stateName(NavState state);

/// One step's result.
struct NavOutput {
  NavCommand command;
  NavEvents events;
  NavState state = NavState::Idle;
  FollowInfo follow;          ///< the follower's view (while Following)
  double targetDistance = 0;  ///< straight-line distance to the target [m] (0 without one)
};

class Navigator {
 public:
  /// Maps the 2D layer's rectangle (params.grid) once.
  Navigator(const engine::PlaneWorld& plane, const NavigatorParams& params = {});

  /// A new target (plans on the next step). Replaces the current one.
  void setTarget(const Eigen::Vector2d& target);
  /// Forgets the target: Idle, standing still.
  void clearTarget();

  /// One control tick: senses movable bodies in `plane`, replans when needed, follows the path.
  NavOutput step(const engine::PlaneWorld& plane, const NavInput& input, double dt);

  NavState state() const { return state_; }
  const Path& path() const { return path_; }
  const OccupancyGrid& grid() const { return grid_; }
  bool hasTarget() const { return hasTarget_; }
  const Eigen::Vector2d& target() const { return target_; }
  const NavigatorParams& params() const { return params_; }

 private:
  void replan(const engine::PlaneWorld& plane, const NavInput& input, NavOutput* out);
  /// At least `seconds` have passed since the current state began.
  bool elapsed(double seconds) const { return time_ - stateSince_ >= seconds - 1e-9; }

  NavigatorParams params_;
  OccupancyGrid grid_;
  PathFollower follower_;
  Path path_;
  NavState state_ = NavState::Idle;
  bool hasTarget_ = false, planPending_ = false;
  Eigen::Vector2d target_ = Eigen::Vector2d::Zero();
  double time_ = 0;                // sum of dt [s]
  double lastBlockReplan_ = -1e9;  // when the last replan for a movable body was [s]
  double stateSince_ = 0;          // when the current state began [s]
  double bestRemaining_ = 1e18;    // the least path left since the clock was last reset [m]
  double noProgressTime_ = 0;      // time asked to move forward without progress [s]
  bool markStuckSpot_ = false;     // the next replan blocks stuckSpot_
  Eigen::Vector2d stuckSpot_ = Eigen::Vector2d::Zero();
};

}  // namespace game::nav
