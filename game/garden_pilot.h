// garden_pilot.h — plays a map level (plane = "top", no [rules]: levels/garden) the way the paper's operator and
// navigation did: targets one after another (drawn from the run's seed over the map, or a fixed list), a planned
// path to each (game::nav::Navigator, which sees the world only through the level's 2D layer), and the skills
// chosen on the way (walk, run on long straight legs, stairs squared up at a staircase). It acts by key events
// only, so a recorded run replays from its keys like any other.
//
// The key scheme (GardenKeys). It follows the path leg by leg:
//
//   Stop   every movement key up; wait until the command is 0 and the robot at rest (settleTicks)
//   Turn   A or D held toward the leg's heading, let go early enough that the turn's ramp-down (3 rad/s^2) and the
//          skill's lag end it on the heading (turnRelease); after settling, again until within the tolerance (walk
//          legs 0.15 rad with steering, stairs legs 0.05 rad) or maxTurnTries
//   Go     the leg's skill key (0 walk, 2 stairs; 1 run on a long leg when useRun) and W held. With the skill's
//          forward_turn (engine::CommandInput: W with A or D drives and turns together) A or D is held under W to
//          steer toward the path 1.5 m ahead (a stairs leg: toward the staircase's middle line), and away from a wall
//          ahead of one side. A walk leg stops (then turns from rest) at a corner sharper than steerCorner, at a wall
//          or a ball right ahead, and at its end before a staircase or at the last target, the last 1.5 m walked
//          slowly; a target with another after it is walked through. A stairs leg is walked to its end. Without
//          forward_turn the runtime's heading hold keeps W straight and a drifting walk stops to turn again
//          (returnHeading)
//   Back   S held while the navigation backs off a stuck robot
//
//   A leg runs from the robot to the path's next waypoint (with steering, one more than kCornerReach away). Before a
//   staircase it ends at the stairs' entry on the staircase's middle line, 0.85 m before the first riser where that
//   can be walked to; the stairs leg that follows is latched in the world (the middle line and the exit 0.3 m past
//   the last stair cell) until the robot has crossed.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "engine/input/key_script.h"
#include "game/autopilot.h"
#include "game/held_keys.h"
#include "game/nav/navigator.h"

namespace engine {
class PlaneWorld;
}

namespace game {

class Session;

/// A target list: one target per line, "x y" in metres (world x, y), separated by spaces or a comma; '#' starts a
/// comment; blank lines are skipped. Anything else is an error "file:line: what is wrong" (engine::Error).
std::vector<Eigen::Vector2d> parseTargets(const std::string& text, const std::string& fileName);

/// What the key scheme sees in one tick (from the navigation and the robot's own state).
struct LegCues {
  double yaw = 0;                       ///< pelvis heading [rad]
  double yawMean = 0;                   ///< its mean over the last kYawWindow ticks (the gait sways it +-0.03 rad)
  double speed = 0;                     ///< horizontal pelvis speed [m/s]
  double commandVx = 0, commandWz = 0;  ///< the keys' ramped command now
  bool haveLeg = false;                 ///< a path to follow
  double legHeading = 0;                ///< the heading to face for the leg [rad]
  double legRemaining = 0;              ///< distance to the leg's end [m]
  bool endStops = true;                 ///< the leg's end is the path's end or a staircase's entry: stop there
  bool stairsLeg = false;               ///< the leg crosses a staircase (key 2)
  bool runAllowed = false;              ///< the navigation's skill choice is run
  bool running = false;                 ///< the run is in control (a switch asked for waits for the runtime)
  bool backOff = false;                 ///< the navigation backs off (stuck)
  bool pathChanged = false;             ///< a replan this tick
  bool movableAhead = false;            ///< a movable body (a ball) right in front
  double obstacleFactor = 1;            ///< the navigation's obstacle factor (1 clear, 0 touching)
  /// the nearest wall or movable body ahead along the heading from the pelvis and from +-0.25 m either side of it
  /// (staircases looked through) [m], 1e9 when nothing is within 1.5 m
  double leftAhead = 1e9, centreAhead = 1e9, rightAhead = 1e9;
};

/// The key scheme's numbers (see the file comment).
struct GardenKeyParams {
  int settleTicks = 30;           ///< at rest this long before turning or going [ticks]
  double restSpeed = 0.15;        ///< "at rest" below this pelvis speed [m/s]
  double walkTolerance = 0.08;    ///< a walk leg starts within this of its heading [rad] (0.4 m off over 5 m)
  double stairsTolerance = 0.05;  ///< a stairs leg within this [rad] (0.3 m off over the bridge's 6 m)
  int maxTurnTries = 4;           ///< then go anyway
  double turnRamp = 3.0;          ///< the keys' wz ramp [rad/s^2] (engine::CommandLimits::wzRate per 0.01 s)
  double turnLag = 0.12;          ///< the skill's yaw lags its command by about this [s]
  double keyRamp = 2.0;           ///< the keys' vx ramp [m/s^2]
  double brakeLag = 0.15;         ///< the walk's speed lags its command by about this [s]
  double returnHeading = 0.1;     ///< kReturnHeading: stop and turn again when this far off the leg's end [rad] ...
  double returnDistance = 1.0;    ///< ... with more than this to go [m]
  double wallStopFactor = 0.1;    ///< a walk leg stops when the obstacle factor falls below this (a wall 0.47 m ahead)
  /// the run at all: off in the garden. The walk falls taking over from it: with the run on the long straights (and
  /// a run forward_turn of [1.8, 0.3] in a tree copy to steer it), handed back with W held, seeds 1-10 reached 63
  /// targets with 4 walk falls against 85 and 1 without it (docs/navigation.md); the unit tests check it on
  bool useRun = false;
  /// steering under W (the walk's forward_turn: W with A or D): a walk leg starts within steerStartTolerance of its
  /// heading, and on the way A or D is held under W while the leg's end is more than steerOn off the heading (and
  /// more than returnDistance ahead), let go when the ramp down would end it on the heading; the path's corners of at
  /// most steerCorner are walked through, larger ones turned in place from where the walk brakes, without a full stop
  bool steer = false;
  /// the same under W on a stairs leg, toward the staircase's middle line (the stairs' forward_turn)
  bool steerStairs = false;
  double steerStartTolerance = 0.15;  ///< [rad]
  double steerOn = 0.05;              ///< [rad]
  double steerCorner = 0.35;          ///< [rad]: a larger heading error is turned in place
  double steerRamp = 3.0;             ///< the keys' wz ramp under W [rad/s^2]
  double steerLag = 0.25;             ///< the walk's yaw lags a steer by about this [s]
  double steerPursuit = 1.5;          ///< a walk leg aims at the path this far ahead of the robot's progress [m]
  double steerAvoid = 0.7;            ///< a wall or body this close ahead of one side only is steered away from [m]
  double steerWallStop = 0.45;        ///< ... and this close ahead of the pelvis, the leg stops [m]
  double approachDistance = 1.5;      ///< the last this much to a stop (the path's end, a staircase) ... [m]
  double approachSpeed = 0.4;         ///< ... is walked at about this command (W held only below it) [m/s]
  double approachSteerUntil = 0.4;    ///< ... and steered (under W) until this close to its end [m]
  double runMinLeg = 6.0;             ///< run only with this much leg left [m] ...
  double runLeaveLeg = 3.5;           ///< ... and walk again with this much left
  double runFromSpeed = 0.9;          ///< ... and from a walk at least this fast [m/s] ...
  double runHeading = 0.1;            ///< ... and (steering) with the path ahead within this of the heading [rad]
  double runStraightBefore = 2.0;     ///< (steering) the run is not steered in its last this much before the walk [m]
  double walkTopSpeed = 1.3;          ///< (steering) out of a run, W is held, straight on, until the walk is in control
                                      ///< and this slow [m/s] ...
  int walkSettleTicks = 100;          ///< ... and for this long after the walk took over [ticks]
};

/// The yaw error [rad] at which a turn key held at yaw rate `wz` should be let go to stop on the heading.
double turnRelease(double wz, const GardenKeyParams& p);
/// The distance [m] a robot walking at `vx` covers after W is let go.
double brakeDistance(double vx, const GardenKeyParams& p);

/// The key scheme: LegCues in, key events out, one tick at a time (deterministic: no clock of its own).
class GardenKeys {
 public:
  enum class Mode { Stop, Turn, Go, Back };
  GardenKeys(const SkillKeys& keys, GardenKeyParams params = {}) : keys_(keys), p_(params) {}

  std::vector<engine::KeyEvent> decide(int64_t tick, const LegCues& cues);

  Mode mode() const { return mode_; }
  /// The skill key pressed last ('\0': none yet).
  char skillKey() const { return skill_; }
  static const char* modeName(Mode m);
  const GardenKeyParams& params() const { return p_; }

 private:
  void hold(int64_t tick, char key, bool down, std::vector<engine::KeyEvent>* out);
  void releaseMoves(int64_t tick, std::vector<engine::KeyEvent>* out);
  void skill(int64_t tick, char key, std::vector<engine::KeyEvent>* out);
  void enter(Mode m);
  void goSteering(int64_t tick, const LegCues& c, std::vector<engine::KeyEvent>* out);
  void steerUnderW(int64_t tick, const LegCues& c, double until, std::vector<engine::KeyEvent>* out);

  SkillKeys keys_;
  GardenKeyParams p_;
  Mode mode_ = Mode::Stop;
  HeldKeys held_;           // movement keys held (W S A D)
  char skill_ = 0;          // the skill key pressed last
  int64_t restSince_ = -1;  // the tick the robot was first seen at rest in this Stop / between turn pulses
  int tries_ = 0;
  bool goStairs_ = false;    // the Go under way is a stairs leg
  double goHeading_ = 0;     // the leg's heading when it started
  bool wasRunning_ = false;  // the run was in control last tick
  int64_t handover_ = -1;    // the tick the walk took over from the run (-1: not since)
};

/// What the pilot did in one tick, for telemetry.
struct GardenTick {
  int target = -1;              ///< index of the current target (-1: none)
  double targetDistance = 0;    ///< straight-line distance to it [m]
  double targetAngle = 0;       ///< its bearing off the heading [rad]
  double obstacleFactor = 1;    ///< the navigation's obstacle factor
  double navVr = 0, navWr = 0;  ///< the navigation's own command (its interlock), for comparison
  std::string events;           ///< "reached", "stuck", "replanned", "target", "noPath", joined by '+'
  GardenKeys::Mode mode = GardenKeys::Mode::Stop;
};

/// The targets given, reached and the stuck recoveries so far.
struct GardenTally {
  int given = 0, reached = 0, stuck = 0, noPath = 0, replans = 0;
  std::vector<Eigen::Vector2d> targets;  ///< every target given, in order
  std::vector<int64_t> reachedTicks;
};

/// How random targets are drawn, as the paper's operator clicked them one after another: cells of the map that are
/// free (no wall, no stairs) with free cells `clearance` around them, with a path from the previous target (or the
/// spawn) minPath to maxPath long; every acrossEvery-th one (the 2nd, 5th, ...) needs a path that crosses a staircase
/// (the bridge or the short flight), up to acrossMaxPath long. Up to `tries` candidates; then the first that crosses a
/// staircase at any length (an across target), or the first with a path minPath long.
struct TargetDraw {
  double minPath = 4.0;         ///< [m]
  double maxPath = 12.0;        ///< [m] (the paper's sawtooth: target distances mostly under 10 m, one peak near 20 m)
  double acrossMaxPath = 20.0;  ///< [m]
  double clearance = 0.3;       ///< every map cell within this of the target's is free: 0.75 m from a wall [m]
  int acrossEvery = 3;
  int tries = 400;
};

class GardenPilot {
 public:
  /// Maps the session's 2D layer (the rectangle its static bodies cover). With `targets` empty, targets are drawn
  /// from `seed`.
  GardenPilot(const engine::PlaneWorld& plane, const SkillKeys& keys, uint64_t seed,
              std::vector<Eigen::Vector2d> targets, const nav::NavigatorParams& navParams = gardenNavigatorParams(),
              GardenKeyParams keyParams = {});

  std::vector<engine::KeyEvent> decide(int64_t tick, const Session& session);

  const GardenTick& last() const { return last_; }
  const GardenTally& tally() const { return tally_; }
  const nav::Navigator& navigator() const { return *nav_; }

  /// The garden's navigation parameters: the paper's 0.5 m reach radius, the rest docs/navigation.md's defaults.
  static nav::NavigatorParams gardenNavigatorParams();
  /// A random target for a start at `from` (TargetDraw), from `rng`: deterministic.
  static Eigen::Vector2d drawTarget(const nav::OccupancyGrid& grid, const Eigen::Vector2d& from, bool across,
                                    const TargetDraw& draw, std::mt19937_64* rng);

 private:
  LegCues legCues(const Session& session, const nav::NavOutput& out);
  /// the staircase whose entry the robot reached, in the world: its stairs leg is kept while the robot squares up and
  /// climbs (the gait's sway would take it in and out of the entry's reach, a replan would start on the stairs) until
  /// it is passed: its middle line (a point, the axis, the heading up or down it) and where the leg ends along it
  struct StairsLatch {
    bool on = false;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero(), axis = Eigen::Vector2d::UnitX();
    double heading = 0, exitAlong = 0;
  };
  StairsLatch latch_;
  /// The latched staircase's leg cues for a robot at p; false once it is passed (or left).
  bool latchedLeg(const Eigen::Vector2d& p, LegCues* c) const;
  /// the staircase (its span's start) the robot has crossed on the current path: not the next one any more
  double stairsPassed_ = -1;
  static constexpr int kYawWindow = 40;  ///< ticks (about one gait cycle)
  std::vector<double> yaws_;             // the last kYawWindow yaws, a ring
  size_t yawNext_ = 0;
  void nextTarget(const Eigen::Vector2d& from);

  std::unique_ptr<nav::Navigator> nav_;
  GardenKeys keys_;
  std::mt19937_64 rng_;
  std::vector<Eigen::Vector2d> fixed_;
  bool random_ = true;
  int targetIndex_ = -1;
  GardenTally tally_;
  GardenTick last_;
  TargetDraw draw_;
};

}  // namespace game
