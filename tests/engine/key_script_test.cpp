// key_script_test.cpp — key-script parsing: the documented example, comments, every error with its
// line number, and random bytes (must always be rejected cleanly, never crash).
#include "engine/input/key_script.h"

#include <gtest/gtest.h>

#include <random>
#include <string>

#include "engine/core/error.h"
#include "engine/input/input_timeline.h"

namespace engine {
namespace {

// Parses text expecting an engine::Error; returns its message ("" if nothing was thrown).
std::string parseError(const std::string& text) {
  try {
    parseKeyScript(text, "file.keys");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// Two valid lines, then `third` on line 3.
std::string withThirdLine(const std::string& third) { return "0.00 tap 0\n0.50 down W\n" + third + "\n"; }

TEST(KeyScript, ParsesTheDesignExampleIntoTicks) {
  const auto events = parseKeyScript("0.00 tap 0\n0.50 down W\n6.20 up W\n6.20 tap 1\n", "example.keys");
  ASSERT_EQ(events.size(), 4u);
  // 0.50 s / 0.01 s = tick 50; 6.20 s / 0.01 s = tick 620.
  EXPECT_EQ(events[0], (KeyEvent{0, KeyAction::kTap, '0'}));
  EXPECT_EQ(events[1], (KeyEvent{50, KeyAction::kDown, 'W'}));
  EXPECT_EQ(events[2], (KeyEvent{620, KeyAction::kUp, 'W'}));
  EXPECT_EQ(events[3], (KeyEvent{620, KeyAction::kTap, '1'}));
}

TEST(KeyScript, SkipsCommentsAndBlankLinesAndAcceptsTabsAndCrlf) {
  const std::string text =
      "# walk forward, then turn\n"
      "\n"
      "   \t \n"
      "0 tap 0   # start walking (comments may hold UTF-8: \xe5\x89\x8d\xe8\xbf\x9b)\n"
      "1.5\tdown\tw\r\n"
      "2. up w\n"
      "2.25 tap a";  // no final line break
  const auto events = parseKeyScript(text, "ok.keys");
  ASSERT_EQ(events.size(), 4u);
  EXPECT_EQ(events[0], (KeyEvent{0, KeyAction::kTap, '0'}));
  EXPECT_EQ(events[1], (KeyEvent{150, KeyAction::kDown, 'W'}));  // lowercase key becomes 'W'
  EXPECT_EQ(events[2], (KeyEvent{200, KeyAction::kUp, 'W'}));
  EXPECT_EQ(events[3], (KeyEvent{225, KeyAction::kTap, 'A'}));
  EXPECT_EQ(parseKeyScript(".5 tap 1", "short.keys").at(0).tick, 50);  // leading dot: 0.5 s
}

TEST(KeyScript, ASeedLineBeforeTheEventsGivesTheScriptsSeed) {
  const KeyScript s = parseKeyScriptWithSeed("# recorded at seed 26\nseed 26\n0.00 tap 0\n", "win.keys");
  ASSERT_TRUE(s.seed.has_value());
  EXPECT_EQ(*s.seed, 26u);
  EXPECT_EQ(s.seedLine, 2);
  ASSERT_EQ(s.events.size(), 1u);
  EXPECT_EQ(parseKeyScriptWithSeed("seed 18446744073709551615\n", "k").seed, UINT64_MAX);  // the largest 64-bit seed
  EXPECT_FALSE(parseKeyScriptWithSeed("0.00 tap 0\n", "k").seed.has_value());
  EXPECT_EQ(parseKeyScript("seed 26\n0.00 tap 0\n", "k").size(), 1u);  // the events alone
}

TEST(KeyScript, RejectsABadSecondOrLateSeedLine) {
  const auto seedError = [](const std::string& text) {
    try {
      parseKeyScriptWithSeed(text, "s.keys");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(seedError("seed 1\nseed 2\n"), "s.keys:2: a second seed line (the first is line 1)");
  EXPECT_EQ(seedError("0.00 tap 0\nseed 2\n"), "s.keys:2: the seed line must come before the first key event");
  EXPECT_EQ(seedError("seed\n"), "s.keys:1: expected 'seed <N>' (2 fields), got 1");
  EXPECT_EQ(seedError("seed 1 2\n"), "s.keys:1: expected 'seed <N>' (2 fields), got 3");
  for (const char* bad : {"-1", "+1", "1e3", "0x10", "2.5", "18446744073709551616", "x"})
    EXPECT_EQ(seedError(std::string("seed ") + bad + "\n"),
              std::string("s.keys:1: bad seed '") + bad + "' (expected a whole number from 0 to 18446744073709551615)")
        << bad;
}

TEST(KeyScript, EmptyScriptHasNoEvents) {
  EXPECT_TRUE(parseKeyScript("", "empty.keys").empty());
  EXPECT_TRUE(parseKeyScript("# nothing yet\n", "empty.keys").empty());
}

TEST(KeyScript, RoundsTimesToTheNearestTick) {
  // 0.014 s -> 1.4 ticks -> 1; 0.016 s -> 1.6 ticks -> 2; 86400 s -> 8640000 ticks.
  const auto events = parseKeyScript("0.014 tap 1\n0.016 tap 2\n86400 tap 3\n", "t.keys");
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].tick, 1);
  EXPECT_EQ(events[1].tick, 2);
  EXPECT_EQ(events[2].tick, 8640000);
}

TEST(KeyScript, EachErrorNamesItsLine) {
  const struct {
    std::string line;
    std::string what;
  } cases[] = {
      {"1.0 press W", "unknown action 'press'"},
      {"1.0 down X", "unknown key 'X'"},
      {"1.0 down WA", "unknown key 'WA'"},
      {"1.0 down", "3 fields"},
      {"1.0", "3 fields"},
      {"1.0 down A extra", "3 fields"},
      {"1e999 tap 1", "bad time '1e999'"},
      {"nan tap 1", "bad time 'nan'"},
      {"inf tap 1", "bad time 'inf'"},
      {"-1 tap 1", "negative time '-1'"},
      {"abc tap 1", "bad time 'abc'"},
      {"1.5x tap 1", "bad time '1.5x'"},
      {"1..5 tap 1", "bad time '1..5'"},
      {". tap 1", "bad time '.'"},
      {"86400.01 tap 1", "beyond the limit"},
      {"0.25 tap 1", "before the previous event's time 0.50"},
      {"1.0 up A", "'up A' but A is not held"},
      {"1.0 down W", "'down W' but W is already held"},
      {"1.0 tap W", "'tap W' but W is held"},
      {"1.0 tap \x01", "control byte 0x01"},
      {std::string("1.0 tap 1 # a\0b", 15), "NUL byte"},
      {"1.0 tap \xc3\xa9", "non-ASCII byte 0xc3"},
      {"1.0 tap 1 # bad utf-8 \xff", "invalid UTF-8 in comment"},
      {"1.0 tap 1\rx", "stray carriage return"},
      {"1.0 tap 1 #" + std::string(190, 'x'), "line too long (201 characters, limit 200)"},
  };
  for (const auto& c : cases) {
    const std::string message = parseError(withThirdLine(c.line));
    EXPECT_NE(message.find("file.keys:3: "), std::string::npos) << c.line << " -> " << message;
    EXPECT_NE(message.find(c.what), std::string::npos) << c.line << " -> " << message;
  }
}

TEST(KeyScript, LineOfExactly200CharactersIsAccepted) {
  const std::string line = "1.0 tap 1 #" + std::string(189, 'x');
  ASSERT_EQ(line.size(), 200u);
  EXPECT_EQ(parseKeyScript(line + "\n", "long.keys").size(), 1u);
}

TEST(KeyScript, RejectsMoreThan100000Events) {
  std::string text;
  for (int i = 0; i < 100000; ++i) text += "1 tap 1\n";
  EXPECT_EQ(parseKeyScript(text, "many.keys").size(), 100000u);
  text += "1 tap 1\n";
  const std::string message = parseError(text);
  EXPECT_NE(message.find("file.keys:100001: too many events (limit 100000)"), std::string::npos) << message;
}

TEST(KeyScript, TapAfterReleaseAndDownAfterTapAreAllowed) {
  const auto events = parseKeyScript("0 tap R\n0 down R\n1 up R\n1 tap R\n", "t.keys");
  EXPECT_EQ(events.size(), 4u);
}

TEST(KeyScript, RandomBytesAlwaysThrowErrorAndNeverCrash) {
  std::mt19937 rng(12345);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> length(32, 600);
  for (int i = 0; i < 200; ++i) {
    std::string buffer(static_cast<size_t>(length(rng)), '\0');
    for (char& c : buffer) c = static_cast<char>(byte(rng));
    EXPECT_THROW(parseKeyScript(buffer, "random.keys"), Error) << "buffer " << i;
  }
}

TEST(KeyScript, AWrittenScriptReadsBackAsTheSameEventsAndSeed) {
  const std::vector<KeyEvent> events = {{0, KeyAction::kTap, '0'},
                                        {50, KeyAction::kDown, 'W'},
                                        {698, KeyAction::kTap, '1'},
                                        {1318, KeyAction::kUp, 'W'},
                                        {8640000, KeyAction::kTap, 'F'}};
  const std::string text = formatKeyScript(events, 26, "recorded by the autopilot\nat seed 26");
  EXPECT_EQ(text.substr(0, 60), "# recorded by the autopilot\n# at seed 26\nseed 26\n0.00 tap 0\n");
  EXPECT_NE(text.find("\n6.98 tap 1\n13.18 up W\n86400.00 tap F\n"), std::string::npos) << text;
  const KeyScript back = parseKeyScriptWithSeed(text, "written.keys");
  EXPECT_EQ(back.events, events);
  EXPECT_EQ(back.seed, std::optional<uint64_t>(26));
  // a header that would not read back as comments (a control byte, a 300-character path) is made readable
  const std::string odd = formatKeyScript(events, 1, "runs/\x01" + std::string(300, 'x') + ".replay");
  EXPECT_EQ(parseKeyScriptWithSeed(odd, "odd.keys").events, events);
  EXPECT_EQ(odd.find('\x01'), std::string::npos);
}

TEST(KeyScript, FormatsEventsWithTheirTick) {
  EXPECT_EQ(formatKeyEvent(KeyEvent{123, KeyAction::kDown, 'W'}), "123 down W");
  EXPECT_EQ(formatKeyEvent(KeyEvent{0, KeyAction::kTap, '7'}), "0 tap 7");
  EXPECT_EQ(formatKeyEvent(KeyEvent{9, KeyAction::kUp, 'F'}), "9 up F");
}

TEST(KeyScript, ActionAndKeyNameHelpers) {
  EXPECT_EQ(parseKeyAction("down"), KeyAction::kDown);
  EXPECT_EQ(parseKeyAction("tap"), KeyAction::kTap);
  EXPECT_FALSE(parseKeyAction("Down").has_value());
  EXPECT_EQ(keyActionName(KeyAction::kUp), "up");
  EXPECT_EQ(parseKeyName("q"), 'Q');
  EXPECT_EQ(parseKeyName("9"), '9');
  EXPECT_FALSE(parseKeyName("x").has_value());
  EXPECT_FALSE(parseKeyName("").has_value());
  EXPECT_TRUE(isValidKey('R'));
  EXPECT_FALSE(isValidKey('r'));
}

TEST(InputTimeline, DeliversEachTicksEventsOnceInFileOrder) {
  InputTimeline timeline(parseKeyScript("0.00 tap 0\n0.50 down W\n6.20 up W\n6.20 tap 1\n", "t.keys"));
  EXPECT_EQ(timeline.eventsAt(0).size(), 1u);
  EXPECT_TRUE(timeline.eventsAt(0).empty());  // consumed
  for (int64_t t = 1; t < 50; ++t) EXPECT_TRUE(timeline.eventsAt(t).empty());
  EXPECT_EQ(timeline.eventsAt(50), (std::vector<KeyEvent>{{50, KeyAction::kDown, 'W'}}));
  EXPECT_FALSE(timeline.done());
  const std::vector<KeyEvent> at620 = {{620, KeyAction::kUp, 'W'}, {620, KeyAction::kTap, '1'}};
  EXPECT_EQ(timeline.eventsAt(620), at620);
  EXPECT_TRUE(timeline.done());
  EXPECT_EQ(timeline.remaining(), 0u);
}

TEST(InputTimeline, SortsUnorderedInputStably) {
  InputTimeline timeline({{5, KeyAction::kTap, '2'}, {1, KeyAction::kTap, '1'}, {5, KeyAction::kTap, '3'}});
  EXPECT_EQ(timeline.eventsAt(1), (std::vector<KeyEvent>{{1, KeyAction::kTap, '1'}}));
  const std::vector<KeyEvent> at5 = {{5, KeyAction::kTap, '2'}, {5, KeyAction::kTap, '3'}};
  EXPECT_EQ(timeline.eventsAt(5), at5);
}

}  // namespace
}  // namespace engine
