// autopilot.h — plays a game level from environment cues only: it never reads a key script or the level file.
// Each tick it looks at the level's 2D side layer (Box2D ray casts ahead of and above the robot), the ghost's
// distance and the ball's position, decides which skill the situation needs, and presses keys, exactly as a
// player would (so a recorded autopilot run replays from its key events alone).
//
//   ghost close behind        -> run (1) with W held, until it gives up or stairs come
//   a step ahead              -> stop (once at the walk's speeds), stairs (2) with W from rest facing +X, back to
//                                walk (0) on flat ground; turned round before the climb: stop and face +X again
//   a low ceiling ahead       -> stop square to the course 0.3 m left of its middle, prone (7), lie 3 s, crawl (9)
//                                with W under it, then 0 (routed through standup) 1.2 m past its end
//   a question box overhead   -> jump (4) until it is hit, then walk on (walk under it if no jump is loaded)
//   the ball ahead            -> stop, face +X and step sideways until the ball is where the kick's card puts
//                                it (0.12 m right of the pelvis), walk up in short steps to 0.30 m from it,
//                                then the one-leg stand (5) and the kick (6); again if it is still short
//   the ball beside or behind  -> (a kick that sent it sideways) step clear of it, back up (S) until it is ahead,
//                                and line up again
//   the ball by a wall        -> (the kick's spot within 0.35 m of the wall) line up with it in front of the foot
//                                nearer the wall, facing 0.1 rad toward it, and walk into it (W) until it has rolled
//                                0.1 m further off the wall or is passed
//   off the course's line     -> (walking, nothing close) slow to 0.8 m/s, stop, turn back to +X, step sideways back
//                                to y = 0
//   put back at a checkpoint  -> walk on from there (every key released first)
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/input/key_script.h"
#include "game/held_keys.h"
#include "robot/skill_runtime.h"

namespace game {

class Session;

/// What the autopilot perceives in one tick (from the Session; all distances along +X from the pelvis).
struct Cues {
  double x = 0;  ///< pelvis x [m]
  double pelvisHeight = 0.78;
  double stepAhead = 1e9;     ///< distance to an obstacle at shin height (0.05 m) [m]
  double ceilingAhead = 1e9;  ///< distance to an obstacle at 0.7 m that has open space at 0.3 m (a tunnel)
  bool underCeiling = false;  ///< something between 0.3 m and 1.0 m above the ground right over the pelvis
  bool boxOverhead = false;   ///< something 1.2-2.0 m up within 0.15 m of the pelvis along x
  double boxAhead = 1e9;      ///< distance to an obstacle at 1.5 m height (a question box)
  double ghost = -1;          ///< the chasing ghost's distance, -1 if none
  double ballAhead = 1e9;     ///< ball centre x minus pelvis x (1e9: no ball)
  bool boxJustHit = false;    ///< the course reported a box hit this tick
  // the robot's own state (odometry and the key state, as a player sees the robot)
  double y = 0;                                        ///< pelvis y: across the course [m]
  double yaw = 0;                                      ///< pelvis heading [rad], 0 = along +X
  double speed = 0;                                    ///< horizontal pelvis speed [m/s]
  double commandVx = 0, commandVy = 0, commandWz = 0;  ///< the keys' ramped command now
  int respawns = 0;                                    ///< times the robot has been put back at a checkpoint so far
  bool canJump = true;                                 ///< the jump has a loaded model
  double ballY = 0;                                    ///< ball centre y [m]
  std::string skill;  ///< the skill in control, as the HUD names it ("stand": the standing controller)
};

/// Reads the cues from a running session.
Cues senseCues(const Session& session);

/// The keys that request the skills the autopilot plays with, found in the tree by name ('\0': not loaded). A keyless
/// skill is requested by the key of the first skill up from it that has one (robot::SkillSet::requestKey).
struct SkillKeys {
  char walk = 0, run = 0, stairs = 0, jump = 0, oneLeg = 0, kick = 0, prone = 0, crawl = 0;
};
SkillKeys skillKeys(const robot::SkillSet& skills);

class Autopilot {
 public:
  explicit Autopilot(const SkillKeys& keys) : keys_(keys) {}

  enum class Mode {
    Walk,
    Run,
    Stairs,
    Prone,
    Crawl,
    StandUp,
    Jump,
    Align,
    Approach,
    Balance,
    Kick,
    Recover,
    BackUp,
    Dribble
  };

  /// The key events for this tick, given what the robot perceives.
  std::vector<engine::KeyEvent> decide(int64_t tick, const Cues& cues);

  Mode mode() const { return mode_; }
  static const char* modeName(Mode m);

 private:
  void backOffBall(int64_t tick, const Cues& c, std::vector<engine::KeyEvent>* out);
  void enter(int64_t tick, Mode m, char skillKey, bool forward, std::vector<engine::KeyEvent>* out);
  SkillKeys keys_;
  void hold(int64_t tick, char key, bool down, std::vector<engine::KeyEvent>* out);
  void releaseAll(int64_t tick, std::vector<engine::KeyEvent>* out);
  /// Align mode: stop, turn to yaw 0, step sideways to alignY_; true once within the tolerances.
  bool align(int64_t tick, const Cues& c, std::vector<engine::KeyEvent>* out);
  void nudge(int64_t tick, double error, double command, double ramp, double tolerance, char plus, char minus,
             std::vector<engine::KeyEvent>* out);
  /// Approach mode: short steps forward (W) or back (S) until the ball is kBallKick ahead; true once there.
  bool approach(int64_t tick, const Cues& c, std::vector<engine::KeyEvent>* out);
  /// The ball where the kick's card puts it (kBallKick ahead, kBallSide to the right, in the pelvis's heading
  /// frame), within tolerances, facing +X within yawTol.
  static bool atKickSpot(const Cues& c, double yawTol);
  /// Align mode toward the kick's spot beside the ball (then Approach).
  void lineUpWithBall(int64_t tick, const Cues& c, std::vector<engine::KeyEvent>* out);

  Mode mode_ = Mode::Walk;
  bool started_ = false;
  HeldKeys held_;  // movement keys held now (W S A D Q E)
  int respawnsSeen_ = 0;
  // Align / Approach: the target, the tolerances, the step (stop, turn, side) and when the last key went up
  double alignY_ = 0, alignYTol_ = 0.1, alignYawTol_ = 0.1, alignYaw_ = 0;  // alignYaw_: the heading to face
  Mode afterAlign_ = Mode::Walk;
  int alignStep_ = 0, alignTries_ = 0;
  int64_t keyUpTick_ = -1;
  int pulses_ = 0;              // Approach: short W / S presses so far ...
  int64_t pulseTick_ = 0;       // ... and when the latest began
  double jumpedAtX_ = -1e9;     // where the last jump was (one per box)
  int64_t standSince_ = -1;     // Balance: the tick the one-leg stand took over (-1: not yet)
  bool flew_ = false;           // the jump in progress has left the ground once
  bool stairsStarted_ = false;  // Stairs mode: at rest and the stairs key pressed ...
  bool climbed_ = false;        // ... and up the first step (higher than standing on flat ground)
  int64_t since_ = 0;           // tick the current mode began
  double ceilingEndX_ = -1e9;   // last x seen under the tunnel ceiling
  double flatSince_ = -1;       // x where stairs mode last saw flat ground
};

}  // namespace game
