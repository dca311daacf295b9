// entry_state_test.cpp — play's handover states: recorded at every switch, written and read back exactly, refused
// at their line when broken, restored into a session that goes on as the recorded run did, and the play-entry card.
#include "robot/entry_state.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/core/error.h"
#include "engine/input/input_timeline.h"
#include "game/entry_card.h"
#include "game/entry_recorder.h"
#include "game/play.h"
#include "robot/skill_tree.h"
#include "tests/fixtures.h"

namespace {

using fixtures::kSource;

// walk (key 0) and squat (key 3) from the shipped tree, both holding the default pose (zero action) with the walk's
// gait prior taken out: a robot that stands still, so that its state after a restore can be compared to the run's
robot::SkillSet standingSet() {
  const robot::SkillTree shipped = robot::loadSkillTree(kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  robot::SkillSet set;
  for (const char* name : {"walk", "squat"}) {
    robot::SkillDef d = *shipped.find(name);
    d.prior.kind = robot::PriorDef::Kind::None;
    set.skills.push_back({d, [](const Eigen::MatrixXf&, Eigen::MatrixXf* a) { a->setZero(robot::kActionSize, 1); }});
  }
  return set;
}

const levels::Level& flat() {
  static const levels::Level l = levels::loadLevel(kSource + "/levels/flat");
  return l;
}

// walk at 0, squat at 1.5 s with R held from 2 s to 2.5 s, back to walk at 4 s; recorded on levels/flat
struct Recorded {
  robot::SkillSet set = standingSet();
  game::PlayResult result;
  std::vector<robot::EntryState> entries;
};
const Recorded& recorded() {
  static const Recorded r = [] {
    Recorded out;
    game::EntryRecorder recorder(kSource + "/levels/flat", "test.keys", 7);
    game::PlayOptions po;
    po.seed = 7;
    po.ticks = 500;
    po.skills = &out.set;
    po.events = engine::parseKeyScript("0 tap 0\n1.5 tap 3\n2.0 down R\n2.5 up R\n4.0 tap 0\n", "test.keys");
    po.entries = &recorder;
    out.result = game::play(flat(), fixtures::robotModel(), po);
    out.entries = recorder.entries();
    return out;
  }();
  return r;
}

std::string errorOf(const std::string& text) {
  try {
    robot::parseEntries(text, "t.entries");
  } catch (const engine::Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(EntryRecorder, OpensAnEntryAtEverySwitchAndClosesItAtTheNext) {
  const Recorded& r = recorded();
  const std::vector<game::SwitchEvent>& sw = r.result.telemetry.switches;
  ASSERT_EQ(r.entries.size(), sw.size());  // stand -> walk, walk -> squat, squat -> walk
  ASSERT_EQ(r.entries.size(), 3u);
  for (size_t i = 0; i < sw.size(); ++i) {
    EXPECT_EQ(r.entries[i].skill, sw[i].to);
    EXPECT_EQ(r.entries[i].tick, sw[i].tick);
    EXPECT_FALSE(r.entries[i].fellInPlay);
    // a segment runs to the next switch (the last one to the run's end)
    const int64_t end = i + 1 < sw.size() ? sw[i + 1].tick : r.result.ticks - 1;
    EXPECT_EQ(r.entries[i].tick + r.entries[i].segmentTicks, end) << i;
  }
  // the squat's segment holds R's two events (at 2.0 s and 2.5 s) and the tap back to walk at 4.0 s
  const std::vector<engine::KeyEvent>& ev = r.entries[1].events;
  ASSERT_EQ(ev.size(), 3u);
  EXPECT_EQ(ev[0].tick, 200);
  EXPECT_EQ(ev[0].key, 'R');
  EXPECT_EQ(ev[1].tick, 250);
  EXPECT_EQ(ev[2].key, '0');
  EXPECT_EQ(r.entries[1].fadingFrom, "walk");
  EXPECT_EQ(r.entries[1].source, "test.keys");
  EXPECT_EQ(r.entries[1].seed, 7u);
}

TEST(EntryFile, WritingAndReadingBackIsExact) {
  const std::vector<robot::EntryState>& e = recorded().entries;
  const std::string text = robot::formatEntries(e);
  const std::vector<robot::EntryState> back = robot::parseEntries(text, "t.entries");
  ASSERT_EQ(back.size(), e.size());
  EXPECT_EQ(robot::formatEntries(back), text);
  for (size_t i = 0; i < e.size(); ++i) {
    EXPECT_EQ(back[i].body.basePosition, e[i].body.basePosition);
    EXPECT_EQ(back[i].body.qd, e[i].body.qd);
    EXPECT_EQ(back[i].runtime.action, e[i].runtime.action);
    EXPECT_EQ(back[i].keys.amplitude, e[i].keys.amplitude);
    EXPECT_EQ(back[i].events, e[i].events);
  }
}

TEST(EntryFile, BrokenEntriesAreRefusedAtTheirLine) {
  const std::string good = robot::formatEntries({recorded().entries[1]});
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    const size_t at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return t.replace(at, from.size(), to);
  };
  auto lineOf = [&](const std::string& field) {
    const size_t at = good.find("\n  " + field + " ");
    return 1 + std::count(good.begin(), good.begin() + long(at) + 1, '\n');
  };
  EXPECT_NE(errorOf("hello\n").find("t.entries:1: not an entries file"), std::string::npos);
  EXPECT_NE(errorOf(replaced("  seed 7\n", "")).find("has no 'seed' line"), std::string::npos);
  EXPECT_NE(errorOf(replaced("  fade_ticks ", "  fade_ticks nan "))
                .find("t.entries:" + std::to_string(lineOf("fade_ticks")) + ": fade_ticks: expected 1 value, found 2"),
            std::string::npos)
      << errorOf(replaced("  fade_ticks ", "  fade_ticks nan "));
  const std::string qd = "  qd ";
  EXPECT_NE(errorOf(replaced(qd, qd + "1e999 ")).find(":" + std::to_string(lineOf("qd")) + ": qd: expected 23 values"),
            std::string::npos);
  EXPECT_NE(errorOf(replaced("  level ", "  colour red\n  level ")).find("colour: unknown field"), std::string::npos);
  EXPECT_NE(errorOf(replaced("up R", "up Z")).find("'Z' is not a key"), std::string::npos);
  EXPECT_NE(errorOf(replaced("end\n", "")).find("has no 'end'"), std::string::npos);
  EXPECT_NE(errorOf(replaced("  tick ", "  tick 5\n  tick ")).find("given twice"), std::string::npos);
  // a seed past 2^64 - 1 was read as 2^64 - 1 (strtoull saturates), and "+7" as 7
  EXPECT_NE(errorOf(replaced("  seed 7\n", "  seed 99999999999999999999999\n"))
                .find(":" + std::to_string(lineOf("seed")) +
                      ": seed: '99999999999999999999999' is larger than the largest seed"),
            std::string::npos);
  EXPECT_NE(errorOf(replaced("  seed 7\n", "  seed +7\n")).find("'+7' is not a seed"), std::string::npos);
  EXPECT_EQ(errorOf(replaced("  seed 7\n", "  seed 18446744073709551615\n")), "(no error)");
}

TEST(EntryState, ARestoredEntryGoesOnAsTheRecordedRunDid) {
  // the squat's entry, restored into a fresh session of the level, with its segment's keys: after 2 s the robot is
  // where the recorded run had it (Bullet's contact caches start empty, so not to the bit: within a millimetre)
  const Recorded& r = recorded();
  const robot::EntryState& e = r.entries[1];
  game::Session s(flat(), fixtures::robotModel(), game::SessionOptions{e.seed, &r.set});
  s.restoreEntry(e);
  EXPECT_EQ(s.activeSkillName(), "squat");
  EXPECT_EQ(s.tick(), e.tick + 1);
  EXPECT_EQ(s.sensors().basePosition, e.body.basePosition);
  engine::InputTimeline keys(e.events);
  while (s.tick() < 300) s.step(keys.eventsAt(s.tick()));
  // the recorded run's pelvis at 3.0 s, from its 50 Hz log (the centre of mass there; compare the same measure)
  const game::ComSample* at = nullptr;
  for (const game::ComSample& c : r.result.comLog)
    if (std::abs(c.t - 3.0) < 1e-9) at = &c;
  ASSERT_NE(at, nullptr);
  EXPECT_NEAR(s.sensors().centreOfMass.x(), at->x, 1e-3);
  EXPECT_NEAR(s.sensors().centreOfMass.z(), at->z, 1e-3);
  EXPECT_NEAR(s.command().amplitude, 0.5, 1e-9);  // R held 0.5 s at 0.01 a tick, replayed from the segment's events
}

TEST(EntryState, ARestoreCarriesTheVelocitiesTheKeysAndTheRuntime) {
  const Recorded& r = recorded();
  robot::EntryState e = r.entries[2];
  e.body.baseLinearVelocity = Eigen::Vector3d(0.3, -0.1, 0.0);
  e.body.qd[3] = 1.5;  // left knee
  e.keys.vx = 0.4, e.keys.keysHeld = engine::keyMask('W');
  e.runtime.phase.tp = 17;
  e.runtime.action[5] = 0.25f;
  game::Session s(flat(), fixtures::robotModel(), game::SessionOptions{e.seed, &r.set});
  s.restoreEntry(e);
  const robot::Sensors& sensed = s.sensors();
  EXPECT_NEAR((sensed.baseRotation * sensed.linearVelocity - e.body.baseLinearVelocity).norm(), 0.0, 1e-6);
  EXPECT_NEAR(sensed.qd[3], 1.5, 1e-9);
  EXPECT_EQ(s.command().vx, 0.4);
  EXPECT_EQ(s.command().keysHeld, engine::keyMask('W'));
  EXPECT_EQ(s.runtime().phase.tp, 17);
  EXPECT_EQ(s.runtime().action[5], 0.25f);
  EXPECT_EQ(s.runtime().active, r.set.byName("walk"));
  EXPECT_EQ(s.runtime().fadingFrom, r.set.byName("squat"));
  // an entry of a skill the set does not hold is refused, naming it
  e.skill = "crawl";
  game::Session other(flat(), fixtures::robotModel(), game::SessionOptions{e.seed, &r.set});
  try {
    other.restoreEntry(e);
    ADD_FAILURE() << "no error";
  } catch (const engine::Error& err) {
    EXPECT_NE(std::string(err.what()).find("hands over to 'crawl', which is not among the loaded skills"),
              std::string::npos)
        << err.what();
  }
}

TEST(EntryCard, AStandingSkillHoldsAndARobotPutDownOnTheGroundFallsAtOnce) {
  const Recorded& r = recorded();
  const game::EntryCardResult held = game::runEntryCard(r.entries, "walk", r.set, fixtures::robotModel(), 2);
  ASSERT_EQ(held.trials.size(), 2u);
  EXPECT_EQ(held.held(), 2);
  EXPECT_TRUE(held.trials[0].handedOver);   // its segment's keys asked for the squat
  EXPECT_FALSE(held.trials[1].handedOver);  // the last one drove its segment and the margin
  EXPECT_EQ(held.trials[1].ticks, r.entries[2].segmentTicks + game::kEntryCardMarginTicks);
  // the same entry with the robot lying on its back, the pelvis 0.15 m up: down in the first tick
  std::vector<robot::EntryState> lying = {r.entries[2]};
  lying[0].body.basePosition.z() = 0.15;
  lying[0].body.baseRotation = Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitY()));
  const game::EntryCardResult fell = game::runEntryCard(lying, "walk", r.set, fixtures::robotModel(), 1);
  ASSERT_EQ(fell.trials.size(), 1u);
  EXPECT_TRUE(fell.trials[0].fell);
  EXPECT_EQ(fell.trials[0].ticks, 0);
  EXPECT_EQ(fell.percent(), 0.0);
}
