// entry_state.h — play's handover states: the moment play handed the robot to a skill on a level, recorded so that a
// play-entry card can start the skill there again (game/entry_card.h) and training can start episodes there
// ([draws] play_share). One entry holds the robot's full physics state after the skill's first control tick, the
// skill runtime's state (clock, filtered action, the fading prior, the lines), the keys' state and the key events
// of the segment that followed, until the skill handed over, fell or kSegmentCapTicks passed. The level's geometry
// is not copied: an entry names its level file, and whoever starts from it loads that level.
// File format (text, one `entry ... end` block per handover): docs/formats.md.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/input/command.h"
#include "engine/input/key_script.h"
#include "engine/physics/articulation.h"
#include "engine/physics/physics_world.h"
#include "robot/skill_runtime.h"

namespace robot {

/// A segment is recorded for at most this many ticks after the entry (30 s: the stairs of levels/mario take 10-20 s).
constexpr int64_t kSegmentCapTicks = 3000;

struct EntryState {
  std::string skill;               ///< the skill that took over
  std::string level;               ///< the level file or folder it happened on, as play was given it (levels/mario)
  std::string source;              ///< who pressed the keys: "autopilot", or the key script's file name
  uint64_t seed = 0;               ///< play's seed
  int64_t tick = 0;                ///< the tick whose control step the skill made first; the state is the one after it
  int64_t segmentTicks = 0;        ///< ticks the skill drove in play after `tick` (to a switch away, a fall or the cap)
  bool fellInPlay = false;         ///< the segment ended in a fall
  engine::ArticulationState body;  ///< the robot (base pose and velocities, joints)
  std::vector<engine::BallState> balls;  ///< the level's balls, in level order
  /// the runtime: active and fadingFrom are nullptr here (the skills are named: skill, fadingFrom)
  SkillState runtime;
  std::string fadingFrom;  ///< "" when no prior is fading out
  engine::CommandState keys;
  engine::CommandLimits limits;
  std::vector<engine::KeyEvent> events;  ///< the segment's key events (ticks after `tick`), in order
};

/// The entries as the file holds them (exact: doubles to 17 significant digits, so a round trip is lossless).
std::string formatEntries(const std::vector<EntryState>& entries);
/// Parses entries; `fileName` is used in messages. Throws engine::Error "file:line: what is wrong" on an unknown or
/// missing field, a wrong count of numbers, a non-finite or out-of-range number, or a bad key event.
std::vector<EntryState> parseEntries(const std::string& text, const std::string& fileName);
/// Reads (parseEntries) and writes (atomically) an entries file.
std::vector<EntryState> loadEntries(const std::string& path);
void saveEntries(const std::string& path, const std::vector<EntryState>& entries);

/// The runtime state an entry holds, with its skills looked up in `set` by name. Throws engine::Error naming the
/// entry if a skill is not in the set.
SkillState entryRuntime(const EntryState& entry, const SkillSet& set);

}  // namespace robot
