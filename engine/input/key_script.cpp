// key_script.cpp — strict key-script parser: byte checks, comments, fields, times, held-key tracking.
#include "engine/input/key_script.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <system_error>

#include "engine/core/error.h"
#include "engine/loop/clock.h"

namespace engine {
namespace {

constexpr std::string_view kKeyLetters = "WASDQERF";

// Bit index of a canonical key in a held-key mask: digits 0..9, then the letters in kKeyLetters order.
int keyIndex(char key) {
  if (key >= '0' && key <= '9') return key - '0';
  const size_t i = kKeyLetters.find(key);
  return i == std::string_view::npos ? -1 : 10 + static_cast<int>(i);
}

std::string hexByte(unsigned char c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02x", static_cast<unsigned>(c));
  return buf;
}

// Describes a byte that may not appear in a script, or returns "" if it may (outside comments).
std::string badCodeByte(unsigned char c) {
  if (c == 0) return "NUL byte (binary file?)";
  if (c == '\r') return "stray carriage return";
  if (c == '\t') return "";
  if (c < 0x20 || c == 0x7f) return "control byte " + hexByte(c) + " (binary file?)";
  if (c >= 0x80) return "non-ASCII byte " + hexByte(c) + " (only comments may hold non-ASCII text)";
  return "";
}

// Length of the valid UTF-8 sequence starting at s[i] (1..4), or 0 if it is not valid UTF-8
// (overlong forms, surrogates and code points above U+10FFFF are invalid).
size_t utf8SequenceLength(std::string_view s, size_t i) {
  const auto b = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  if (c < 0x80) return 1;
  size_t n;
  unsigned char lo = 0x80, hi = 0xbf;  // allowed range of the second byte
  if (c >= 0xc2 && c <= 0xdf) {
    n = 2;
  } else if (c >= 0xe0 && c <= 0xef) {
    n = 3;
    if (c == 0xe0) lo = 0xa0;
    if (c == 0xed) hi = 0x9f;
  } else if (c >= 0xf0 && c <= 0xf4) {
    n = 4;
    if (c == 0xf0) lo = 0x90;
    if (c == 0xf4) hi = 0x8f;
  } else {
    return 0;
  }
  if (i + n > s.size()) return 0;
  if (b(i + 1) < lo || b(i + 1) > hi) return 0;
  for (size_t k = 2; k < n; ++k) {
    if (b(i + k) < 0x80 || b(i + k) > 0xbf) return 0;
  }
  return n;
}

// Checks every byte of one line (without its line break); returns "" or what is wrong.
std::string checkLineBytes(std::string_view line) {
  const size_t commentStart = line.find('#');
  for (size_t i = 0; i < line.size();) {
    const auto c = static_cast<unsigned char>(line[i]);
    const std::string column = " at column " + std::to_string(i + 1);
    if (i < commentStart) {
      const std::string bad = badCodeByte(c);
      if (!bad.empty()) return bad + column;
      ++i;
      continue;
    }
    if (c != '\t' && (c < 0x20 || c == 0x7f)) return badCodeByte(c) + column;
    const size_t n = utf8SequenceLength(line, i);
    if (n == 0) return "invalid UTF-8 in comment" + column;
    i += n;
  }
  return "";
}

std::vector<std::string_view> splitFields(std::string_view code) {
  std::vector<std::string_view> fields;
  size_t i = 0;
  while (i < code.size()) {
    while (i < code.size() && (code[i] == ' ' || code[i] == '\t')) ++i;
    const size_t start = i;
    while (i < code.size() && code[i] != ' ' && code[i] != '\t') ++i;
    if (i > start) fields.push_back(code.substr(start, i - start));
  }
  return fields;
}

// Parses a plain decimal ("6", "6.20", ".5", "6.") into *out; returns "" or what is wrong.
std::string parseSeconds(std::string_view word, double* out) {
  const std::string quoted = "'" + std::string(word) + "'";
  if (!word.empty() && word[0] == '-') return "negative time " + quoted + " (times are seconds from the start)";
  size_t digits = 0, dots = 0;
  for (char c : word) {
    if (c >= '0' && c <= '9')
      ++digits;
    else if (c == '.')
      ++dots;
    else
      return "bad time " + quoted + ": expected seconds as a plain decimal such as 6.20";
  }
  if (digits == 0 || dots > 1) return "bad time " + quoted + ": expected seconds as a plain decimal such as 6.20";
  double value = 0.0;
  const auto result = std::from_chars(word.data(), word.data() + word.size(), value, std::chars_format::fixed);
  if (result.ec != std::errc() || result.ptr != word.data() + word.size() || !std::isfinite(value)) {
    return "bad time " + quoted + ": not a representable number";
  }
  if (value > kMaxKeyScriptSeconds) return "time " + quoted + " is beyond the limit of 86400 s";
  *out = value;
  return "";
}

}  // namespace

std::optional<KeyAction> parseKeyAction(std::string_view word) {
  if (word == "down") return KeyAction::kDown;
  if (word == "up") return KeyAction::kUp;
  if (word == "tap") return KeyAction::kTap;
  return std::nullopt;
}

std::string_view keyActionName(KeyAction action) {
  switch (action) {
    case KeyAction::kDown:
      return "down";
    case KeyAction::kUp:
      return "up";
    case KeyAction::kTap:
      return "tap";
  }
  return "?";
}

std::optional<char> parseKeyName(std::string_view word) {
  if (word.size() != 1) return std::nullopt;
  char c = word[0];
  if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  if (!isValidKey(c)) return std::nullopt;
  return c;
}

bool isValidKey(char key) { return keyIndex(key) >= 0; }

KeyScript parseKeyScriptWithSeed(std::string_view text, const std::string& fileName) {
  KeyScript script;
  std::vector<KeyEvent>& events = script.events;
  uint32_t held = 0;  // bit keyIndex(k) set while key k is down
  double previousSeconds = 0.0;
  std::string previousTime;  // the previous event's time as written, for messages
  int lineNumber = 0;
  size_t pos = 0;
  while (pos < text.size()) {
    ++lineNumber;
    const auto fail = [&](const std::string& what) { throw Error(located(fileName, lineNumber, what)); };
    const size_t newline = text.find('\n', pos);
    const size_t end = newline == std::string_view::npos ? text.size() : newline;
    std::string_view line = text.substr(pos, end - pos);
    pos = newline == std::string_view::npos ? text.size() : newline + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);

    const std::string badBytes = checkLineBytes(line);
    if (!badBytes.empty()) fail(badBytes);
    if (line.size() > kMaxKeyScriptLineLength) {
      fail("line too long (" + std::to_string(line.size()) + " characters, limit 200)");
    }
    const std::vector<std::string_view> fields = splitFields(line.substr(0, line.find('#')));
    if (fields.empty()) continue;
    if (fields[0] == "seed") {
      if (fields.size() != 2) fail("expected 'seed <N>' (2 fields), got " + std::to_string(fields.size()));
      if (script.seed) fail("a second seed line (the first is line " + std::to_string(script.seedLine) + ")");
      if (!events.empty()) fail("the seed line must come before the first key event");
      const std::string_view n = fields[1];
      uint64_t value = 0;
      const auto [rest, ec] = std::from_chars(n.data(), n.data() + n.size(), value);  // digits only: no sign, no "0x"
      if (ec != std::errc() || rest != n.data() + n.size())
        fail("bad seed '" + std::string(n) + "' (expected a whole number from 0 to 18446744073709551615)");
      script.seed = value;
      script.seedLine = lineNumber;
      continue;
    }
    if (fields.size() != 3) {
      fail("expected '<time_s> <action> <key>' (3 fields), got " + std::to_string(fields.size()));
    }

    double seconds = 0.0;
    const std::string badTime = parseSeconds(fields[0], &seconds);
    if (!badTime.empty()) fail(badTime);
    if (!events.empty() && seconds < previousSeconds) {
      fail("time " + std::string(fields[0]) + " is before the previous event's time " + previousTime +
           " (times must not decrease)");
    }
    const std::optional<KeyAction> action = parseKeyAction(fields[1]);
    if (!action) fail("unknown action '" + std::string(fields[1]) + "' (expected down, up or tap)");
    const std::optional<char> key = parseKeyName(fields[2]);
    if (!key) fail("unknown key '" + std::string(fields[2]) + "' (expected 0-9, W, A, S, D, Q, E, R or F)");

    const uint32_t bit = 1u << keyIndex(*key);
    const std::string k(1, *key);
    switch (*action) {
      case KeyAction::kDown:
        if (held & bit) fail("'down " + k + "' but " + k + " is already held (missing 'up " + k + "'?)");
        held |= bit;
        break;
      case KeyAction::kUp:
        if (!(held & bit)) fail("'up " + k + "' but " + k + " is not held");
        held &= ~bit;
        break;
      case KeyAction::kTap:
        if (held & bit) fail("'tap " + k + "' but " + k + " is held (release it with 'up " + k + "' first)");
        break;
    }
    if (events.size() >= kMaxKeyScriptEvents) fail("too many events (limit 100000)");
    events.push_back(KeyEvent{secondsToTicks(seconds), *action, *key});
    previousSeconds = seconds;
    previousTime = std::string(fields[0]);
  }
  return script;
}

std::vector<KeyEvent> parseKeyScript(std::string_view text, const std::string& fileName) {
  return parseKeyScriptWithSeed(text, fileName).events;
}

std::string formatKeyEvent(const KeyEvent& event) {
  std::string s = std::to_string(event.tick);
  s += ' ';
  s += keyActionName(event.action);
  s += ' ';
  s += event.key;
  return s;
}

std::string formatKeyScript(const std::vector<KeyEvent>& events, uint64_t seed, const std::string& header) {
  std::string text;
  for (size_t at = 0; !header.empty() && at <= header.size();) {
    const size_t end = std::min(header.find('\n', at), header.size());
    std::string comment = "# " + header.substr(at, end - at);
    for (char& c : comment)  // kept readable as a script: no control bytes, within the line limit
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
    text += comment.substr(0, kMaxKeyScriptLineLength) + "\n";
    at = end + 1;
  }
  text += "seed " + std::to_string(seed) + "\n";
  char line[64];
  for (const KeyEvent& e : events) {
    std::snprintf(line, sizeof line, "%.2f %s %c\n", double(e.tick) * kTickSeconds,
                  std::string(keyActionName(e.action)).c_str(), e.key);
    text += line;
  }
  return text;
}

}  // namespace engine
