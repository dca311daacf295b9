// key_script.h — keyboard scripts: timed key events read from a text file, one per line,
// "<time_s> <action> <key>" (e.g. "0.50 down W"), '#' starts a comment; an optional "seed <N>" line before the
// first event names the seed the script was made for (play uses it unless --seed is given). Parsing is strict: any
// problem throws engine::Error "file:line: what is wrong". Key events are also the unit a replay
// records, so the event type and its one-line text form live here.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace engine {

/// What happens to a key: pressed and held, released, or pressed and released within one tick.
enum class KeyAction { kDown, kUp, kTap };

/// One key event at a control tick.
struct KeyEvent {
  int64_t tick = 0;                    ///< control tick (0.01 s each) at which the event applies
  KeyAction action = KeyAction::kTap;  ///< down, up or tap
  char key = '0';                      ///< '0'..'9' or one of 'W','A','S','D','Q','E','R','F' (uppercase)

  /// Same tick, action and key.
  bool operator==(const KeyEvent& o) const { return tick == o.tick && action == o.action && key == o.key; }
  /// Differs in tick, action or key.
  bool operator!=(const KeyEvent& o) const { return !(*this == o); }
};

/// Largest number of events a key script may hold.
constexpr size_t kMaxKeyScriptEvents = 100000;
/// Longest key-script line (characters, without the line break).
constexpr size_t kMaxKeyScriptLineLength = 200;
/// Latest time a key script may use (s): one day.
constexpr double kMaxKeyScriptSeconds = 86400.0;

/// "down", "up" or "tap" (exact, lowercase) to a KeyAction; nullopt for anything else.
std::optional<KeyAction> parseKeyAction(std::string_view word);

/// The lowercase name of an action: "down", "up" or "tap".
std::string_view keyActionName(KeyAction action);

/// A one-character key name ("0".."9", "W"/"w", ... "F"/"f") to its canonical form (digit or
/// uppercase letter); nullopt for anything else.
std::optional<char> parseKeyName(std::string_view word);

/// True for the canonical keys: '0'..'9' and 'W','A','S','D','Q','E','R','F'.
bool isValidKey(char key);

/// Parses a key script into events in file order. Times (s, plain decimals such as "6.20", 0..86400,
/// non-decreasing) become ticks with secondsToTicks(). Throws engine::Error "fileName:line: ..." for an
/// unknown action or key, missing or extra fields, a bad time ("1e999", "nan", "-1", "1.5x"), time going
/// backwards, "down" of a held key, "up" of a key not held, "tap" of a held key, NUL or other control
/// bytes, non-ASCII outside comments (comments may hold UTF-8), lines over 200 characters, more than
/// 100000 events. Fields are separated by spaces or tabs; CRLF line ends are accepted. A seed line is checked
/// as parseKeyScriptWithSeed() checks it and then left out.
std::vector<KeyEvent> parseKeyScript(std::string_view text, const std::string& fileName);

/// A key script with its optional seed line.
struct KeyScript {
  std::vector<KeyEvent> events;  ///< in file order
  std::optional<uint64_t> seed;  ///< from a "seed <N>" line (N: 0..18446744073709551615), if the script has one
  int seedLine = 0;              ///< the seed line's number (1-based), for messages; 0 without one
};

/// parseKeyScript() that also reads a "seed <N>" line (at most one, before the first event; N a plain decimal
/// integer that fits 64 bits). Throws engine::Error "fileName:line: ..." for a second seed line, a seed line after
/// an event, or a bad number ("-1", "1e3", "0x10", too large), besides parseKeyScript()'s errors.
KeyScript parseKeyScriptWithSeed(std::string_view text, const std::string& fileName);

/// One-line text form with the tick, e.g. "123 down W" (used by replays and logs).
std::string formatKeyEvent(const KeyEvent& event);

/// A key script that parseKeyScriptWithSeed() reads back as `events` and `seed`: `header` as '#' comment lines
/// (split at '\n', control bytes as '?', each cut to the 200-character line limit), a "seed <N>" line, then one
/// "<seconds> <action> <key>" line per event (two decimals: a tick is 0.01 s). Events must be in tick order and
/// valid as a script (as a replay's are).
std::string formatKeyScript(const std::vector<KeyEvent>& events, uint64_t seed, const std::string& header);

}  // namespace engine
