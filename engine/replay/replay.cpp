// replay.cpp — replay text writer and its strict reader (byte checks, header order, body order,
// checksum, truncation).
#include "engine/replay/replay.h"

#include <array>
#include <cstdio>
#include <optional>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"

namespace engine {
namespace {

constexpr std::string_view kMagic = "treelearn-replay";
constexpr std::array<std::string_view, 6> kHeaderKeys = {"level", "robot", "skills", "seed", "ticks", "hash_every"};
constexpr std::string_view kHeaderOrder = "level, robot, skills, seed, ticks, hash_every";

// A token as quoted in messages, cut short if long.
std::string quote(std::string_view s) {
  if (s.size() > 40) return "'" + std::string(s.substr(0, 40)) + "...'";
  return "'" + std::string(s) + "'";
}

// "" if every byte is printable ASCII or '\n', else "byte N: what is wrong" for the first bad one.
std::string checkBytes(std::string_view bytes) {
  for (size_t i = 0; i < bytes.size(); ++i) {
    const auto c = static_cast<unsigned char>(bytes[i]);
    if (c == '\n' || (c >= 0x20 && c <= 0x7e)) continue;
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02x", static_cast<unsigned>(c));
    std::string what;
    if (c == 0)
      what = "NUL byte (binary data in a text replay)";
    else if (c == '\r')
      what = "carriage return (CRLF line endings are not allowed)";
    else if (c >= 0x80)
      what = "non-ASCII byte " + std::string(hex) + " (replays are plain ASCII)";
    else
      what = "control byte " + std::string(hex) + " (binary data in a text replay)";
    return "byte " + std::to_string(i) + ": " + what;
  }
  return "";
}

// Splits on single spaces; returns false if any field is empty (leading, trailing or double space).
bool splitFields(std::string_view line, std::vector<std::string_view>* fields) {
  fields->clear();
  size_t start = 0;
  while (true) {
    const size_t space = line.find(' ', start);
    const std::string_view field = line.substr(start, space == std::string_view::npos ? space : space - start);
    if (field.empty()) return false;
    fields->push_back(field);
    if (space == std::string_view::npos) return true;
    start = space + 1;
  }
}

// Whole-text reader that tracks line numbers and reports problems at the current line.
class ReplayReader {
 public:
  ReplayReader(std::string_view bytes, const std::string& fileName) : bytes_(bytes), fileName_(fileName) {}

  Replay read() {
    if (bytes_.empty()) throw Error(located(fileName_, 0, "empty file, expected a treelearn replay"));
    const std::string magicPrefix = std::string(kMagic) + " ";
    if (bytes_.size() < magicPrefix.size() && magicPrefix.compare(0, bytes_.size(), bytes_) == 0) {
      throw Error(located(fileName_, 1, "truncated: missing end line"));
    }
    if (bytes_.substr(0, magicPrefix.size()) != magicPrefix) {
      throw Error(located(fileName_, 1, "not a treelearn replay (the first line must be 'treelearn-replay 1')"));
    }
    const std::string badByte = checkBytes(bytes_);
    if (!badByte.empty()) throw Error(located(fileName_, 0, badByte));

    while (nextLine()) {
      if (line_.size() > kMaxReplayLineLength) fail("line too long (limit 1024 characters)");
      if (!splitFields(line_, &fields_)) fail("malformed line: fields must be separated by single spaces");
      if (lineNumber_ == 1)
        readMagic();
      else if (readBodyLine())
        return replay_;
    }
    fail("truncated: missing end line");
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw Error(located(fileName_, lineNumber_, what)); }

  // Advances to the next complete line; false at the end of the bytes. A last line without '\n' is a
  // truncated file.
  bool nextLine() {
    ++lineNumber_;
    if (pos_ >= bytes_.size()) return false;
    const size_t newline = bytes_.find('\n', pos_);
    if (newline == std::string_view::npos) {
      if (bytes_.substr(pos_).substr(0, 4) == "end ") fail("truncated: missing newline after end line");
      fail("truncated: missing end line");
    }
    lineStart_ = pos_;
    line_ = bytes_.substr(pos_, newline - pos_);
    pos_ = newline + 1;
    return true;
  }

  void expectFields(size_t n, std::string_view form) const {
    if (fields_.size() != n) fail("expected '" + std::string(form) + "'");
  }

  uint64_t number(std::string_view word, uint64_t min, uint64_t max, std::string_view what) const {
    if (!word.empty() && word[0] == '-') fail("negative " + std::string(what) + " " + quote(word));
    uint64_t v = 0;
    bool overflow = word.size() > 20;
    for (char c : word) {
      if (c < '0' || c > '9') fail("bad " + std::string(what) + " " + quote(word) + ": expected a whole number");
      const auto d = static_cast<uint64_t>(c - '0');
      if (v > (UINT64_MAX - d) / 10)
        overflow = true;
      else
        v = v * 10 + d;
    }
    if (overflow || v < min || v > max) {
      fail(std::string(what) + " " + quote(word) + " out of range (" + std::to_string(min) + ".." +
           std::to_string(max) + ")");
    }
    return v;
  }

  // Exactly 16 lowercase hex digits (the only form the writer produces, so every value has one spelling
  // and no byte of the end line can change without the file being rejected).
  uint64_t hex(std::string_view word, std::string_view what) const {
    uint64_t v = 0;
    bool lowercase = true;
    for (char c : word) lowercase = lowercase && !(c >= 'A' && c <= 'F');
    if (!lowercase || !parseHex(word, &v)) {
      fail("bad " + std::string(what) + " " + quote(word) + ": expected 16 lowercase hex digits");
    }
    return v;
  }

  void readMagic() {
    expectFields(2, "treelearn-replay 1");
    const uint64_t version = number(fields_[1], 0, UINT64_MAX, "version");
    if (version != static_cast<uint64_t>(kReplayVersion)) {
      fail("unsupported replay version " + std::string(fields_[1]) + " (this build reads version 1)");
    }
    replay_.version = kReplayVersion;
  }

  // Reads one line after the magic; true once the end line has been read and checked.
  bool readBodyLine() {
    const std::string_view key = fields_[0];
    size_t headerPos = 0;
    while (headerPos < kHeaderKeys.size() && kHeaderKeys[headerPos] != key) ++headerPos;
    if (headerPos < kHeaderKeys.size()) {
      if (headerPos < headersRead_) fail("duplicate '" + std::string(key) + "' line");
      if (headerPos > headersRead_) {
        fail("missing '" + std::string(kHeaderKeys[headersRead_]) + "' line before '" + std::string(key) +
             "' (header order: " + std::string(kHeaderOrder) + ")");
      }
      readHeader(headerPos);
      ++headersRead_;
      return false;
    }
    if (key != "event" && key != "state" && key != "end") fail("unknown line type " + quote(key));
    if (headersRead_ < kHeaderKeys.size()) {
      fail("missing '" + std::string(kHeaderKeys[headersRead_]) + "' line before '" + std::string(key) + "'");
    }
    if (key == "event")
      readEvent();
    else if (key == "state")
      readState();
    else
      return readEnd();
    return false;
  }

  void readHeader(size_t which) {
    switch (which) {
      case 0:
        expectFields(3, "level <name> <16 hex digits>");
        replay_.level = std::string(fields_[1]);
        replay_.levelHash = hex(fields_[2], "level hash");
        break;
      case 1:
        expectFields(2, "robot <16 hex digits>");
        replay_.robotHash = hex(fields_[1], "robot hash");
        break;
      case 2:
        expectFields(2, "skills <16 hex digits>");
        replay_.skillsHash = hex(fields_[1], "skills hash");
        break;
      case 3:
        expectFields(2, "seed <number>");
        replay_.seed = number(fields_[1], 0, UINT64_MAX, "seed");
        break;
      case 4:
        expectFields(2, "ticks <number>");
        replay_.ticks = static_cast<int64_t>(number(fields_[1], 0, kMaxReplayTicks, "ticks"));
        break;
      default:
        expectFields(2, "hash_every <number>");
        replay_.hashEvery = static_cast<int>(number(fields_[1], 1, kMaxReplayHashEvery, "hash_every"));
        break;
    }
  }

  void readEvent() {
    expectFields(4, "event <tick> <down|up|tap> <key>");
    if (!replay_.states.empty()) fail("event line after state lines (all events come first)");
    const auto tick = static_cast<int64_t>(number(fields_[1], 0, kMaxReplayTicks, "event tick"));
    if (tick >= replay_.ticks) {
      fail("event tick " + std::to_string(tick) + " is not before the end of the recording (ticks " +
           std::to_string(replay_.ticks) + ")");
    }
    if (!replay_.events.empty() && tick < replay_.events.back().tick) {
      fail("event tick " + std::to_string(tick) + " is before the previous event's tick " +
           std::to_string(replay_.events.back().tick));
    }
    const std::optional<KeyAction> action = parseKeyAction(fields_[2]);
    if (!action) fail("unknown action " + quote(fields_[2]) + " (expected down, up or tap)");
    const std::optional<char> key = parseKeyName(fields_[3]);
    if (!key) fail("unknown key " + quote(fields_[3]) + " (expected 0-9, W, A, S, D, Q, E, R or F)");
    replay_.events.push_back(KeyEvent{tick, *action, *key});
  }

  void readState() {
    expectFields(3, "state <tick> <16 hex digits>");
    const auto tick = static_cast<int64_t>(number(fields_[1], 0, kMaxReplayTicks, "state tick"));
    if (tick > replay_.ticks) {
      fail("state tick " + std::to_string(tick) + " is after the end of the recording (ticks " +
           std::to_string(replay_.ticks) + ")");
    }
    if (tick % replay_.hashEvery != 0) {
      fail("state tick " + std::to_string(tick) + " is not a multiple of hash_every " +
           std::to_string(replay_.hashEvery));
    }
    if (!replay_.states.empty() && tick <= replay_.states.back().tick) {
      fail("state tick " + std::to_string(tick) + " does not follow the previous state tick " +
           std::to_string(replay_.states.back().tick) + " (must be strictly increasing)");
    }
    replay_.states.push_back(StateHash{tick, hex(fields_[2], "state hash")});
  }

  bool readEnd() {
    expectFields(2, "end <16 hex digits>");
    const uint64_t stored = hex(fields_[1], "checksum");
    if (stored != hashBytes(bytes_.substr(0, lineStart_))) fail("checksum mismatch: file was modified or corrupted");
    if (pos_ != bytes_.size()) {
      ++lineNumber_;
      fail("unexpected content after end line");
    }
    return true;
  }

  std::string_view bytes_;
  const std::string& fileName_;
  size_t pos_ = 0;         // start of the next line
  size_t lineStart_ = 0;   // start of the current line
  int lineNumber_ = 0;     // 1-based number of the current line
  std::string_view line_;  // current line without its '\n'
  std::vector<std::string_view> fields_;
  size_t headersRead_ = 0;  // header lines read so far (index into kHeaderKeys)
  Replay replay_;
};

// True if the level name fits on the level line: printable ASCII without spaces, short enough.
bool isWritableLevelName(const std::string& level) {
  if (level.empty() || level.size() > kMaxReplayLineLength - 32) return false;
  for (char c : level) {
    if (c <= 0x20 || c >= 0x7f) return false;
  }
  return true;
}

}  // namespace

bool operator==(const Replay& a, const Replay& b) {
  return a.version == b.version && a.level == b.level && a.levelHash == b.levelHash && a.robotHash == b.robotHash &&
         a.skillsHash == b.skillsHash && a.seed == b.seed && a.ticks == b.ticks && a.hashEvery == b.hashEvery &&
         a.events == b.events && a.states == b.states;
}

bool operator!=(const Replay& a, const Replay& b) { return !(a == b); }

std::string serializeReplay(const Replay& replay) {
  if (replay.version != kReplayVersion) {
    throw Error("replay: cannot write format version " + std::to_string(replay.version) + " (only version 1)");
  }
  if (!isWritableLevelName(replay.level)) {
    throw Error("replay: level name " + quote(replay.level) +
                " cannot be written (must be 1-992 printable ASCII characters without spaces)");
  }
  std::string out;
  out.reserve(200 + 24 * replay.events.size() + 32 * replay.states.size());
  out += std::string(kMagic) + " " + std::to_string(kReplayVersion) + "\n";
  out += "level " + replay.level + " " + toHex(replay.levelHash) + "\n";
  out += "robot " + toHex(replay.robotHash) + "\n";
  out += "skills " + toHex(replay.skillsHash) + "\n";
  out += "seed " + std::to_string(replay.seed) + "\n";
  out += "ticks " + std::to_string(replay.ticks) + "\n";
  out += "hash_every " + std::to_string(replay.hashEvery) + "\n";
  for (const KeyEvent& e : replay.events) out += "event " + formatKeyEvent(e) + "\n";
  for (const StateHash& s : replay.states) out += "state " + std::to_string(s.tick) + " " + toHex(s.hash) + "\n";
  out += "end " + toHex(hashBytes(out)) + "\n";
  return out;
}

Replay parseReplay(std::string_view bytes, const std::string& fileName) { return ReplayReader(bytes, fileName).read(); }

void saveReplay(const std::string& path, const Replay& replay) {
  std::string bytes;
  try {
    bytes = serializeReplay(replay);
    parseReplay(bytes, path);
  } catch (const Error& e) {
    throw Error(path + ": refusing to write an invalid replay: " + e.what());
  }
  writeFileAtomic(path, bytes);
}

Replay loadReplay(const std::string& path) { return parseReplay(readFile(path), path); }

}  // namespace engine
