// follower.h — from a planned path and the robot's pose to the keyboard-style command the paper's navigation
// gives its skills: a forward speed vr [m/s] and a yaw rate wr [rad/s], and which skill to move with.
//
//   heading control   wr = clamp(turnGain * a, -wMax, wMax), a = the angle from the robot's heading to a point
//                     `lookahead` metres further along the path than the robot's projection on it
//   interlock         vr <= the boundary in the vr-wr plane (interlockLimit): vMax while |wr| <= wFree, falling in a
//                     straight line to vMin at |wr| = wMax: (0, vMax) - (wFree, vMax) - (wMax, vMin), mirrored for
//                     wr < 0. A large heading error turns the robot (nearly) in place, a small one lets it go at speed.
//   obstacle factor   vr *= f in [0, 1] from ray casts straight ahead (obstacleFactor): 1 when nothing is within
//                     obstacleClear of the pelvis, 0 at obstacleStop (the body touching it), linear between
//   arrival           vr <= arrivalGain * (distance left along the path)
//   skills            chooseSkill: stairs on a staircase (after squaring up to it), run on a long straight, walk else
//
// Every threshold is a field of FollowerParams with its reason; docs/navigation.md lists them all.
#pragma once

#include <Eigen/Core>

#include "game/nav/occupancy_grid.h"
#include "game/nav/planner.h"

namespace engine {
class PlaneWorld;
}

namespace game::nav {

/// The skills the navigation moves with (the paper's garden: Walk, Run, Stair).
enum class NavSkill { Walk, Run, Stairs };
const char* skillName(NavSkill skill);

/// One skill's speeds and its interlock boundary. Defaults within the skill-tree's command ranges
/// (assets/skills/tree.toml: walk vx -0.6..1.2, wz +-1.0; run vx 0.8..2.2, wz +-0.5; stairs vx 0.5, wz +-0.3).
struct SpeedProfile {
  double vMax = 1.0;       ///< forward speed on a straight [m/s] (the paper's walk: 0.8-1.0 m/s)
  double vMin = 0.0;       ///< forward speed at the fastest turn, |wr| = wMax [m/s] (0: the turn is in place)
  double wFree = 0.2;      ///< turns up to this rate keep full speed [rad/s] (the runtime's heading hold turns 0.2)
  double wMax = 1.0;       ///< fastest turn [rad/s]
  double lookahead = 0.6;  ///< the heading control's aim point, this far along the path [m]
};

struct FollowerParams {
  SpeedProfile walk{1.0, 0.0, 0.2, 1.0, 0.6};
  /// the paper's run peaked at 1.5 m/s; the run skill has no slow gait (vx >= 0.8) and turns at most 0.5 rad/s,
  /// so the chooser leaves it for the walk before a turn needs more
  SpeedProfile run{1.5, 0.8, 0.2, 0.5, 1.2};
  /// the stairs skill climbs at its one speed (0.5 m/s) and steers within +-0.3 rad/s: no slowing in its turns
  SpeedProfile stairs{0.5, 0.5, 0.3, 0.3, 0.4};

  double turnGain = 1.0;     ///< wr per radian of heading error [1/s]: full turn (1 rad/s) from 1 rad (57 deg) off
  double arrivalGain = 1.0;  ///< vr <= this x the distance left [1/s]: 0.3 m/s when 0.3 m are left

  // obstacle factor: rays parallel to the heading from the pelvis at lateral offsets -w, -w/2, 0, w/2, w (w =
  // obstacleHalfWidth), obstacleClear long; walls and movable bodies count, staircases are seen through
  double obstacleStop = kRobotRadius;  ///< factor 0 when the nearest hit is this far ahead of the pelvis [m] (contact)
  double obstacleClear = 1.5;          ///< factor 1 when nothing is this close [m] (about 1.5 s of walking)
  /// the rays' half spread [m]: the body's core, 0.1 m inside kRobotRadius, so that a wall the path passes at the
  /// map's inflated clearance does not slow the robot
  double obstacleHalfWidth = 0.25;

  // stairs
  double stairsApproach = 1.0;        ///< square up from this far along the path before its first stair cell [m]
                                      ///< (the first riser is a robot radius further: 1.35 m ahead)
  double stairsAlignTolerance = 0.1;  ///< facing the staircase's axis within this [rad] (5.7 deg) before moving on
  double stairsApproachSpeed = 0.3;   ///< the walk's speed cap while squaring up [m/s]
  double stairsEntrySpeed = 0.4;      ///< the stairs skill takes over once the robot is this slow [m/s] (the stairs
                                      ///< skill fell taking over from a 0.7 m/s walk on the Mario course)
  double stairsExit = 0.2;            ///< back to the walk this far past the path's last stair cell [m]
  double minTurnInPlace = 0.2;        ///< squaring up turns at least this fast [rad/s]

  // run: entered on a long straight with the robot facing along it, left before the straight ends
  double runStraight = 5.0;       ///< straight path ahead to start running [m] (about 3 s at 1.5 m/s)
  double runHeading = 0.15;       ///< ... with the heading error within this [rad]
  double runObstacle = 0.99;      ///< ... and the obstacle factor at least this
  double runLeaveStraight = 2.5;  ///< back to the walk when less straight is left [m] (time to slow for the corner)
  double runLeaveHeading = 0.3;   ///< ... or the heading error grows past this [rad]
  double runLeaveObstacle = 0.8;  ///< ... or the obstacle factor falls below this
  double runCornerAngle = 0.35;   ///< a waypoint turning the path by more than this [rad] ends a straight
};

/// The interlock boundary: the largest forward speed allowed while turning at wr.
double interlockLimit(const SpeedProfile& profile, double wr);

/// How far ahead along `yaw` from `from` the first wall or movable body is within `length` [m] (1e9: none);
/// staircases are looked through (one of the obstacle factor's rays).
double clearAhead(const engine::PlaneWorld& plane, const Eigen::Vector2d& from, double yaw, double length);

/// The obstacle factor from the 2D layer at the robot's pose (see FollowerParams). Also gives the nearest hit's
/// distance ahead of the pelvis [m] (1e9: none) when `nearest` is given.
double obstacleFactor(const engine::PlaneWorld& plane, const Eigen::Vector2d& position, double yaw,
                      const FollowerParams& params, double* nearest = nullptr);

/// Where the robot is along a path.
struct PathProgress {
  int segment = 0;     ///< the segment it is projected on
  double arc = 0;      ///< arc length of its projection [m]
  double offPath = 0;  ///< its distance from the path [m]
};
/// Projects p on the path's segments from `fromSegment` on (progress never goes back to an earlier segment);
/// the nearest projection wins, the earlier segment on a tie.
PathProgress projectOnPath(const Path& path, const Eigen::Vector2d& p, int fromSegment);

/// The straight path ahead of arc length s: to the first waypoint turning by more than cornerAngle, or the end.
double straightAhead(const Path& path, double s, double cornerAngle);

/// What the skill choice looks at.
struct SkillCues {
  NavSkill current = NavSkill::Walk;
  double straightAhead = 0;  ///< [m] (ends where the stairs' approach begins)
  double headingError = 0;   ///< to the lookahead point [rad]
  double obstacleFactor = 1;
  bool stairsZone = false;  ///< within stairsApproach before a stairs span up to stairsExit past it
  bool squaredUp = false;   ///< facing the span's heading within stairsAlignTolerance
  double speed = 0;         ///< the robot's forward speed [m/s]
};
/// Stairs in a stairs zone (taken over once squared up and slower than stairsEntrySpeed, then kept to the zone's
/// end); run on a long straight (hysteresis: runStraight/runHeading/runObstacle to start, the runLeave* to stop);
/// walk otherwise.
NavSkill chooseSkill(const SkillCues& cues, const FollowerParams& params);

/// A command for the robot.
struct NavCommand {
  double vr = 0;  ///< forward speed [m/s] (negative: backward)
  double wr = 0;  ///< yaw rate [rad/s], + turns left
  NavSkill skill = NavSkill::Walk;
};

/// What the follower saw this tick (for telemetry, figures and the navigator's stuck clock).
struct FollowInfo {
  PathProgress progress;
  double headingError = 0;  ///< [rad]
  double obstacleFactor = 1;
  double remaining = 0;  ///< path left [m]
  bool stairsZone = false;
  bool squaringUp = false;      ///< turning to the staircase's axis before going on
  bool turningInPlace = false;  ///< the command turns with vr held at 0 by the heading (not by an obstacle)
};

/// Follows one path: keeps the progress along it and the skill in use between ticks (deterministic: no clock).
class PathFollower {
 public:
  explicit PathFollower(FollowerParams params = {}) : params_(params) {}

  /// Starts over on a (new) path, keeping the skill in use.
  void reset() { segment_ = 0; }
  /// Forgets the skill in use too (a new target, a robot standing still).
  void resetSkill(NavSkill skill) { skill_ = skill; }

  /// The command for this tick. `speed`: the robot's forward speed [m/s].
  NavCommand follow(const Path& path, const engine::PlaneWorld& plane, const Eigen::Vector2d& position, double yaw,
                    double speed, FollowInfo* info = nullptr);

  NavSkill skill() const { return skill_; }
  /// The path segment the robot was last projected on.
  int segment() const { return segment_; }
  const FollowerParams& params() const { return params_; }

 private:
  FollowerParams params_;
  int segment_ = 0;
  NavSkill skill_ = NavSkill::Walk;
};

/// The heading error wrapped to [-pi, pi].
double wrapAngle(double a);

}  // namespace game::nav
