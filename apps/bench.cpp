// bench.cpp — `treelearn bench`: physics (standing G1, 1 and 2 threads), rendering (640x360 with and
// without PNG) and headless play throughput; with --autopilot N, levels/mario by autopilot at seeds 1..N. Timing
// and counts only; nothing here passes or fails.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <thread>

#include "apps/commands.h"
#include "engine/core/file_io.h"
#include "engine/loop/clock.h"
#include "engine/render/png_writer.h"
#include "engine/render/renderer.h"
#include "game/play.h"
#include "levels/level.h"
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

}  // namespace

int runBench(const BenchOptions& o) {
  const robot::RobotModel model = robot::loadRobotModel(robot::defaultRobotConfigPath());
  // --autopilot's level and skills, loaded before the timings so that a missing file stops it at once
  const levels::Level mario = o.autopilotSeeds > 0 ? levels::loadLevel("levels/mario") : levels::Level{};
  const robot::SkillSet skills = o.autopilotSeeds > 0 ? loadSkills(model) : robot::SkillSet{};
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
  report("control_ticks_per_s_1thread", substeps / robot::kSubsteps / one, "ticks/s", "(0.01 s ticks, 5 substeps each)");
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

  // levels/mario by autopilot (issue 6's measure: wins out of 10 seeds), two seeds at a time
  if (o.autopilotSeeds > 0) {
    std::vector<game::PlayResult> results(size_t(o.autopilotSeeds));
    std::atomic<int> next{0};
    auto worker = [&] {
      for (int i; (i = next++) < o.autopilotSeeds;) {
        game::PlayOptions ap;
        ap.seed = uint64_t(i + 1);
        ap.skills = &skills;
        ap.autopilot = true;
        ap.hashEvery = 0;
        ap.ticks = engine::secondsToTicks(mario.timeLimit > 0 ? mario.timeLimit + 0.5 : 600.0);  // until it ends
        results[size_t(i)] = game::play(mario, model, ap);
      }
    };
    std::thread a(worker), b(worker);
    a.join();
    b.join();
    int wins = 0, falls = 0;
    std::map<std::string, int> bySkill;
    for (int i = 0; i < o.autopilotSeeds; ++i) {
      const game::PlayResult& p = results[size_t(i)];
      const bool won = p.outcome == game::Outcome::Won;
      wins += won;
      falls += p.telemetry.falls;
      for (const auto& [skill, n] : p.telemetry.fallsBySkill) bySkill[skill] += n;
      std::printf("  autopilot seed %-3d %-40s %7.2f s  falls %d%s%s\n", i + 1, p.outcomeReason.c_str(),
                  double(p.ticks) * engine::kTickSeconds, p.telemetry.falls, p.telemetry.falls ? ": " : "",
                  game::fallsBySkillText(p.telemetry.fallsBySkill).c_str());
    }
    if (falls > 0) std::printf("  falls by skill over all the seeds: %s\n", game::fallsBySkillText(bySkill).c_str());
    report("autopilot_mario_wins", wins, "seeds", ("of " + std::to_string(o.autopilotSeeds) + " (issue 6's target: 9 of 10)").c_str());
    report("autopilot_mario_falls", falls, "falls", "(over all the seeds)");
  }

  if (!o.csv.empty()) engine::writeFileAtomic(o.csv, csv.str());
  return 0;
}

}  // namespace apps
