// replay.h — the replay file: what was played (level, model hashes, seed, length), every key event
// with its tick, and periodic state hashes, as strict line-based text (version 1) closed by an FNV-1a
// checksum line. Same binary + same inputs re-simulates bit for bit; the state hashes prove it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "engine/input/key_script.h"

namespace engine {

/// The only replay format version this build reads and writes.
constexpr int kReplayVersion = 1;
/// Largest recording length (ticks of 0.01 s): 86400 s, play's own limit.
constexpr int64_t kMaxReplayTicks = 8640000;
/// Largest state-hash period (ticks).
constexpr int kMaxReplayHashEvery = 1000000;
/// Longest line in a replay file (characters, without the line break).
constexpr size_t kMaxReplayLineLength = 1024;

/// A simulation state hash recorded at a tick.
struct StateHash {
  int64_t tick = 0;   ///< control tick at which the state was hashed
  uint64_t hash = 0;  ///< FNV-1a (64 bit) of the simulation state

  /// Same tick and same hash.
  bool operator==(const StateHash& o) const { return tick == o.tick && hash == o.hash; }
  /// Different tick or hash.
  bool operator!=(const StateHash& o) const { return !(*this == o); }
};

/// Everything needed to re-simulate a play session and check that it matches.
struct Replay {
  int version = kReplayVersion;   ///< format version (always 1)
  std::string level;              ///< level as named when played, e.g. "levels/flat" (printable ASCII, no spaces)
  uint64_t levelHash = 0;         ///< FNV-1a of the level file's content
  uint64_t robotHash = 0;         ///< FNV-1a of the robot model file's content
  uint64_t skillsHash = 0;        ///< FNV-1a of the skill tree (file and models)
  uint64_t seed = 0;              ///< simulation seed
  int64_t ticks = 0;              ///< recording length in control ticks (0..1e9)
  int hashEvery = 50;             ///< state hash period in ticks (1..1e6)
  std::vector<KeyEvent> events;   ///< key events, ticks non-decreasing and < ticks
  std::vector<StateHash> states;  ///< state hashes, ticks strictly increasing, multiples of hashEvery, <= ticks
};

/// Field-by-field equality.
bool operator==(const Replay& a, const Replay& b);
/// Field-by-field inequality.
bool operator!=(const Replay& a, const Replay& b);

/// The version-1 text of a replay, ending with "end <checksum>\n". Throws engine::Error if the version is
/// not 1 or the level name cannot be written (empty, spaces, control or non-ASCII characters, too long).
std::string serializeReplay(const Replay& replay);

/// Parses version-1 replay text strictly. Throws engine::Error "fileName:line: ..." for a wrong magic or
/// version, missing, duplicate or out-of-order header lines, bad hex (exactly 16 lowercase digits), bad
/// or out-of-range numbers, event ticks decreasing or >= ticks, state ticks not strictly increasing,
/// > ticks or not multiples of hash_every, a truncated file ("truncated: missing end line"), a checksum
/// mismatch, or anything after the end line; and "fileName: byte N: ..." (N counted from 0) for NUL,
/// control (incl. CR) or non-ASCII bytes. Layout: magic; header lines level, robot, skills, seed, ticks,
/// hash_every in that order; all event lines; all state lines; "end <FNV-1a of all preceding bytes>" and
/// a final '\n'. Fields are separated by single spaces. Held-key consistency of the events is not checked
/// (CommandInput tolerates repeated downs and ups).
Replay parseReplay(std::string_view bytes, const std::string& fileName);

/// Serialises, checks that the text parses back, and writes it atomically (no half-written file).
/// Throws engine::Error naming path on any failure.
void saveReplay(const std::string& path, const Replay& replay);

/// Reads and parses a replay file. Throws engine::Error naming path on any failure.
Replay loadReplay(const std::string& path);

}  // namespace engine
