// cli_test.cpp — the treelearn program end to end: exit codes, messages, replays and outputs on disk.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "ai/ppo/checkpoint.h"
#include "engine/core/file_io.h"
#include "tests/cli_run.h"

namespace {

namespace fs = std::filesystem;
using cli::kSource;

using cli::CliRun;
using cli::run;
using cli::shell;
std::string tempDir(const std::string& name) { return cli::tempDir("cli", name); }

// every regular file of a folder (recursively) with a hash of its bytes and its modification time
std::map<std::string, std::pair<size_t, fs::file_time_type>> snapshot(const std::string& dir) {
  std::map<std::string, std::pair<size_t, fs::file_time_type>> files;
  for (const auto& f : fs::recursive_directory_iterator(dir))
    if (f.is_regular_file())
      files[fs::relative(f.path(), dir).string()] = {std::hash<std::string>()(engine::readFile(f.path())),
                                                     f.last_write_time()};
  return files;
}

// a folder holding a copy of the skill tree whose squat card runs `episodes` episodes (2: a few seconds), with
// `edit` applied to the squat card's table; the shipped models are not copied
std::string squatTree(const std::string& name, int episodes, const std::pair<std::string, std::string>& edit = {}) {
  const std::string d = tempDir(name) + "/skills";
  fs::create_directories(d);
  std::string tree = engine::readFile(kSource + "/assets/skills/tree.toml");
  const size_t card = tree.find("[skill.squat.card]");
  const size_t count = tree.find("episodes = 20\n", card);
  if (card == std::string::npos || count == std::string::npos) return "";
  tree.replace(count, 14, "episodes = " + std::to_string(episodes) + "\n");
  if (!edit.first.empty()) {
    const size_t at = tree.find(edit.first, card);
    if (at == std::string::npos) return "";
    tree.replace(at, edit.first.size(), edit.second);
  }
  engine::writeFileAtomic(d + "/tree.toml", tree);
  return d;
}

// a run folder holding squat.onnx and squat.policy.bin as `train squat` exports them (the shipped squat's files)
std::string squatRun(const std::string& parent) {
  const std::string run = parent + "/run";
  fs::create_directories(run);
  for (const char* f : {"squat.onnx", "squat.policy.bin"})
    fs::copy_file(kSource + "/assets/skills/" + f, run + "/" + f);
  return run;
}

}  // namespace

TEST(Cli, HelpListsTheCommands) {
  const CliRun r = run("--help");
  EXPECT_EQ(r.code, 0);
  for (const char* c : {"play", "replay", "bench", "train", "eval", "ship", "tree"})
    EXPECT_NE(r.out.find(c), std::string::npos) << c;
}

TEST(Cli, FlatSquareScriptStaysAlive) {
  const CliRun r = run("play levels/flat --keys square.keys --expect alive");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("expectation 'alive' met"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("requested keys: 0"), std::string::npos) << r.out;
}

TEST(Cli, ProneScriptLiesDownWithoutAFall) {
  // walk, stop, prone: lying face down is the prone skill's job, not a fall (its own termination judges it)
  const CliRun r = run("play levels/flat --keys prone.keys --seconds 9 --expect alive");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("walk->prone"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("min 0.1"), std::string::npos) << r.out;  // the pelvis went down to ~0.12 m
}

TEST(Cli, KeyZeroWhileLyingStandsUpAndTheWalkGoesOn) {
  // walk, prone, then 0 while lying: routed through the stand-up (keyless), the walk once the robot stands
  const CliRun r = run("play levels/flat --keys up_again.keys --seconds 19 --expect alive");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("walk->prone"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("prone->standup at 7.50 s"), std::string::npos) << r.out;  // the key's tick: lying, at once
  EXPECT_NE(r.out.find("standup->walk at 12."), std::string::npos) << r.out;      // standing ~4.6-5 s later
  EXPECT_NE(r.out.find("requested keys: 0, 7"), std::string::npos) << r.out;
}

TEST(Cli, KeyEightLiesDownFirstThenPushesUpAndKeyZeroStandsBackUp) {
  // walk, then 8: routed walk -> prone -> pushup, the push-ups only once the robot lies still (not one tick after
  // prone, from standing); then 0: pushup -> standup (its way up) -> walk
  const CliRun r = run("play levels/flat --keys pushups.keys --seconds 22 --expect alive");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("walk->prone at 3.60 s"), std::string::npos) << r.out;  // at rest after the stop
  EXPECT_NE(r.out.find("prone->pushup at 5."), std::string::npos) << r.out;    // lying still ~2.3 s later
  EXPECT_NE(r.out.find("pushup->standup at 14.00 s"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("standup->walk at 18."), std::string::npos) << r.out;
}

TEST(Cli, WalkingWithWHeldKeepsToTheLineItStartedOn) {
  // 17.5 s of W from the spawn (facing +X at y = 0): the session steers the walk back toward its line (the walk's
  // line_hold); with the heading alone held it ended 1.9-2.3 m to the side at seeds 1-4, with the line 0.2-0.43 m
  const CliRun r = run("play levels/flat --keys straight.keys --seconds 18 --expect alive");
  EXPECT_EQ(r.code, 0) << r.out;
  double x = 0, y = 0;
  const size_t at = r.out.find("position   x ");
  ASSERT_NE(at, std::string::npos) << r.out;
  ASSERT_EQ(std::sscanf(r.out.c_str() + at, "position   x %lf y %lf", &x, &y), 2) << r.out;
  EXPECT_GT(x, 12.0);           // it walked (~0.8 m/s)
  EXPECT_LT(std::abs(y), 0.6);  // and stayed near y = 0
}

TEST(Cli, TheShippedScriptWinsTheMarioCourse) {
  // levels/mario/win.keys: the keys the autopilot pressed at seed 54; every stage in order, both question boxes hit
  // from below by a jump, the ball in the goal
  // (the script's seed line gives the seed: no --seed needed)
  const CliRun r = run("play levels/mario --keys win.keys --expect win");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("seed       54\n"), std::string::npos) << r.out;
  for (const char* stage : {"walk->run at", "walk->stairs at", "walk->prone at", "prone->crawl at", "crawl->standup at",
                            "squat->jump at", "question box at x = 32.00 hit", "question box at x = 33.50 hit",
                            "one_leg->kick at", "won: the ball is in the goal"})
    EXPECT_NE(r.out.find(stage), std::string::npos) << stage << "\n" << r.out;
  // the paper's switch continuity: walk -> run when the ghost comes, from about 0.8 m/s to >= 1.8 m/s
  // 2-3 s later, with no spike: the 0.1 s-smoothed forward speed changes by at most 5 m/s^2 (half a g; the W key's
  // ramp asks for 2) from 0.5 s before the switch to 3 s after
  const size_t at = r.out.find("switch     walk->run at");
  ASSERT_NE(at, std::string::npos) << r.out;
  double t = 0, before = 0, after = 0, peak = 0;
  ASSERT_EQ(std::sscanf(r.out.c_str() + at,
                        "switch     walk->run at %lf s: forward speed %lf -> %lf m/s, peak acceleration %lf", &t,
                        &before, &after, &peak),
            4)
      << r.out;
  EXPECT_NEAR(before, 0.8, 0.1);
  EXPECT_GE(after, 1.8);
  EXPECT_LE(peak, 5.0);
}

TEST(Cli, AKeyScriptsSeedLinePlaysAsTheSameSeedGivenByOption) {
  // the seed picks the spawn's joint offsets: a script with "seed 3" plays the run --seed 3 plays, tick for tick
  // (the same final position to the printed digit), and --seed overrides the line with a note
  const std::string d = tempDir("seedline");
  const std::string keys = "0.00 tap 0\n0.00 down W\n";
  engine::writeFileAtomic(d + "/plain.keys", keys);
  engine::writeFileAtomic(d + "/seeded.keys", "# made at seed 3\nseed 3\n" + keys);
  const auto position = [](const CliRun& r) {
    const size_t at = r.out.find("position   ");
    return at == std::string::npos ? std::string("none") : r.out.substr(at, r.out.find('\n', at) - at);
  };
  const CliRun byLine = run("play levels/flat --seconds 2 --keys " + d + "/seeded.keys");
  const CliRun byOption = run("play levels/flat --seconds 2 --seed 3 --keys " + d + "/plain.keys");
  const CliRun byDefault = run("play levels/flat --seconds 2 --keys " + d + "/plain.keys");
  const CliRun overridden = run("play levels/flat --seconds 2 --seed 1 --keys " + d + "/seeded.keys");
  ASSERT_EQ(byLine.code, 0) << byLine.out;
  EXPECT_NE(byLine.out.find("seed       3\n"), std::string::npos) << byLine.out;
  EXPECT_EQ(position(byLine), position(byOption));
  EXPECT_NE(position(byLine), position(byDefault));  // seed 1: other joint offsets, another run
  EXPECT_EQ(position(overridden), position(byDefault));
  EXPECT_NE(overridden.out.find("note: --seed 1 overrides"), std::string::npos) << overridden.out;
  EXPECT_NE(overridden.out.find("seeded.keys:2 (seed 3)"), std::string::npos) << overridden.out;
}

TEST(Cli, TheStepsTourEndsAliveThroughEveryShippedStage) {
  // levels/steps/tour.keys: walk, run, squat, one jump, stairs, prone, crawl through the tunnel,
  // stand-up, and the walk again at the end, without a fall (at seed 1; 50 of seeds 1-60 end alive, the stairs fall)
  const CliRun r = run("play levels/steps --keys tour.keys --expect alive");
  EXPECT_EQ(r.code, 0) << r.out;
  for (const char* stage :
       {"walk->run at", "run->walk at", "walk->squat at", "squat->jump at", "jump->squat at", "squat->walk at",
        "walk->stairs at", "walk->prone at", "prone->crawl at", "crawl->standup at", "standup->walk at"})
    EXPECT_NE(r.out.find(stage), std::string::npos) << stage << "\n" << r.out;
}

TEST(Cli, TheAutopilotWinsTheMarioCourseAtThreeSeeds) {
  // from cues alone (rays in the side layer, the ghost's distance, the ball, its own pose); all of seeds 1-10:
  // `treelearn bench --autopilot 10` (README)
  for (const char* seed : {"1", "6", "8"}) {
    const CliRun r = run(std::string("play levels/mario --autopilot --seed ") + seed + " --expect win");
    EXPECT_EQ(r.code, 0) << "seed " << seed << "\n" << r.out;
  }
}

TEST(Cli, TheCommittedMarioReplayVerifies) {
  // levels/mario/win.replay, recorded from win.keys: tick for tick the same run. If a model, the level or the
  // robot changed, replay says which (record it again: play levels/mario --keys win.keys --record ...); if the
  // code changed the run, it names the first tick that differs
  const CliRun r = run("replay levels/mario/win.replay --verify");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("identical: 206 state hashes over 10300 ticks match (the recording is 10316 ticks)"),
            std::string::npos)
      << r.out;
}

TEST(Cli, KeySixKicksTheBallIntoTheGoalFromAStandingStart) {
  // levels/penalty: the ball where the kick's card puts it, a goal 4.7 m beyond; the learned kick scores
  const CliRun r = run("play levels/penalty --keys kick.keys --expect win");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("stand->kick at 0.50 s"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("won: the ball is in the goal"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("falls      0"), std::string::npos) << r.out;
}

TEST(Cli, FromJumpsInARowTheSquatTakesOverOnceTheRobotHasStopped) {
  // the squat asked for mid-jump waits for the cycle's closing stand and for the drift to stop
  // (robot::cycleAllowsSwitch)
  const CliRun r = run("play levels/flat --keys jump_squat.keys --seconds 9 --expect alive");
  EXPECT_EQ(r.code, 0) << r.out;
  // the jump from 0.50 s, 1.6 s cycles: the second cycle's closing stand (its default pose) runs from 3.30 s to 4.10 s;
  // the first settled moment is at its start, the drift stops later in it
  const size_t at = r.out.find("stand->jump at 0.50 s, jump->squat at ");
  ASSERT_NE(at, std::string::npos) << r.out;
  double t = 0;
  ASSERT_EQ(std::sscanf(r.out.c_str() + at, "stand->jump at 0.50 s, jump->squat at %lf s", &t), 1) << r.out;
  EXPECT_GT(t, 3.30);
  EXPECT_LT(t, 4.10);
  EXPECT_NE(r.out.find("falls      0"), std::string::npos) << r.out;
}

TEST(Cli, FromTheCrawlKeyZeroStandsUpThenTheWalkGoesOn) {
  // walk, then 9: routed walk -> prone -> crawl once the robot lies still; W crawls; then 0: crawl -> standup (its
  // way up; the crawl does not come to rest at a zero command, so the switch comes when the 1.5 s wait runs out)
  // -> walk once the robot stands
  const CliRun r = run("play levels/flat --keys crawl.keys --seconds 25 --expect alive");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("walk->prone at 3.60 s"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("prone->crawl at 5."), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("crawl->standup at 17.00 s"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("standup->walk at 21."), std::string::npos) << r.out;
}

TEST(Cli, FromARunTheProneKeyFirstSlowsToAStopThroughTheWalk) {
  // run, W held, then 7: routed run -> walk -> prone; the run brakes to rest before the walk takes over (before,
  // the walk took over at the run's speed and fell braking in 3 of 4 seeds)
  const CliRun r = run("play levels/flat --keys run_then_prone.keys --seconds 14 --expect alive");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("run->walk at 7.10 s"), std::string::npos) << r.out;  // 2.2 m/s braked at 2 m/s^2: 1.1 s
  EXPECT_NE(r.out.find("walk->prone at 8."), std::string::npos) << r.out;
}

TEST(Cli, BadArgumentsExitWithCodeTwo) {
  EXPECT_EQ(run("play levels/flat --bogus").code, 2);
  EXPECT_EQ(run("play levels/flat --seconds abc").code, 2);
  EXPECT_EQ(run("play levels/flat --seconds -5").code, 2);
  EXPECT_EQ(run("play levels/flat --expect victory").code, 2);
  EXPECT_EQ(run("frobnicate").code, 2);
  EXPECT_EQ(run("").code, 2);
  const CliRun missing = run("play levels/nowhere");
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.out.find("levels/nowhere"), std::string::npos) << missing.out;
}

// numbers that would silently become something else: a seed of -1 (2^64 - 1), a NaN rate (taken as "not given"),
// an option that only means something with another one
TEST(Cli, NumbersThatWouldWrapOrVanishAreRefused) {
  const CliRun seed = run("play levels/flat --seconds 0.1 --seed -1");
  EXPECT_EQ(seed.code, 2);
  EXPECT_NE(seed.out.find("a seed is a whole number >= 0"), std::string::npos) << seed.out;
  EXPECT_EQ(run("eval walk --seed -3").code, 2);
  const CliRun rate = run("train squat --learning-rate nan --run-dir " + testing::TempDir() + "/never");
  EXPECT_EQ(rate.code, 2);
  EXPECT_NE(rate.out.find("must be a finite number"), std::string::npos) << rate.out;
  EXPECT_EQ(run("train squat --reinflate-log-std 40 --run-dir " + testing::TempDir() + "/never").code, 2);
  const CliRun exportFrom = run("train squat --export-from best --run-dir " + testing::TempDir() + "/never");
  EXPECT_EQ(exportFrom.code, 2);
  EXPECT_NE(exportFrom.out.find("--export-from picks what --export-only exports"), std::string::npos) << exportFrom.out;
  EXPECT_FALSE(std::filesystem::exists(testing::TempDir() + "/never"));  // nothing started
}

TEST(Cli, BadKeyScriptNamesFileAndLine) {
  const std::string d = tempDir("keys");
  engine::writeFileAtomic(d + "/bad.keys", "0.00 tap 0\n0.50 hold W\n");
  const CliRun r = run("play levels/flat --keys " + d + "/bad.keys");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("bad.keys:2:"), std::string::npos) << r.out;
}

TEST(Cli, ExpectWinOnALevelWithoutGoalIsAnError) {
  const CliRun r = run("play levels/flat --seconds 1 --expect win");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("no goal"), std::string::npos) << r.out;
}

TEST(Cli, RecordedReplayVerifiesIdentical) {
  const std::string d = tempDir("replay");
  const CliRun rec = run("play levels/steps --keys " + kSource +
                         "/levels/flat/square.keys --seconds 4 --seed 11 --record " + d + "/run.replay");
  ASSERT_EQ(rec.code, 0) << rec.out;
  const CliRun ver = run("replay " + d + "/run.replay --verify");
  EXPECT_EQ(ver.code, 0) << ver.out;
  EXPECT_NE(ver.out.find("identical: 8 state hashes over 400 ticks match"), std::string::npos) << ver.out;
}

TEST(Cli, AReplayFindsItsLevelWhenReplayedFromAnotherFolder) {
  // the replay names its level as typed ("levels/flat", relative to where play ran)
  const std::string d = tempDir("replay_elsewhere");
  ASSERT_EQ(run("play levels/flat --seconds 1 --record " + d + "/run.replay").code, 0);
  const CliRun here = shell("cd " + d + " && " + TREELEARN_BINARY + " replay run.replay --verify");
  EXPECT_EQ(here.code, 0) << here.out;
  EXPECT_NE(here.out.find("identical"), std::string::npos) << here.out;
  // a level of one's own, recorded from its project folder, with the replay kept inside that folder
  std::filesystem::create_directories(d + "/mine/levels/open");
  std::filesystem::copy_file(kSource + "/levels/flat/level.toml", d + "/mine/levels/open/level.toml");
  const CliRun rec = shell("cd " + d + "/mine && " + TREELEARN_BINARY +
                           " play levels/open --seconds 1 --record levels/open/run.replay");
  ASSERT_EQ(rec.code, 0) << rec.out;
  const CliRun away =
      shell("cd / && " + std::string(TREELEARN_BINARY) + " replay " + d + "/mine/levels/open/run.replay --verify");
  EXPECT_EQ(away.code, 0) << away.out;
  EXPECT_NE(away.out.find("identical"), std::string::npos) << away.out;
}

TEST(Cli, AReplaysKeysWrittenOutPlayTheSameRunAgain) {
  // replay --keys-out: the recorded events and seed as a key script; played, it records the same replay byte for byte
  const std::string d = tempDir("keysout");
  ASSERT_EQ(run("play levels/steps --keys " + kSource + "/levels/flat/square.keys --seconds 4 --seed 11 --record " + d +
                "/first.replay")
                .code,
            0);
  const CliRun out = run("replay " + d + "/first.replay --keys-out " + d + "/keys/first.keys");
  ASSERT_EQ(out.code, 0) << out.out;
  EXPECT_NE(out.out.find("seed 11)"), std::string::npos) << out.out;
  const std::string keys = engine::readFile(d + "/keys/first.keys");
  EXPECT_NE(keys.find("\nseed 11\n0.00 tap 0\n0.50 down W\n"), std::string::npos) << keys;
  const CliRun again =
      run("play levels/steps --keys " + d + "/keys/first.keys --seconds 4 --record " + d + "/again.replay");
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_EQ(engine::readFile(d + "/again.replay"), engine::readFile(d + "/first.replay"));
}

TEST(Cli, CorruptedAndTruncatedReplaysAreRejected) {
  const std::string d = tempDir("corrupt");
  ASSERT_EQ(run("play levels/flat --seconds 1 --record " + d + "/ok.replay").code, 0);
  const std::string good = engine::readFile(d + "/ok.replay");
  std::string flipped = good;
  flipped[flipped.size() / 2] ^= 0x01;
  engine::writeFileAtomic(d + "/flipped.replay", flipped);
  engine::writeFileAtomic(d + "/short.replay", good.substr(0, good.size() / 3));
  engine::writeFileAtomic(d + "/noise.replay", std::string("\x89\x01\xffgarbage\0\x02", 12));
  for (const char* f : {"flipped", "short", "noise"}) {
    const CliRun r = run("replay " + d + "/" + f + ".replay --verify");
    EXPECT_EQ(r.code, 2) << f << ": " << r.out;
    EXPECT_NE(r.out.find(std::string(f) + ".replay"), std::string::npos) << r.out;
  }
}

TEST(Cli, OutputFoldersAreCreated) {
  const std::string d = tempDir("mkdir");
  const CliRun r = run("play levels/flat --seconds 0.2 --summary " + d + "/a/b/summary.txt");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(fs::exists(d + "/a/b/summary.txt"));
}

TEST(Cli, TheLogSaysWhereTheWeightIsBetweenTheFeet) {
  const std::string d = tempDir("log");
  const CliRun r = run("play levels/steps --seconds 1 --log " + d + "/com.csv");
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string csv = engine::readFile(d + "/com.csv");
  ASSERT_EQ(csv.substr(0, csv.find('\n')),
            "t_s,skill,com_x_m,com_z_m,com_vx_m_per_s,com_y_m,yaw_rad,com_left_of_feet_m");
  // the robot stands where it spawned (levels/steps: y = 2.3 facing +X) on its symmetric stance: the centre of mass
  // is at y 2.3 and between the feet
  const size_t row = csv.find("\n0.50,stand,");
  ASSERT_NE(row, std::string::npos) << csv.substr(0, 400);
  std::istringstream line(csv.substr(row + 1, csv.find('\n', row + 1) - row - 1));
  std::vector<double> v;
  std::string field;
  for (int i = 0; std::getline(line, field, ','); ++i)
    if (i >= 2) v.push_back(std::stod(field));  // after "t,skill,"
  ASSERT_EQ(v.size(), 6u);                      // x, height, forward speed, y, heading, left of the feet
  EXPECT_LT(std::abs(v[4]), 0.01);              // still facing +X
  EXPECT_NEAR(v[3], 2.3, 0.02);                 // y across the course
  EXPECT_LT(std::abs(v[5]), 0.02);  // measured from the feet, not the course (the sign: RewardTerms.WeightCentred*)
}

TEST(Cli, FramesAndVideoAreWritten) {
  const std::string d = tempDir("frames");
  const CliRun r = run("play levels/steps --seconds 0.5 --fps 20 --frames " + d + "/png --video " + d +
                       "/v.mp4 --summary " + d + "/summary.txt");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(fs::exists(d + "/png/frame_000000.png"));
  EXPECT_TRUE(fs::exists(d + "/png/frame_000010.png"));  // 0.5 s at 20 fps: frames 0..10
  EXPECT_GT(fs::file_size(d + "/v.mp4"), 1000u);
  EXPECT_NE(engine::readFile(d + "/summary.txt").find("outcome    alive"), std::string::npos);
}

TEST(Cli, FailedOutputLeavesNoHalfWrittenFile) {
  const std::string d = tempDir("nofile");
  // the replay path is an existing folder: the atomic rename fails and no temp file is left behind
  fs::create_directories(d + "/taken.replay");
  const CliRun r = run("play levels/flat --seconds 0.2 --record " + d + "/taken.replay");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("taken.replay"), std::string::npos) << r.out;
  size_t entries = 0;
  for (const auto& e : fs::directory_iterator(d)) entries += e.path().filename() != "taken.replay";
  EXPECT_EQ(entries, 0u);
  EXPECT_TRUE(fs::is_empty(d + "/taken.replay"));
}

TEST(Cli, TrainWritesLogCheckpointAndAValidOnnxModel) {
  const std::string d = tempDir("train");
  const CliRun r = run("train walk --steps 20480 --envs 4 --threads 2 --eval-every 0 --run-dir " + d + "/run");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("iter 1/1"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(d + "/run/checkpoint.bin"));
  EXPECT_TRUE(fs::exists(d + "/run/walk.policy.bin"));
  const std::string log = engine::readFile(d + "/run/log.csv");
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 2);  // header + one iteration
  // the exported model loads and has the shared layout in its metadata
  EXPECT_GT(fs::file_size(d + "/run/walk.onnx"), 1000000u);
  const std::string onnx = engine::readFile(d + "/run/walk.onnx");
  EXPECT_NE(onnx.find("treelearn.joint_order"), std::string::npos);
  EXPECT_NE(onnx.find("left_hip_pitch_joint"), std::string::npos);
}

TEST(Cli, EvalConfirmScoresACandidateAgainOnOtherEpisodes) {
  // the first evaluation beats nothing confirmed yet, so it is run again on 2 other episodes, and that card's score
  // is the one logged and kept with best.bin
  const std::string d = tempDir("confirm");
  const CliRun r =
      run("train walk --steps 20480 --envs 4 --threads 2 --eval-every 1 --eval-episodes 1 --eval-confirm 2 "
          "--run-dir " +
          d + "/run");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("(1-episode card"), std::string::npos) << r.out;
  const size_t at = r.out.find("  confirm: ");
  ASSERT_NE(at, std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(2-episode card on other episodes", at), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(d + "/run/best.bin"));
}

TEST(Cli, AResumedRunConfirmsExactlyWhenTheUninterruptedRunDoes) {
  // two iterations straight through, and one then a --resume to two: the second iteration's card lines are the
  // same in both. At seed 2 its card does not beat the first iteration's confirmed score, so neither run confirms
  // it again (a resumed run that forgot its best confirmed score would)
  const std::string d = tempDir("confirm_resume");
  const std::string args = "train walk --seed 2 --envs 4 --threads 1 --eval-every 1 --eval-episodes 1 --eval-confirm 2";
  const CliRun straight = run(args + " --steps 40960 --run-dir " + d + "/a");
  ASSERT_EQ(straight.code, 0) << straight.out;
  ASSERT_EQ(run(args + " --steps 20480 --run-dir " + d + "/b").code, 0);
  const CliRun resumed = run(args + " --steps 40960 --resume --run-dir " + d + "/b");
  ASSERT_EQ(resumed.code, 0) << resumed.out;
  for (const CliRun* c : {&straight, &resumed}) ASSERT_NE(c->out.find("iter 2/"), std::string::npos) << c->out;
  auto secondIteration = [](const std::string& out) {  // the card lines printed before "iter 2/" (after "iter 1/")
    size_t from = out.find("iter 1/");
    if (from == std::string::npos) from = 0;  // the resumed run starts at the second iteration
    std::istringstream in(out.substr(from, out.find("iter 2/") - from));
    std::string lines;
    for (std::string line; std::getline(in, line);)
      if (line.rfind("  eval: ", 0) == 0 || line.rfind("  confirm: ", 0) == 0) lines += line + "\n";
    return lines;
  };
  const std::string expected = secondIteration(straight.out);
  EXPECT_NE(expected.find("  eval: "), std::string::npos) << straight.out;
  EXPECT_EQ(expected.find("  confirm: "), std::string::npos)
      << "seed 2's second card now confirms: pick a seed where it does not\n"
      << straight.out;
  EXPECT_EQ(secondIteration(resumed.out), expected) << resumed.out;
}

TEST(Cli, TrainingABranchStartsFromItsParentAndWritesOnlyIntoItsRunFolder) {
  // a copy of the tree and its models: the branch reads its parent's policy from the tree's folder and writes
  // nothing there, its own model included (ship installs it)
  const std::string d = tempDir("branch");
  const std::string models = d + "/models";
  fs::copy(kSource + "/assets/skills", models, fs::copy_options::recursive);
  const auto before = snapshot(models);
  ASSERT_TRUE(fs::exists(models + "/walk.policy.bin"));
  const CliRun r =
      run("--tree " + models + "/tree.toml train run --steps 20480 --envs 4 --threads 2 --eval-every 0 --run-dir " + d +
          "/run");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("initialised from parent 'walk' (" + models + "/walk.policy.bin)"), std::string::npos) << r.out;
  EXPECT_TRUE(snapshot(models) == before) << "training changed or added files in the tree's folder";
  EXPECT_TRUE(fs::exists(d + "/run/run.onnx"));
  EXPECT_TRUE(fs::exists(d + "/run/run.policy.bin"));
  EXPECT_NE(r.out.find("treelearn --tree " + models + "/tree.toml ship run --from " + d + "/run"), std::string::npos)
      << r.out;
}

TEST(Cli, TrainAndExportLeaveTheShippedModelsUntouched) {
  // the real tree, as a user runs it: neither a run nor --export-only writes into assets/skills
  const std::string d = tempDir("assets_untouched");
  const auto before = snapshot(kSource + "/assets/skills");
  const CliRun trained = run("train walk --steps 20480 --envs 4 --threads 2 --eval-every 0 --run-dir " + d + "/run");
  ASSERT_EQ(trained.code, 0) << trained.out;
  const CliRun exported = run("train walk --export-only --export-from last --run-dir " + d + "/run");
  ASSERT_EQ(exported.code, 0) << exported.out;
  EXPECT_NE(exported.out.find("exported " + d + "/run/walk.onnx and " + d + "/run/walk.policy.bin"), std::string::npos)
      << exported.out;
  EXPECT_NE(exported.out.find("treelearn ship walk --from " + d + "/run"), std::string::npos) << exported.out;
  EXPECT_TRUE(snapshot(kSource + "/assets/skills") == before) << "train or train --export-only changed assets/skills";
}

TEST(Cli, TheExportedPolicyFileRecordsStepsIterationAndCardScore) {
  // RUN/SKILL.policy.bin says where its policy came from, as best.bin does: the best by the training card, with
  // its score; --export-from last: the checkpoint's iteration and steps, and no score (it was not judged)
  const std::string d = tempDir("policy_info");
  const CliRun r =
      run("train walk --steps 20480 --envs 4 --threads 2 --eval-every 1 --eval-episodes 1 --run-dir " + d + "/run");
  ASSERT_EQ(r.code, 0) << r.out;
  ai::PolicyInfo best, exported;
  ai::loadPolicyState(d + "/run/best.bin", &best);
  ai::loadPolicyState(d + "/run/walk.policy.bin", &exported);
  EXPECT_EQ(exported.iteration, 1);
  EXPECT_EQ(exported.envSteps, 20480);
  EXPECT_FALSE(std::isnan(exported.score));
  EXPECT_EQ(exported.score, best.score);
  EXPECT_EQ(exported.configHash, best.configHash);
  const CliRun last = run("train walk --export-only --export-from last --run-dir " + d + "/run");
  ASSERT_EQ(last.code, 0) << last.out;
  ai::loadPolicyState(d + "/run/walk.policy.bin", &exported);
  EXPECT_EQ(exported.iteration, 1);
  EXPECT_EQ(exported.envSteps, 20480);
  EXPECT_TRUE(std::isnan(exported.score));
  EXPECT_EQ(exported.configHash, best.configHash);
}

TEST(Cli, ShipInstallsAModelWhoseCardPassesAndRecordsTheCardAsEvalDoes) {
  // a tree copy whose squat card runs 2 episodes; the run folder holds the shipped squat's files as if exported
  const std::string skills = squatTree("ship_pass", 2);
  ASSERT_FALSE(skills.empty());
  const std::string from = squatRun(fs::path(skills).parent_path());
  const CliRun r = run("--tree " + skills + "/tree.toml ship squat --from " + from);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("CARD PASSED"), std::string::npos) << r.out;
  for (const char* f : {"squat.onnx", "squat.policy.bin"})
    EXPECT_EQ(engine::readFile(skills + "/" + f), engine::readFile(from + "/" + f)) << f;
  const std::string record = engine::readFile(skills + "/squat.card.txt");
  EXPECT_NE(record.find("squat report card: 2 episodes"), std::string::npos) << record;
  EXPECT_NE(record.find("(model " + skills + "/squat.onnx, hash "), std::string::npos) << record;
  // the record is the one eval keeps for the installed model: eval finds its card identical to it
  const CliRun eval = run("--tree " + skills + "/tree.toml eval squat");
  EXPECT_EQ(eval.code, 0) << eval.out;
  EXPECT_NE(eval.out.find("identical to the card recorded for this model"), std::string::npos) << eval.out;
  for (const auto& f : fs::directory_iterator(skills))  // the atomic writes left no temp files
    EXPECT_EQ(f.path().filename().string().find(".tmp"), std::string::npos) << f.path();
}

TEST(Cli, ShipRefusesAModelWhoseCardFailsAndNamesTheFailingFigure) {
  // the squat card's height bar made unreachable (0.1 mm) in a tree copy: the model stays in its run folder
  const std::string skills = squatTree("ship_refused", 2, {"height_error = 0.04", "height_error = 0.0001"});
  ASSERT_FALSE(skills.empty());
  const std::string from = squatRun(fs::path(skills).parent_path());
  const auto before = snapshot(skills);
  const CliRun r = run("--tree " + skills + "/tree.toml ship squat --from " + from);
  EXPECT_EQ(r.code, 1) << r.out;
  const size_t at = r.out.find("REFUSED: ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string refused = r.out.substr(at, r.out.find('\n', at) - at);
  EXPECT_NE(refused.find("the card of 'squat' fails (mean |h - h_target| (pelvis) "), std::string::npos) << refused;
  EXPECT_NE(refused.find("bar <= 0.0001 m)"), std::string::npos) << refused;
  EXPECT_EQ(refused.find("episodes without a fall"), std::string::npos) << refused;  // a passing figure is not named
  EXPECT_NE(refused.find("nothing was installed"), std::string::npos) << refused;
  EXPECT_TRUE(snapshot(skills) == before) << "a refused model changed the tree's folder";
}

TEST(Cli, ShipForceInstallsAModelWhoseCardFailsAndRecordsTheFailure) {
  const std::string skills = squatTree("ship_forced", 2, {"height_error = 0.04", "height_error = 0.0001"});
  ASSERT_FALSE(skills.empty());
  const std::string from = squatRun(fs::path(skills).parent_path());
  const CliRun r = run("--tree " + skills + "/tree.toml ship squat --force --from " + from);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("installed anyway (--force)"), std::string::npos) << r.out;
  for (const char* f : {"squat.onnx", "squat.policy.bin"})
    EXPECT_EQ(engine::readFile(skills + "/" + f), engine::readFile(from + "/" + f)) << f;
  EXPECT_NE(engine::readFile(skills + "/squat.card.txt").find("CARD FAILED"), std::string::npos);
  const CliRun tree = run("--tree " + skills + "/tree.toml tree");
  EXPECT_NE(tree.out.find("FAIL"), std::string::npos) << tree.out;
}

TEST(Cli, ShipRejectsAMissingRunAMissingModelAndAnotherSkillsModel) {
  const std::string skills = squatTree("ship_bad", 2);
  ASSERT_FALSE(skills.empty());
  const std::string d = fs::path(skills).parent_path();
  const std::string ship = "--tree " + skills + "/tree.toml ship squat --from ";
  const auto before = snapshot(skills);
  const CliRun none = run(ship + d + "/nowhere");
  EXPECT_EQ(none.code, 2) << none.out;
  EXPECT_NE(none.out.find(d + "/nowhere: no such run folder"), std::string::npos) << none.out;
  fs::create_directories(d + "/empty");
  const CliRun empty = run(ship + d + "/empty");
  EXPECT_EQ(empty.code, 2) << empty.out;
  EXPECT_NE(empty.out.find("the run folder holds no model of 'squat' (train exports it"), std::string::npos)
      << empty.out;
  fs::create_directories(d + "/walk_run");  // a run of the walk, shipped as the squat
  fs::copy_file(kSource + "/assets/skills/walk.onnx", d + "/walk_run/walk.onnx");
  const CliRun other = run(ship + d + "/walk_run");
  EXPECT_EQ(other.code, 2) << other.out;
  EXPECT_NE(other.out.find("holds no model of 'squat' but walk.onnx: a run of another skill?"), std::string::npos)
      << other.out;
  fs::create_directories(d + "/renamed");  // the walk's files under the squat's names
  fs::copy_file(kSource + "/assets/skills/walk.onnx", d + "/renamed/squat.onnx");
  fs::copy_file(kSource + "/assets/skills/walk.policy.bin", d + "/renamed/squat.policy.bin");
  const CliRun renamed = run(ship + d + "/renamed");
  EXPECT_EQ(renamed.code, 2) << renamed.out;
  EXPECT_NE(renamed.out.find("squat.onnx: a model of skill 'walk', not of 'squat'"), std::string::npos) << renamed.out;
  fs::create_directories(d + "/mixed");  // the squat's model next to another policy file
  fs::copy_file(kSource + "/assets/skills/squat.onnx", d + "/mixed/squat.onnx");
  const CliRun lonely = run(ship + d + "/mixed");
  EXPECT_EQ(lonely.code, 2) << lonely.out;
  EXPECT_NE(lonely.out.find("squat.policy.bin: missing next to"), std::string::npos) << lonely.out;
  fs::copy_file(kSource + "/assets/skills/walk.policy.bin", d + "/mixed/squat.policy.bin");
  const CliRun mixed = run(ship + d + "/mixed");
  EXPECT_EQ(mixed.code, 2) << mixed.out;
  EXPECT_NE(mixed.out.find("hold different policies"), std::string::npos) << mixed.out;
  const CliRun unknown = run("--tree " + skills + "/tree.toml ship flyer --from " + d + "/mixed");
  EXPECT_EQ(unknown.code, 2) << unknown.out;
  EXPECT_NE(unknown.out.find("unknown skill 'flyer'"), std::string::npos) << unknown.out;
  EXPECT_TRUE(snapshot(skills) == before) << "a rejected ship changed the tree's folder";
}

TEST(Cli, AResumeAtOrPastTheStepsSaysNothingWasTrained) {
  // one iteration of 4 x 5120 steps, then the same --steps again with --resume: the checkpoint is already there
  const std::string d = tempDir("resume_done");
  const std::string args = "train walk --steps 20480 --envs 4 --threads 1 --eval-every 0 --run-dir " + d + "/run";
  ASSERT_EQ(run(args).code, 0);
  const CliRun r = run(args + " --resume");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(r.out.find("iter "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("already at 20480 env steps (iteration 1), at or past --steps 20480: nothing was trained"),
            std::string::npos)
      << r.out;
}

TEST(Cli, AKeyWhoseSkillHasNoModelIsNamedInTheSummary) {
  // a tree copy with the walk's model alone: key 2 (stairs) does nothing, and the summary says why
  const std::string d = tempDir("missing_model");
  fs::copy_file(kSource + "/assets/skills/tree.toml", d + "/tree.toml");
  fs::copy_file(kSource + "/assets/skills/walk.onnx", d + "/walk.onnx");
  engine::writeFileAtomic(d + "/stairs.keys", "0.00 tap 2\n");
  const CliRun r = run("--tree " + d + "/tree.toml play levels/flat --keys " + d + "/stairs.keys --seconds 1");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("used: none (standing controller); requested keys: 2"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("missing    key 2 (stairs): no model at " + d + "/stairs.onnx, so the key did nothing"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("key 0 (walk)"), std::string::npos) << r.out;  // not requested, and its model is there
}

TEST(Cli, BranchWithoutParentModelIsAnError) {
  const std::string d = tempDir("orphan");
  const CliRun r = run("train run --steps 20480 --envs 4 --eval-every 0 --run-dir " + d + "/run --models-dir " + d);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("train walk first"), std::string::npos) << r.out;
}

// the skills with a shipped model in assets/skills (NAME.onnx), sorted
std::vector<std::string> shippedSkills() {
  std::vector<std::string> skills;
  for (const auto& f : fs::directory_iterator(kSource + "/assets/skills"))
    if (f.path().extension() == ".onnx") skills.push_back(f.path().stem());
  std::sort(skills.begin(), skills.end());
  return skills;
}

class ShippedCard : public testing::TestWithParam<std::string> {};

TEST_P(ShippedCard, ReproducesItsRecord) {
  // retention: a skill's card, re-run with its seed on the shipped model, must equal the record kept when the
  // model was shipped (training other skills never touches it; same binary, same numbers, whatever the thread
  // count). One test per skill on one thread, so that ctest -j2 runs two cards side by side on the two cores
  const std::string skill = GetParam();
  ASSERT_TRUE(fs::exists(kSource + "/assets/skills/" + skill + ".card.txt"))
      << skill << " is shipped without its card record (treelearn ship " << skill << " writes it)";
  const CliRun r = run("eval " + skill + " --threads 1");
  EXPECT_NE(r.out.find("identical to the card recorded"), std::string::npos) << skill << ":\n" << r.out;
}

INSTANTIATE_TEST_SUITE_P(Cli, ShippedCard, testing::ValuesIn(shippedSkills()),
                         [](const testing::TestParamInfo<std::string>& skill) { return skill.param; });

TEST(Cli, ThereAreShippedModelsForTheCardTestsToCheck) {
  // the cards above run over assets/skills/*.onnx: an empty list would check nothing
  EXPECT_FALSE(shippedSkills().empty()) << "no models in assets/skills";
}

TEST(Cli, TreeShowsEverySkillWithItsKeyAndCard) {
  const CliRun r = run("tree");
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* skill : {"walk", "run", "stairs", "squat", "jump", "one_leg"})
    EXPECT_NE(r.out.find(skill), std::string::npos) << skill << "\n" << r.out;
  EXPECT_NE(r.out.find("└─"), std::string::npos) << r.out;
}

TEST(Cli, UnknownSkillIsAnError) {
  const CliRun r = run("train flyer --steps 10");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("unknown skill 'flyer'"), std::string::npos) << r.out;
}

TEST(Cli, SwitchesOnlyTakesASkillWithSwitches) {
  const CliRun unknown = run("eval switches --only flyer --episodes 1");
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(unknown.out.find("eval switches --only flyer: no such skill"), std::string::npos) << unknown.out;
  const CliRun notSwitches = run("eval walk --only squat");
  EXPECT_EQ(notSwitches.code, 2);
  EXPECT_NE(notSwitches.out.find("--only picks the switches of one skill"), std::string::npos) << notSwitches.out;
}

TEST(Cli, PriorOnlyCardRunsTheSkillsPriorWithoutAModel) {
  // the squat's key pose alone at depth 0 is the default pose: standing, it keeps the robot up without a network
  const std::string dir = tempDir("prior_only");
  fs::copy_file(kSource + "/assets/skills/tree.toml", dir + "/tree.toml");  // no models next to it
  const CliRun r = run("--tree " + dir + "/tree.toml eval squat --prior-only --episodes 2 --threads 1");
  EXPECT_NE(r.out.find("model none (the prior alone)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("episodes without a fall"), std::string::npos) << r.out;
  EXPECT_TRUE(r.code == 0 || r.code == 1) << r.out;  // the card may pass or fail; it must run
  const CliRun bad = run("eval squat --prior-only --model assets/skills/squat.onnx");
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("--prior-only runs the card with zero network output"), std::string::npos) << bad.out;
}

TEST(Cli, SampledCardDrawsSeededActionsAndLeavesTheRecordAlone) {
  // eval --sample: the card with the policy as training acts (mean + seeded Gaussian noise); the same seed gives the
  // same run, the shipped model's card record is not touched, and it refuses a second source of actions
  const std::string record = kSource + "/assets/skills/squat.card.txt";
  const std::string before = engine::readFile(record);
  const std::string cmd = "eval squat --sample assets/skills/squat.policy.bin --episodes 2 --threads 1";
  const CliRun a = run(cmd), b = run(cmd);
  EXPECT_NE(a.out.find("squat.policy.bin (actions drawn from its Gaussian)"), std::string::npos) << a.out;
  EXPECT_NE(a.out.find("episodes without a fall"), std::string::npos) << a.out;
  EXPECT_TRUE(a.code == 0 || a.code == 1) << a.out;
  EXPECT_EQ(a.out, b.out);
  EXPECT_EQ(engine::readFile(record), before);
  const CliRun bad = run("eval squat --sample assets/skills/squat.policy.bin --model assets/skills/squat.onnx");
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("eval --sample draws the card's actions from a policy file"), std::string::npos) << bad.out;
}

TEST(Cli, BranchInitialisationOptionsAreRefusedWhereTheyWouldDoNothing) {
  const CliRun resume = run("train squat --resume --zero-output --run-dir " + tempDir("zero_resume"));
  EXPECT_EQ(resume.code, 2) << resume.out;
  EXPECT_NE(resume.out.find("--zero-output is a branch's initialisation from its parent: not with --resume"),
            std::string::npos)
      << resume.out;
  const CliRun root = run("train walk --init-log-std -2 --steps 10 --run-dir " + tempDir("zero_root"));
  EXPECT_EQ(root.code, 2) << root.out;
  EXPECT_NE(root.out.find("for the root skill"), std::string::npos) << root.out;
  const CliRun resumed = run("train squat --resume --init-log-std -2 --run-dir " + tempDir("std_resume"));
  EXPECT_EQ(resumed.code, 2) << resumed.out;
  EXPECT_NE(resumed.out.find("not with --resume"), std::string::npos) << resumed.out;
}
