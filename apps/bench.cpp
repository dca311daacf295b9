// bench.cpp — `treelearn bench`: physics (standing G1, 1 and 2 threads), rendering (640x360 with and
// without PNG) and headless play throughput; with --autopilot N, levels/mario by autopilot at seeds 1..N. Timing
// and counts only; nothing here passes or fails.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "apps/commands.h"
#include "engine/core/file_io.h"
#include "engine/loop/clock.h"
#include "engine/render/png_writer.h"
#include "engine/render/renderer.h"
#include "game/play.h"
#include "levels/garden_layout.h"
#include "levels/level.h"
#include "levels/variant.h"
#include "robot/robot.h"

namespace apps {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// seconds of wall time to simulate `ticks` control ticks of a standing G1 (robot::stepPhysicsTick: PD every substep)
double timeStanding(const robot::RobotModel& model, int ticks) {
  engine::PhysicsWorld world;
  world.addGround(1.0);
  robot::Robot robot(model, world, 0, 0, 0);
  for (int i = 0; i < 100; ++i) robot::stepPhysicsTick(robot, world);  // settle onto the ground first
  const auto t = Clock::now();
  for (int i = 0; i < ticks; ++i) robot::stepPhysicsTick(robot, world);
  return since(t);
}

struct AutopilotRun {
  const levels::Level* level = nullptr;
  uint64_t seed = 1;
  std::string label;  // "seed 3", "variant 3"
};
struct Totals {
  int wins = 0, falls = 0, targets = 0, withoutFall = 0;
};

// plays each run by autopilot until it is won or lost, two at a time; a line on stderr as each one ends, then a
// line per run (outcome, time, falls by skill) and the totals on stdout, in the runs' order
Totals playByAutopilot(const std::vector<AutopilotRun>& runs, const robot::RobotModel& model,
                       const robot::SkillSet& skills) {
  const int n = int(runs.size());
  std::vector<game::PlayResult> results(runs.size());
  std::atomic<int> next{0}, done{0};
  std::mutex progress;
  const auto start = Clock::now();
  auto worker = [&] {
    for (int i; (i = next++) < n;) {
      const levels::Level& level = *runs[size_t(i)].level;
      game::PlayOptions ap;
      ap.seed = runs[size_t(i)].seed;
      ap.skills = &skills;
      ap.autopilot = true;
      ap.hashEvery = 0;
      // until it ends; a map (the garden) for the paper's 240 s
      ap.ticks = engine::secondsToTicks(game::isMapLevel(level) ? 240.0
                                        : level.timeLimit > 0   ? level.timeLimit + 0.5
                                                                : 600.0);
      results[size_t(i)] = game::play(level, model, ap);
      const std::lock_guard<std::mutex> lock(progress);
      const game::PlayResult& r = results[size_t(i)];
      std::fprintf(stderr, "bench: %d of %d played (%s: %s, %.0f s wall so far)\n", ++done, n,
                   runs[size_t(i)].label.c_str(),
                   r.garden.played                   ? (std::to_string(r.garden.targetsReached) + " targets").c_str()
                   : r.outcome == game::Outcome::Won ? "won"
                                                     : "lost",
                   since(start));
    }
  };
  std::thread a(worker), b(worker);
  a.join();
  b.join();
  Totals t;
  std::map<std::string, int> bySkill;
  for (int i = 0; i < n; ++i) {
    const game::PlayResult& p = results[size_t(i)];
    const bool won = p.outcome == game::Outcome::Won;
    t.wins += won;
    t.falls += p.telemetry.falls;
    t.withoutFall += p.telemetry.falls == 0;
    t.targets += p.garden.targetsReached;
    for (const auto& [skill, k] : p.telemetry.fallsBySkill) bySkill[skill] += k;
    const std::string what = p.garden.played ? std::to_string(p.garden.targetsReached) + " targets of " +
                                                   std::to_string(p.garden.targetsGiven) + " given, " +
                                                   std::to_string(p.garden.stuck) + " stuck"
                                             : p.outcomeReason;
    std::printf("  autopilot %-12s %-4s %-52s %7.2f s  falls %d%s%s\n", runs[size_t(i)].label.c_str(),
                p.garden.played ? ""
                : won           ? "won"
                                : "lost",
                what.c_str(), double(p.ticks) * engine::kTickSeconds, p.telemetry.falls, p.telemetry.falls ? ": " : "",
                game::fallsBySkillText(p.telemetry.fallsBySkill).c_str());
  }
  const std::string outcome = n && results[0].garden.played
                                  ? std::to_string(t.targets) + " targets"
                                  : "won " + std::to_string(t.wins) + " of " + std::to_string(n);
  std::printf("  total: %s, %d falls (%.2f a run)%s%s\n", outcome.c_str(), t.falls, n ? double(t.falls) / n : 0.0,
              t.falls ? "; by skill: " : "", game::fallsBySkillText(bySkill).c_str());
  return t;
}

}  // namespace

int runBench(const BenchOptions& o) {
  const robot::RobotModel model = robot::loadRobotModel(robot::defaultRobotConfigPath());
  // --autopilot's level and skills, loaded before the timings so that a missing file stops it at once
  const bool autopilot = o.autopilotSeeds > 0 || o.variants > 0 || o.gardens > 0;
  const levels::Level mario = autopilot ? levels::loadLevel("levels/mario") : levels::Level{};
  const robot::SkillSet skills = autopilot ? loadSkills(model) : robot::SkillSet{};
  std::ostringstream csv;
  csv << "metric,value,unit\n";
  auto report = [&](const char* metric, double value, const char* unit, const char* note) {
    std::printf("%-38s %12.1f %-10s %s\n", metric, value, unit, note);
    csv << metric << "," << value << "," << unit << "\n";
  };
  std::printf("treelearn bench (%u hardware threads)\n", std::thread::hardware_concurrency());

  // physics: one world on one core, then two worlds on two threads
  const int ticks = int(o.seconds / (robot::kSubsteps * robot::kSubstepSeconds));
  const int substeps = ticks * robot::kSubsteps;
  const double one = timeStanding(model, ticks);
  const double usPerStep = one / substeps * 1e6;
  report("physics_us_per_substep_1thread", usPerStep, "us", "(target <= 70; MuJoCo ~25 on a comparable model)");
  report("physics_ratio_to_mujoco", usPerStep / 25.0, "x", "(MuJoCo 2.2.2 figure from research/feasibility.md)");
  report("control_ticks_per_s_1thread", substeps / robot::kSubsteps / one, "ticks/s",
         "(0.01 s ticks, 5 substeps each)");
  double two[2] = {0, 0};
  {
    std::thread a([&] { two[0] = timeStanding(model, ticks); });
    std::thread b([&] { two[1] = timeStanding(model, ticks); });
    a.join();
    b.join();
  }
  const double aggregate = 2.0 * substeps / std::max(two[0], two[1]);
  report("physics_us_per_substep_2threads", 1e6 / aggregate, "us", "(aggregate of two worlds on two threads)");
  report("control_ticks_per_s_2threads", aggregate / robot::kSubsteps, "ticks/s", "");

  // rendering: the flat level's robot scene at 640x360
  levels::Level flat = levels::parseLevel("name = \"bench\"\n", "bench.toml");
  game::PlayOptions po;
  po.ticks = 50;
  engine::SceneSnapshot scene;
  po.frameEvery = 50;
  po.onFrame = [&](const engine::SceneSnapshot& s) { scene = s; };
  game::play(flat, model, po);
  {
    engine::Renderer renderer(640, 360);
    renderer.render(scene);
    auto t = Clock::now();
    for (int i = 0; i < o.frames; ++i) renderer.render(scene);
    report("render_fps_640x360", o.frames / since(t), "frames/s", "(target >= 150; includes reading the pixels)");
    const std::string dir = (std::filesystem::temp_directory_path() / "treelearn_bench_png").string();
    engine::makeDirectories(dir);
    t = Clock::now();
    for (int i = 0; i < o.frames; ++i) {
      renderer.render(scene);
      engine::writePng(dir + "/frame.png", renderer.rgba(), 640, 360);
    }
    report("render_fps_640x360_png", o.frames / since(t), "frames/s", "(target >= 60; zlib level 1)");
    std::filesystem::remove_all(dir);
  }

  // headless play of the flat level, no frames
  game::PlayOptions play;
  play.ticks = int64_t(o.seconds * 100);
  const game::PlayResult r = game::play(flat, model, play);
  report("play_realtime_factor", o.seconds / r.wallSeconds, "x", "(target >= 20; headless, no frames)");

  // levels/mario by autopilot at seeds 1..N (wins out of 10 seeds is the course's measure)
  if (o.autopilotSeeds > 0) {
    std::vector<AutopilotRun> runs;
    for (int i = 1; i <= o.autopilotSeeds; ++i) runs.push_back({&mario, uint64_t(i), "seed " + std::to_string(i)});
    const Totals t = playByAutopilot(runs, model, skills);
    report("autopilot_mario_wins", t.wins, "seeds", ("of " + std::to_string(o.autopilotSeeds)).c_str());
    report("autopilot_mario_falls", t.falls, "falls", "(over all the seeds)");
  }
  // variants 1..N of levels/mario (levels/variant.h), variant N played at seed N
  if (o.variants > 0) {
    std::vector<levels::Level> variants;
    variants.reserve(size_t(o.variants));
    std::vector<AutopilotRun> runs;
    for (int i = 1; i <= o.variants; ++i) {
      const levels::MarioVariant v = levels::drawMarioVariant(uint64_t(i), int(mario.questionBoxes.size()));
      variants.push_back(
          levels::parseLevel(levels::marioVariantToml(mario, v), "variant " + std::to_string(i) + " of " + mario.path));
      std::printf("  variant %-3d %s\n", i, levels::describeVariant(v).c_str());
    }
    for (int i = 1; i <= o.variants; ++i)
      runs.push_back({&variants[size_t(i - 1)], uint64_t(i), "variant " + std::to_string(i)});
    const Totals t = playByAutopilot(runs, model, skills);
    report("autopilot_variants_wins", t.wins, "variants", ("of " + std::to_string(o.variants)).c_str());
    report("autopilot_variants_falls", t.falls, "falls", "(over all the variants)");
  }

  // the garden at seeds 1..N and random garden layouts 1..N (levels/garden_layout.h, layout N at seed N), 240 s each
  if (o.gardens > 0) {
    const levels::Level garden = levels::loadLevel("levels/garden");
    std::vector<levels::Level> layouts;
    layouts.reserve(size_t(o.gardens));
    for (int i = 1; i <= o.gardens; ++i) {
      const levels::GardenLayout g = levels::drawGardenLayout(uint64_t(i));
      layouts.push_back(levels::parseLevel(levels::gardenLayoutToml(g), "garden layout " + std::to_string(i)));
      std::printf("  layout %-3d %s\n", i, levels::describeGardenLayout(g).c_str());
    }
    for (int pass = 0; pass < 2; ++pass) {
      std::vector<AutopilotRun> runs;
      for (int i = 1; i <= o.gardens; ++i)
        runs.push_back({pass == 0 ? &garden : &layouts[size_t(i - 1)], uint64_t(i),
                        (pass == 0 ? "garden " : "layout ") + std::to_string(i)});
      const Totals t = playByAutopilot(runs, model, skills);
      const std::string of = "(over " + std::to_string(o.gardens) + " runs of 240 s)";
      report(pass == 0 ? "autopilot_garden_targets" : "autopilot_layouts_targets", t.targets, "targets", of.c_str());
      report(pass == 0 ? "autopilot_garden_falls" : "autopilot_layouts_falls", t.falls, "falls", of.c_str());
      report(pass == 0 ? "autopilot_garden_runs_without_fall" : "autopilot_layouts_runs_without_fall", t.withoutFall,
             "runs", ("of " + std::to_string(o.gardens)).c_str());
    }
  }

  if (!o.csv.empty()) engine::writeFileAtomic(o.csv, csv.str());
  return 0;
}

}  // namespace apps
