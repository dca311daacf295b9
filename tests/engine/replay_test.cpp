// replay_test.cpp — replay text format: round trip, save/load, truncation at every byte, random and
// single-byte-corrupted input (always engine::Error, never a crash), and each structural error's line.
#include "engine/replay/replay.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <string>

#include "engine/core/error.h"
#include "engine/core/hash.h"

namespace engine {
namespace {

Replay sampleReplay() {
  Replay r;
  r.level = "levels/flat";
  r.levelHash = 0x0123456789abcdefull;
  r.robotHash = 0xfedcba9876543210ull;
  r.skillsHash = 0x00000000000000ffull;
  r.seed = 42;
  r.ticks = 6000;
  r.hashEvery = 50;
  r.events = {{0, KeyAction::kTap, '0'},   {50, KeyAction::kDown, 'W'},  {620, KeyAction::kUp, 'W'},
              {620, KeyAction::kTap, '1'}, {700, KeyAction::kDown, 'R'}, {5999, KeyAction::kUp, 'R'}};
  for (int64_t t = 50; t <= 300; t += 50) r.states.push_back({t, 0x1000000000000000ull + static_cast<uint64_t>(t)});
  return r;
}

// Appends the end line with the correct checksum, so a test can isolate one structural error.
std::string sealed(const std::string& body) { return body + "end " + toHex(hashBytes(body)) + "\n"; }

// Lines 1..7: magic and the six header lines.
const char* const kHeader =
    "treelearn-replay 1\n"
    "level levels/flat 0123456789abcdef\n"
    "robot 00000000000000aa\n"
    "skills 00000000000000bb\n"
    "seed 42\n"
    "ticks 6000\n"
    "hash_every 50\n";

std::string parseError(const std::string& bytes) {
  try {
    parseReplay(bytes, "r.replay");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Replay, SerializesTheDocumentedLayout) {
  const std::string text = serializeReplay(sampleReplay());
  const std::string expectedStart =
      "treelearn-replay 1\n"
      "level levels/flat 0123456789abcdef\n"
      "robot fedcba9876543210\n"
      "skills 00000000000000ff\n"
      "seed 42\n"
      "ticks 6000\n"
      "hash_every 50\n"
      "event 0 tap 0\n"
      "event 50 down W\n";
  EXPECT_EQ(text.substr(0, expectedStart.size()), expectedStart);
  const size_t endLine = text.rfind("end ");
  EXPECT_EQ(text.substr(endLine), "end " + toHex(hashBytes(text.substr(0, endLine))) + "\n");
  EXPECT_NE(text.find("\nstate 300 100000000000012c\nend "), std::string::npos);  // 300 = 0x12c
}

TEST(Replay, RoundTripsExactly) {
  const Replay original = sampleReplay();
  const std::string text = serializeReplay(original);
  const Replay parsed = parseReplay(text, "r.replay");
  EXPECT_EQ(parsed, original);
  EXPECT_EQ(serializeReplay(parsed), text);

  Replay edge;  // extremes of every range
  edge.level = "x";
  edge.seed = UINT64_MAX;
  edge.ticks = kMaxReplayTicks;
  edge.hashEvery = kMaxReplayHashEvery;
  edge.events = {{kMaxReplayTicks - 1, KeyAction::kTap, '9'}};
  edge.states = {{0, 0}, {kMaxReplayTicks / kMaxReplayHashEvery * kMaxReplayHashEvery, UINT64_MAX}};
  EXPECT_EQ(parseReplay(serializeReplay(edge), "edge.replay"), edge);

  Replay empty;  // zero-length recording, no events, no states
  empty.level = "levels/empty";
  EXPECT_EQ(parseReplay(serializeReplay(empty), "empty.replay"), empty);
}

TEST(Replay, SavesAtomicallyAndLoadsBack) {
  const std::string path = ::testing::TempDir() + "treelearn_replay_test.replay";
  saveReplay(path, sampleReplay());
  EXPECT_EQ(loadReplay(path), sampleReplay());

  Replay bad = sampleReplay();
  bad.events.push_back({6000, KeyAction::kTap, '2'});  // tick == ticks: not writable
  EXPECT_THROW(saveReplay(path, bad), Error);
  EXPECT_EQ(loadReplay(path), sampleReplay());  // the earlier file is untouched
  std::remove(path.c_str());
  EXPECT_THROW(loadReplay(path), Error);
}

TEST(Replay, RefusesToSerializeUnwritableLevelNames) {
  Replay r = sampleReplay();
  r.level = "my level";
  EXPECT_THROW(serializeReplay(r), Error);
  r.level = "";
  EXPECT_THROW(serializeReplay(r), Error);
  r.level = "levels/\n";
  EXPECT_THROW(serializeReplay(r), Error);
  r.level = "ok";
  r.version = 2;
  EXPECT_THROW(serializeReplay(r), Error);
}

TEST(Replay, TruncationAtEveryByteIsReportedAsTruncated) {
  const std::string text = serializeReplay(sampleReplay());
  EXPECT_NE(parseError("").find("r.replay: empty file"), std::string::npos);
  for (size_t n = 1; n < text.size(); ++n) {
    const std::string message = parseError(text.substr(0, n));
    EXPECT_NE(message.find("truncated"), std::string::npos) << "cut at " << n << ": " << message;
  }
  const size_t lastNewline = text.size() - 1;
  EXPECT_NE(parseError(text.substr(0, lastNewline)).find("r.replay:20: truncated: missing newline after end line"),
            std::string::npos);
  const size_t endLine = text.rfind("end ");
  EXPECT_NE(parseError(text.substr(0, endLine)).find("r.replay:20: truncated: missing end line"), std::string::npos);
}

TEST(Replay, RandomBytesAlwaysThrowError) {
  std::mt19937 rng(2024);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> length(0, 2000);
  for (int i = 0; i < 500; ++i) {
    std::string buffer(static_cast<size_t>(length(rng)), '\0');
    for (char& c : buffer) c = static_cast<char>(byte(rng));
    EXPECT_THROW(parseReplay(buffer, "random.replay"), Error) << "buffer " << i;
  }
  // Past the magic: a valid header followed by random printable lines.
  std::uniform_int_distribution<int> printable(0x20, 0x7f);  // 0x7f stands for '\n'
  for (int i = 0; i < 500; ++i) {
    std::string buffer = kHeader;
    const int n = length(rng);
    for (int k = 0; k < n; ++k) {
      const int c = printable(rng);
      buffer += c == 0x7f ? '\n' : static_cast<char>(c);
    }
    EXPECT_THROW(parseReplay(buffer, "random.replay"), Error) << "buffer " << i;
  }
}

TEST(Replay, EverySingleByteCorruptionIsCaught) {
  const std::string text = serializeReplay(sampleReplay());
  std::mt19937 rng(7);
  std::uniform_int_distribution<size_t> position(0, text.size() - 1);
  std::uniform_int_distribution<int> delta(1, 255);
  for (int i = 0; i < 500; ++i) {
    std::string corrupted = text;
    const size_t p = position(rng);
    corrupted[p] = static_cast<char>(static_cast<unsigned char>(corrupted[p]) + delta(rng));  // always a different byte
    EXPECT_THROW(parseReplay(corrupted, "c.replay"), Error) << "byte " << p;
  }
  // A corruption that keeps the structure valid is caught by the checksum alone: seed 42 -> 43 (line 5).
  std::string edited = text;
  edited[edited.find("seed 42") + 6] = '3';
  EXPECT_NE(parseError(edited).find("r.replay:20: checksum mismatch: file was modified or corrupted"),
            std::string::npos);
}

TEST(Replay, EachStructuralErrorNamesItsLine) {
  const std::string h = kHeader;
  const struct {
    std::string bytes;
    std::string expected;
  } cases[] = {
      {sealed("treelearn-replay2 1\n"), "r.replay:1: not a treelearn replay"},
      {sealed("PK\x03\x04 zip"), "r.replay:1: not a treelearn replay"},
      {sealed("treelearn-replay 2\n"), "r.replay:1: unsupported replay version 2"},
      {sealed("treelearn-replay 1 x\n"), "r.replay:1: expected 'treelearn-replay 1'"},
      {sealed("treelearn-replay 1\nrobot 00000000000000aa\n"), "r.replay:2: missing 'level' line before 'robot'"},
      {sealed("treelearn-replay 1\nlevel a 0123456789abcdef\nlevel a 0123456789abcdef\n"),
       "r.replay:3: duplicate 'level' line"},
      {sealed("treelearn-replay 1\nlevel a 0123456789abcdef\nseed 1\n"),
       "r.replay:3: missing 'robot' line before 'seed'"},
      {sealed("treelearn-replay 1\nlevel a 0123456789abcdef\nevent 0 tap 0\n"),
       "r.replay:3: missing 'robot' line before 'event'"},
      {sealed("treelearn-replay 1\nlevel a 0123456789abcdeg\n"), "r.replay:2: bad level hash '0123456789abcdeg'"},
      {sealed("treelearn-replay 1\nlevel a 0123456789abcde\n"), "r.replay:2: bad level hash"},
      {sealed("treelearn-replay 1\nlevel a\n"), "r.replay:2: expected 'level <name> <16 hex digits>'"},
      {sealed("treelearn-replay 1\nlevel a 0123456789abcdef\nrobot xyz\n"), "r.replay:3: bad robot hash 'xyz'"},
      {sealed(h + "seed 1\n"), "r.replay:8: duplicate 'seed' line"},
      {sealed(h + "event 0 tap 0\nhash_every 50\n"), "r.replay:9: duplicate 'hash_every' line"},
      {sealed(h + "bogus 1\n"), "r.replay:8: unknown line type 'bogus'"},
      {sealed(h + "\n"), "r.replay:8: malformed line"},
      {sealed(h + "event 0  tap 0\n"), "r.replay:8: malformed line"},
      {sealed(h + "event 0 tap 0 \n"), "r.replay:8: malformed line"},
      {sealed(h + "event 0 tap\n"), "r.replay:8: expected 'event <tick> <down|up|tap> <key>'"},
      {sealed(h + "event 10 tap 0\nevent 9 tap 0\n"),
       "r.replay:9: event tick 9 is before the previous event's tick 10"},
      {sealed(h + "event 6000 tap 0\n"), "r.replay:8: event tick 6000 is not before the end of the recording"},
      {sealed(h + "event -1 tap 0\n"), "r.replay:8: negative event tick '-1'"},
      {sealed(h + "event 1x tap 0\n"), "r.replay:8: bad event tick '1x'"},
      {sealed(h + "event 1 hold 0\n"), "r.replay:8: unknown action 'hold'"},
      {sealed(h + "event 1 tap Z\n"), "r.replay:8: unknown key 'Z'"},
      {sealed(h + "state 50 0000000000000001\nevent 60 tap 0\n"), "r.replay:9: event line after state lines"},
      {sealed(h + "state 50 0000000000000001\nstate 50 0000000000000002\n"),
       "r.replay:9: state tick 50 does not follow the previous state tick 50"},
      {sealed(h + "state 100 0000000000000001\nstate 50 0000000000000002\n"),
       "r.replay:9: state tick 50 does not follow"},
      {sealed(h + "state 75 0000000000000001\n"), "r.replay:8: state tick 75 is not a multiple of hash_every 50"},
      {sealed(h + "state 6050 0000000000000001\n"), "r.replay:8: state tick 6050 is after the end of the recording"},
      {sealed(h + "state 50 00000000000000zz\n"), "r.replay:8: bad state hash"},
      {sealed(h + "state 50\n"), "r.replay:8: expected 'state <tick> <16 hex digits>'"},
      {h + "end 0000000000000000\n", "r.replay:8: checksum mismatch: file was modified or corrupted"},
      {h + "end 00000000\n", "r.replay:8: bad checksum '00000000'"},
      {h + "end\n", "r.replay:8: expected 'end <16 hex digits>'"},
      {sealed(h) + "event 1 tap 0\n", "r.replay:9: unexpected content after end line"},
      {sealed(h) + "\n", "r.replay:9: unexpected content after end line"},
      {h, "r.replay:8: truncated: missing end line"},
      {h + "event 1 tap 0\nstate 50 0000000000000001\n", "r.replay:10: truncated: missing end line"},
      {sealed("treelearn-replay 1\nlevel a 0123456789abcdef\nrobot 00000000000000aa\nskills 00000000000000bb\n"
              "seed -5\n"),
       "r.replay:5: negative seed '-5'"},
      {sealed("treelearn-replay 1\nlevel a 0123456789abcdef\nrobot 00000000000000aa\nskills 00000000000000bb\n"
              "seed 18446744073709551616\n"),
       "r.replay:5: seed '18446744073709551616' out of range"},
      {sealed("treelearn-replay 1\nlevel a 0123456789abcdef\nrobot 00000000000000aa\nskills 00000000000000bb\n"
              "seed 1\nticks 8640001\n"),
       "r.replay:6: ticks '8640001' out of range (0..8640000)"},
      {sealed("treelearn-replay 1\nlevel a 0123456789abcdef\nrobot 00000000000000aa\nskills 00000000000000bb\n"
              "seed 1\nticks 10\nhash_every 0\n"),
       "r.replay:7: hash_every '0' out of range (1..1000000)"},
      {sealed("treelearn-replay 1\nlevel a 0123456789abcdef\nrobot 00000000000000aa\nskills 00000000000000bb\n"
              "seed 1\nticks 10\nhash_every 1000001\n"),
       "r.replay:7: hash_every '1000001' out of range"},
      {sealed(h + "event 1 tap 0 " + std::string(1100, 'x') + "\n"), "r.replay:8: line too long"},
      {sealed(std::string("treelearn-replay 1\nlevel a\0", 27)), "r.replay: byte 26: NUL byte"},
      {sealed(h + "state 50 000000000000000A\n"), "r.replay:8: bad state hash '000000000000000A'"},
      {sealed("treelearn-replay 1\r\n"), "r.replay: byte 18: carriage return"},
      {sealed("treelearn-replay 1\nlevel caf\xc3\xa9 0123456789abcdef\n"), "r.replay: byte 28: non-ASCII byte 0xc3"},
      {sealed("treelearn-replay 1\nlevel a\tb 0123456789abcdef\n"), "r.replay: byte 26: control byte 0x09"},
  };
  for (const auto& c : cases) {
    const std::string message = parseError(c.bytes);
    EXPECT_NE(message.find(c.expected), std::string::npos) << "expected: " << c.expected << "\n     got: " << message;
  }
}

TEST(Replay, AcceptsSeedAtUint64MaxAndStateAtTickZero) {
  const Replay r = parseReplay(
      sealed("treelearn-replay 1\nlevel a 0123456789abcdef\nrobot 00000000000000aa\nskills 00000000000000bb\n"
             "seed 18446744073709551615\nticks 100\nhash_every 50\nevent 0 down W\nevent 0 up W\n"
             "state 0 0000000000000001\nstate 100 0000000000000002\n"),
      "r.replay");
  EXPECT_EQ(r.seed, UINT64_MAX);
  EXPECT_EQ(r.events.size(), 2u);
  EXPECT_EQ(r.states.back(), (StateHash{100, 2}));
}

}  // namespace
}  // namespace engine
