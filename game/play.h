// play.h — runs a Session for a number of ticks from a list of key events: the headless game loop used
// by `play`, `replay` and the tests. Frames leave through a callback so simulation never touches the
// renderer. Optionally records state hashes (for replays) or checks them (for --verify).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "engine/input/key_script.h"
#include "engine/render/scene_snapshot.h"
#include "engine/replay/replay.h"
#include "game/entry_recorder.h"
#include "game/session.h"

namespace game {

struct PlayOptions {
  uint64_t seed = 1;
  int64_t ticks = 1000;                                      ///< how long to run [ticks of 0.01 s]
  std::vector<engine::KeyEvent> events;                      ///< sorted by tick
  int hashEvery = 50;                                        ///< record a state hash every N ticks (0 = never)
  const std::vector<engine::StateHash>* expected = nullptr;  ///< if set, stop at the first mismatch
  int frameEvery = 0;                                        ///< call onFrame every N ticks (0 = never)
  engine::CameraMode camera = engine::CameraMode::Side;
  std::function<void(const engine::SceneSnapshot&)> onFrame;
  bool stopOnFall = false;                  ///< end the run at the first fall
  const robot::SkillSet* skills = nullptr;  ///< learned skills, or none
  bool autopilot = false;                   ///< the autopilot presses the keys (after any scripted events); on a
                                            ///< map (plane = top, no [rules]) the garden pilot (game/garden_pilot.h)
  std::vector<Eigen::Vector2d> targets;     ///< the garden pilot's targets in order (empty: drawn from the seed)
  EntryRecorder* entries = nullptr;         ///< records play's handover states (game/entry_recorder.h), or none
};

/// The garden pilot's run (a map level played with autopilot), at 50 Hz and in total.
struct GardenSample {
  double t = 0;
  double x = 0, y = 0, z = 0;   ///< pelvis [m]
  double vx = 0, vy = 0;        ///< pelvis velocity, world [m/s]
  double vr = 0, wr = 0;        ///< the keys' command the robot follows (forward [m/s], yaw rate [rad/s])
  double navVr = 0, navWr = 0;  ///< the navigation's own command (its speed-turn interlock), for comparison
  int target = -1;
  double targetDistance = 0, targetAngle = 0;
  double obstacleFactor = 1;
  std::string skill;
  double roll = 0, pitch = 0, yaw = 0;  ///< pelvis [rad]
  std::string mode;                     ///< the key scheme's mode (stop, turn, go, back)
  std::string events;                   ///< what happened since the last sample ('+'-joined)
};
struct GardenSkillStats {
  int64_t ticks = 0;
  double distance = 0;               ///< pelvis path length while it was in control [m]
  double maxRoll = 0, maxPitch = 0;  ///< largest |roll|, |pitch| [rad]
};
struct GardenReport {
  bool played = false;
  int targetsGiven = 0, targetsReached = 0, stuck = 0, noPath = 0, replans = 0;
  std::vector<Eigen::Vector2d> targets;
  std::map<std::string, GardenSkillStats> skills;  ///< by the skill in control ("stand": none)
  std::vector<GardenSample> samples;
};

/// How the motion carried through one skill switch (forward = world +X, centre of mass, 0.1 s moving average).
struct SwitchReport {
  SwitchEvent event;
  double speedBefore = 0;       ///< mean over the 0.5 s before the switch [m/s]
  double speedAfter = 0;        ///< mean over 2-3 s after it (or up to the next switch) [m/s]
  double peakAcceleration = 0;  ///< largest |d v / dt| of the smoothed speed from 0.5 s before to 3 s after [m/s^2]
};

/// The centre of mass every other tick (50 Hz), for the continuity log.
struct ComSample {
  double t = 0, x = 0, z = 0, vx = 0;
  std::string skill;
  double y = 0, yaw = 0;  ///< the centre of mass across the course [m], the pelvis heading [rad]
  /// the centre of mass's offset to the robot's left (across the pelvis heading) from the point between the feet
  /// [m]: about 0 standing on both feet, the half stance width (~0.1 m) over the left foot
  double leftOfFeet = 0;
};

struct PlayResult {
  int64_t ticks = 0;  ///< ticks simulated
  bool fallen = false;
  int64_t fallTick = -1;
  std::vector<engine::StateHash> hashes;  ///< recorded every hashEvery ticks (after the tick)
  int64_t divergedTick = -1;              ///< first tick whose hash differed from expected, -1 if none
  uint64_t finalHash = 0;
  Telemetry telemetry;
  robot::Sensors finalSensors;
  double wallSeconds = 0;
  // game levels
  Outcome outcome = Outcome::Playing;  ///< won or lost ends the run early
  std::string outcomeReason;
  int score = 0, coins = 0, gifts = 0;
  std::vector<CourseEvent> events;
  std::vector<engine::KeyEvent> keyEvents;  ///< every key event applied (script and autopilot), for replays
  std::vector<SwitchReport> switchReports;  ///< one per skill switch between two learned skills
  std::vector<ComSample> comLog;            ///< 50 Hz centre-of-mass samples
  GardenReport garden;                      ///< the garden pilot's run (PlayOptions::autopilot on a map)
};

/// A map level (plane = top, no [rules]): the autopilot there is the garden pilot.
bool isMapLevel(const levels::Level& level);

/// Plays level with model for options.ticks ticks.
PlayResult play(const levels::Level& level, const robot::RobotModel& model, const PlayOptions& options);

}  // namespace game
