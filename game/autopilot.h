// autopilot.h — plays a game level from environment cues only: it never reads a key script or the level file.
// Each tick it looks at the level's 2D side layer (Box2D ray casts ahead of and above the robot), the ghost's
// distance and the ball's position, decides which skill the situation needs, and presses keys, exactly as a
// player would (so a recorded autopilot run replays from its key events alone).
//
//   ghost close behind        -> run (1) with W held, until it gives up or stairs come
//   a step ahead              -> stairs (2) with W, back to walk (0) on flat ground
//   a low ceiling ahead       -> prone (7), crawl (9) with W under it, then 0 (routed through standup)
//   a question box overhead   -> jump (4) until it is hit, then walk on
//   the ball just ahead       -> one-leg stand (5), then kick (6); walk up to it again if it is still short
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/input/key_script.h"

namespace game {

class Session;

/// What the autopilot perceives in one tick (from the Session; all distances along +X from the pelvis).
struct Cues {
  double x = 0;               ///< pelvis x [m]
  double pelvisHeight = 0.78;
  double stepAhead = 1e9;     ///< distance to an obstacle at shin height (0.05 m) [m]
  double ceilingAhead = 1e9;  ///< distance to an obstacle at 0.7 m that has open space at 0.3 m (a tunnel)
  bool underCeiling = false;  ///< something between 0.3 m and 1.0 m above the ground right over the pelvis
  bool boxOverhead = false;   ///< something 1.2-2.0 m up within 0.15 m of the pelvis along x
  double boxAhead = 1e9;      ///< distance to an obstacle at 1.5 m height (a question box)
  double ghost = -1;          ///< the chasing ghost's distance, -1 if none
  double ballAhead = 1e9;     ///< ball centre x minus pelvis x (1e9: no ball)
  bool boxJustHit = false;    ///< the course reported a box hit this tick
};

/// Reads the cues from a running session.
Cues senseCues(const Session& session);

class Autopilot {
 public:
  enum class Mode { Walk, Run, Stairs, Prone, Crawl, StandUp, Jump, Balance, Kick, Recover };

  /// The key events for this tick, given what the robot perceives.
  std::vector<engine::KeyEvent> decide(int64_t tick, const Cues& cues);

  Mode mode() const { return mode_; }
  static const char* modeName(Mode m);

 private:
  void enter(int64_t tick, Mode m, char skillKey, bool forward, std::vector<engine::KeyEvent>* out);

  Mode mode_ = Mode::Walk;
  bool started_ = false, forwardHeld_ = false;
  int64_t since_ = 0;        // tick the current mode began
  double ceilingEndX_ = -1e9;  // last x seen under the tunnel ceiling
  double flatSince_ = -1;    // x where stairs mode last saw flat ground
};

}  // namespace game
