// main.cpp — the treelearn command line: play, replay, variant, bench, entries, train, eval, ship, tree. Parses
// arguments with CLI11, turns engine::Error into "error: ..." and exit code 2.
#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "ai/dist/comm.h"
#include "ai/onnx/policy_onnx.h"
#include "ai/onnx/skill_metadata.h"
#include "apps/commands.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"
#include "engine/loop/clock.h"
#include "engine/render/frame_output.h"
#include "game/garden_pilot.h"
#include "game/play.h"
#include "levels/garden_layout.h"
#include "levels/level.h"
#include "levels/variant.h"
#include "robot/robot_model.h"
#include "robot/skill_layout.h"
#include "robot/skill_tree.h"

namespace {

constexpr int kExitExpectationFailed = 1;
constexpr int kExitBadInput = 2;
constexpr int kFrameWidth = 640, kFrameHeight = 360;

struct OutputOptions {
  std::string framesDir, videoPath;
  int fps = 50;
  std::string camera = "side";
};

// ticks between rendered frames for a given frame rate (100 Hz ticks)
int frameEvery(int fps) { return std::max(1, int(std::lround(1.0 / (fps * engine::kTickSeconds)))); }

std::string resolveKeys(const std::string& keys, const levels::Level& level) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(keys, ec)) return keys;
  const fs::path inLevel = fs::path(level.directory) / keys;
  if (fs::exists(inLevel, ec)) return inLevel.string();
  return keys;  // readFile reports it missing
}

// the garden pilot's lines: targets, stuck recoveries, falls, distance and speed, and each skill's share of the time
std::string gardenSummaryText(const game::PlayResult& r) {
  const game::GardenReport& g = r.garden;
  if (!g.played) return "";
  const double seconds = double(r.ticks) * engine::kTickSeconds;
  std::ostringstream s;
  char line[512];
  std::snprintf(line, sizeof line,
                "targets    %d reached of %d given; stuck recoveries %d; falls %d; no path %d; replans %d\n",
                g.targetsReached, g.targetsGiven, g.stuck, r.telemetry.falls, g.noPath, g.replans);
  s << line;
  std::snprintf(line, sizeof line, "travelled  %.1f m in %.1f s, mean speed %.2f m/s\n", r.telemetry.distance, seconds,
                seconds > 0 ? r.telemetry.distance / seconds : 0.0);
  s << line;
  int64_t ticks = 0;
  for (const auto& [name, st] : g.skills) ticks += st.ticks;
  for (const auto& [name, st] : g.skills) {
    std::snprintf(line, sizeof line,
                  "gait       %-7s %5.1f %% of the time (%.1f s), %.1f m, largest roll %.1f deg, pitch %.1f deg\n",
                  name.c_str(), ticks ? 100.0 * double(st.ticks) / double(ticks) : 0.0,
                  double(st.ticks) * engine::kTickSeconds, st.distance, st.maxRoll * 180.0 / M_PI,
                  st.maxPitch * 180.0 / M_PI);
    s << line;
  }
  return s.str();
}

std::string summaryText(const levels::Level& level, const game::PlayResult& r, uint64_t seed, const char* outcome) {
  const game::Telemetry& t = r.telemetry;
  const double simSeconds = double(r.ticks) * engine::kTickSeconds;
  std::ostringstream s;
  char line[512];
  std::snprintf(line, sizeof line, "level      %s (%s)\n", level.name.c_str(), level.path.c_str());
  s << line;
  s << "seed       " << seed << "\n";
  s << "outcome    " << outcome << "\n";
  std::snprintf(line, sizeof line, "time       %.2f s simulated in %.2f s wall (%.1fx real time)\n", simSeconds,
                r.wallSeconds, r.wallSeconds > 0 ? simSeconds / r.wallSeconds : 0.0);
  s << line;
  if (level.isGame() || !level.coins.empty()) {
    std::snprintf(line, sizeof line, "score      %d (coins %d, gifts %d)\n", r.score, r.coins, r.gifts);
    s << line;
  } else {
    s << "score      0 (this level has no scoring entities)\n";
  }
  s << "falls      " << t.falls;
  if (r.fallen) {
    std::snprintf(line, sizeof line, " (the first at %.2f s)", double(r.fallTick) * engine::kTickSeconds);
    s << line;
  }
  if (!t.fallsBySkill.empty()) s << "; by skill: " << game::fallsBySkillText(t.fallsBySkill);
  s << "\n";
  std::string keys, used;
  for (int k : t.skillsRequested) keys += (keys.empty() ? "" : ", ") + std::to_string(k);
  for (const std::string& u : t.skillsUsed) used += (used.empty() ? "" : ", ") + u;
  s << "skills     used: " << (used.empty() ? "none (standing controller)" : used)
    << "; requested keys: " << (keys.empty() ? "none" : keys) << "\n";
  if (!t.switches.empty()) {
    s << "switches   " << t.switches.size() << ":";
    for (size_t i = 0; i < t.switches.size(); ++i) {
      if (i == 8) {
        s << " ...";
        break;
      }
      const game::SwitchEvent& e = t.switches[i];
      std::snprintf(line, sizeof line, "%s %s->%s at %.2f s", i ? "," : "", e.from.c_str(), e.to.c_str(),
                    double(e.tick) * engine::kTickSeconds);
      s << line;
    }
    s << "\n";
  }
  std::snprintf(line, sizeof line, "pelvis     mean height %.3f m (min %.3f, max %.3f), max tilt %.1f deg\n",
                t.ticks ? t.sumPelvisHeight / double(t.ticks) : 0.0, t.minPelvisHeight, t.maxPelvisHeight,
                t.maxTilt * 180.0 / M_PI);
  s << line;
  std::snprintf(line, sizeof line, "position   x %.3f y %.3f m, path length %.3f m\n", r.finalSensors.basePosition.x(),
                r.finalSensors.basePosition.y(), t.distance);
  s << line;
  s << "state hash " << engine::toHex(r.finalHash) << " after " << r.ticks << " ticks\n";
  for (const game::SwitchReport& w : r.switchReports) {
    std::snprintf(line, sizeof line,
                  "switch     %s->%s at %.2f s: forward speed %.2f -> %.2f m/s, peak acceleration %.1f m/s^2\n",
                  w.event.from.c_str(), w.event.to.c_str(), double(w.event.tick) * engine::kTickSeconds, w.speedBefore,
                  w.speedAfter, w.peakAcceleration);
    s << line;
  }
  for (const game::CourseEvent& e : r.events) {
    std::snprintf(line, sizeof line, "event      %7.2f s  %s\n", double(e.tick) * engine::kTickSeconds, e.what.c_str());
    s << line;
  }
  s << gardenSummaryText(r);
  return s.str();
}

// plays with optional frame output; shared by play and replay
game::PlayResult runWithOutput(const levels::Level& level, const robot::RobotModel& model, game::PlayOptions options,
                               const OutputOptions& out) {
  std::unique_ptr<engine::FrameOutput> frames;
  if (!out.framesDir.empty() || !out.videoPath.empty()) {
    if (out.camera != "side" && out.camera != "chase") throw engine::Error("--camera must be side or chase");
    frames = std::make_unique<engine::FrameOutput>(out.framesDir, out.videoPath, kFrameWidth, kFrameHeight, out.fps);
    options.frameEvery = frameEvery(out.fps);
    options.camera = out.camera == "chase" ? engine::CameraMode::Chase : engine::CameraMode::Side;
    options.onFrame = [&](const engine::SceneSnapshot& s) { frames->add(s); };
  }
  game::PlayResult r = game::play(level, model, options);
  if (frames) {
    frames->finish();
    if (!out.videoPath.empty())
      std::printf("video      %s (%d frames at %d fps)\n", out.videoPath.c_str(), frames->frames(), out.fps);
    if (!out.framesDir.empty()) std::printf("frames     %s (%d PNG files)\n", out.framesDir.c_str(), frames->frames());
  }
  return r;
}

struct PlayArgs {
  std::string level, keys, record, expect, summary, log, targets;
  double seconds = -1;
  uint64_t seed = 1;
  bool seedGiven = false;  // --seed on the command line (it overrides a key script's seed line)
  bool autopilot = false;
  OutputOptions out;
};

// creates the folder an output file goes into, so `--video out/run.mp4` works on a fresh clone
void makeParentDirectory(const std::string& file) {
  const std::filesystem::path parent = std::filesystem::path(file).parent_path();
  if (!file.empty() && !parent.empty()) engine::makeDirectories(parent.string());
}

int cmdPlay(const PlayArgs& a) {
  const levels::Level level = levels::loadLevel(a.level);
  for (const std::string* f : {&a.record, &a.summary, &a.log, &a.out.videoPath}) makeParentDirectory(*f);
  const robot::RobotModel model = robot::loadRobotModel(robot::defaultRobotConfigPath());
  const robot::SkillSet skills = apps::loadSkills(model);
  if (a.autopilot && !level.isGame() && !game::isMapLevel(level))
    throw engine::Error(level.path +
                        ": --autopilot plays game levels (a level with [rules] and a goal) and maps "
                        "(plane = \"top\")");
  if (!a.targets.empty() && !(a.autopilot && game::isMapLevel(level)))
    throw engine::Error(
        "--targets gives the garden pilot its targets: it needs --autopilot on a map level (plane = \"top\")");
  if (a.autopilot && !a.keys.empty()) throw engine::Error("--autopilot and --keys exclude each other");
  if (!a.expect.empty() && a.expect != "alive" && a.expect != "win")
    throw engine::Error("--expect must be 'alive' or 'win', not '" + a.expect + "'");
  if (a.expect == "win" && !level.isGame())
    throw engine::Error(level.path + ": level '" + level.name +
                        "' has no goal, so it cannot be won (use --expect alive)");

  game::PlayOptions options;
  options.seed = a.seed;
  options.skills = &skills;
  options.autopilot = a.autopilot;
  if (!a.targets.empty()) options.targets = game::parseTargets(engine::readFile(a.targets), a.targets);
  if (!a.keys.empty()) {
    const std::string path = resolveKeys(a.keys, level);
    const engine::KeyScript script = engine::parseKeyScriptWithSeed(engine::readFile(path), path);
    options.events = script.events;
    if (script.seed && !a.seedGiven) options.seed = *script.seed;
    if (script.seed && a.seedGiven && a.seed != *script.seed)
      std::fprintf(stderr,
                   "note: --seed %llu overrides %s:%d (seed %llu): another start, so the keys play another run\n",
                   static_cast<unsigned long long>(a.seed), path.c_str(), script.seedLine,
                   static_cast<unsigned long long>(*script.seed));
  }
  double seconds = a.seconds;
  if (seconds < 0)
    seconds = options.events.empty() ? 10.0 : double(options.events.back().tick) * engine::kTickSeconds + 2.0;
  if (a.seconds < 0 && level.isGame()) seconds = level.timeLimit > 0 ? level.timeLimit + 0.5 : 600.0;  // until it ends
  if (a.seconds < 0 && a.autopilot && game::isMapLevel(level)) seconds = 240.0;  // the paper's garden run
  if (!(seconds > 0) || seconds > 86400) throw engine::Error("--seconds must be in (0, 86400]");
  options.ticks = engine::secondsToTicks(seconds);
  if (!options.events.empty() && options.events.back().tick >= options.ticks)
    std::fprintf(stderr, "warning: the key script runs past --seconds %.2f; later events are ignored\n", seconds);

  const game::PlayResult r = runWithOutput(level, model, options, a.out);
  std::string outcome = r.fallen ? "fell" : "alive (no fall)";
  if (level.isGame())
    outcome = r.outcome == game::Outcome::Won    ? "won (" + r.outcomeReason + ")"
              : r.outcome == game::Outcome::Lost ? "lost (" + r.outcomeReason + ")"
                                                 : std::string("not finished (the run ended first)");
  std::string summary = summaryText(level, r, options.seed, outcome.c_str());
  for (const robot::MissingSkill& m : skills.missing)  // a key the script or autopilot pressed that had no model
    if (r.telemetry.skillsRequested.count(m.key))
      summary += "missing    key " + std::to_string(m.key) + " (" + m.name + "): no model at " + m.path +
                 ", so the key did nothing\n";
  std::fputs(summary.c_str(), stdout);
  if (!a.summary.empty()) engine::writeFileAtomic(a.summary, summary);
  if (!a.log.empty()) {
    std::string csv = "t_s,skill,com_x_m,com_z_m,com_vx_m_per_s,com_y_m,yaw_rad,com_left_of_feet_m";
    // a garden run adds the pilot's columns (the same 50 Hz rows)
    const std::vector<game::GardenSample>& g = r.garden.samples;
    const bool garden = r.garden.played && g.size() == r.comLog.size();
    if (garden)
      csv +=
          ",pelvis_x_m,pelvis_y_m,pelvis_z_m,vel_x_m_per_s,vel_y_m_per_s,vr_m_per_s,wr_rad_per_s,nav_vr_m_per_s,"
          "nav_wr_rad_per_s,target,target_x_m,target_y_m,target_distance_m,target_angle_rad,obstacle_factor,roll_rad,"
          "pitch_rad,mode,events";
    csv += "\n";
    char row[512];
    for (size_t i = 0; i < r.comLog.size(); ++i) {
      const game::ComSample& c = r.comLog[i];
      std::snprintf(row, sizeof row, "%.2f,%s,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f", c.t, c.skill.c_str(), c.x, c.z, c.vx, c.y,
                    c.yaw, c.leftOfFeet);
      csv += row;
      if (garden) {
        const game::GardenSample& m = g[i];
        const Eigen::Vector2d t = m.target >= 0 && m.target < int(r.garden.targets.size())
                                      ? r.garden.targets[size_t(m.target)]
                                      : Eigen::Vector2d(NAN, NAN);
        std::snprintf(row, sizeof row,
                      ",%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%d,%.3f,%.3f,%.4f,%.4f,%.4f,%.4f,%.4f,%s,%s", m.x,
                      m.y, m.z, m.vx, m.vy, m.vr, m.wr, m.navVr, m.navWr, m.target, t.x(), t.y(), m.targetDistance,
                      m.targetAngle, m.obstacleFactor, m.roll, m.pitch, m.mode.c_str(), m.events.c_str());
        csv += row;
      }
      csv += "\n";
    }
    engine::writeFileAtomic(a.log, csv);
  }

  if (!a.record.empty()) {
    engine::Replay replay;
    replay.level = a.level;
    replay.levelHash = level.hash;
    replay.robotHash = model.hash;
    replay.skillsHash = skills.hash;
    replay.seed = options.seed;
    replay.ticks = r.ticks;
    replay.hashEvery = options.hashEvery;
    for (const engine::KeyEvent& e : r.keyEvents)  // the script's or the autopilot's, as applied
      if (e.tick < r.ticks) replay.events.push_back(e);
    replay.states = r.hashes;
    engine::saveReplay(a.record, replay);
    std::printf("replay     %s (%zu events, %zu state hashes)\n", a.record.c_str(), replay.events.size(),
                replay.states.size());
  }
  if (a.expect == "win") {
    if (r.outcome != game::Outcome::Won) {
      std::printf("expectation 'win' FAILED: %s\n", outcome.c_str());
      return kExitExpectationFailed;
    }
    std::printf("expectation 'win' met\n");
    return 0;
  }
  if (a.expect == "alive" && r.fallen) {
    std::printf("expectation 'alive' FAILED: the robot fell at %.2f s\n", double(r.fallTick) * engine::kTickSeconds);
    return kExitExpectationFailed;
  }
  if (a.expect == "alive") std::printf("expectation 'alive' met\n");
  return 0;
}

struct ReplayArgs {
  std::string file, keysOut;
  bool verify = false;
  OutputOptions out;
};

// a replay's level as named when it was recorded (relative to the folder play ran in): from this folder; else from
// the closest folder above the replay file that holds it (a replay kept inside the tree it was recorded in); else in
// the source tree this binary was built from. The level's hash is checked after, so a wrong find is refused.
std::string replayLevelPath(const std::string& replayFile, const std::string& level) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::path(level).is_absolute() || fs::exists(level, ec)) return level;
  for (fs::path dir = fs::absolute(replayFile, ec).parent_path(); !ec && !dir.empty(); dir = dir.parent_path()) {
    if (fs::exists(dir / level, ec)) return (dir / level).string();
    if (dir == dir.root_path()) break;
  }
  return engine::projectFile(level);
}

int cmdReplay(const ReplayArgs& a) {
  const engine::Replay replay = engine::loadReplay(a.file);
  if (!a.keysOut.empty()) {  // before the checks below: the keys of a run stay readable after its models change
    makeParentDirectory(a.keysOut);
    engine::writeFileAtomic(a.keysOut,
                            engine::formatKeyScript(replay.events, replay.seed,
                                                    "the key events of " + a.file + " (level " + replay.level + ")"));
    std::printf("keys       %s (%zu events, seed %llu)\n", a.keysOut.c_str(), replay.events.size(),
                static_cast<unsigned long long>(replay.seed));
  }
  makeParentDirectory(a.out.videoPath);
  const levels::Level level = levels::loadLevel(replayLevelPath(a.file, replay.level));
  const robot::RobotModel model = robot::loadRobotModel(robot::defaultRobotConfigPath());
  if (level.hash != replay.levelHash)
    throw engine::Error(a.file + ": level '" + replay.level + "' has changed since recording (hash " +
                        engine::toHex(level.hash) + ", replay has " + engine::toHex(replay.levelHash) + ")");
  if (model.hash != replay.robotHash)
    throw engine::Error(a.file + ": the robot model has changed since recording (hash " + engine::toHex(model.hash) +
                        ", replay has " + engine::toHex(replay.robotHash) + ")");
  const robot::SkillSet skills = apps::loadSkills(model);
  if (replay.skillsHash != skills.hash)
    throw engine::Error(a.file + ": the skill models have changed since recording (hash " + engine::toHex(skills.hash) +
                        ", replay has " + engine::toHex(replay.skillsHash) + "); record it again");

  game::PlayOptions options;
  options.seed = replay.seed;
  if (a.verify && replay.states.empty())
    throw engine::Error(a.file + ": the recording holds no state hashes, so there is nothing to verify");
  // --verify simulates up to the last recorded state: nothing after it can be compared
  options.ticks =
      a.verify ? (replay.states.empty() ? 0 : std::min(replay.ticks, replay.states.back().tick)) : replay.ticks;
  options.events = replay.events;
  options.hashEvery = replay.hashEvery;
  options.skills = &skills;
  if (a.verify) options.expected = &replay.states;
  const game::PlayResult r = runWithOutput(level, model, options, a.out);
  if (!a.verify) {
    std::fputs(summaryText(level, r, replay.seed, r.fallen ? "fell" : "alive (no fall)").c_str(), stdout);
    return 0;
  }
  if (r.divergedTick >= 0) {
    uint64_t recorded = 0;
    for (const auto& s : replay.states)
      if (s.tick == r.divergedTick) recorded = s.hash;
    std::printf("diverged at tick %lld (%.2f s): recorded %s, re-simulated %s\n", (long long)r.divergedTick,
                double(r.divergedTick) * engine::kTickSeconds, engine::toHex(recorded).c_str(),
                engine::toHex(r.hashes.back().hash).c_str());
    return kExitExpectationFailed;
  }
  std::printf("identical: %zu state hashes over %lld ticks match (the recording is %lld ticks)\n", replay.states.size(),
              (long long)options.ticks, (long long)replay.ticks);
  return 0;
}

struct VariantArgs {
  std::string level, out;
  uint64_t seed = 1;
};

// writes seed's variant of a Mario-style level to OUT/level.toml (checked to load first; written atomically)
// (a map level with a staircase, levels/garden: a random garden layout, levels/garden_layout.h)
int cmdVariant(const VariantArgs& a) {
  const levels::Level base = levels::loadLevel(a.level);
  std::string text, description;
  const bool garden = game::isMapLevel(base) && std::any_of(base.boxes.begin(), base.boxes.end(),
                                                            [](const levels::BoxDef& b) { return b.stairs; });
  if (garden) {  // a map with a staircase (levels/garden; not levels/flat)
    const levels::GardenLayout g = levels::drawGardenLayout(a.seed);
    text = levels::gardenLayoutToml(g), description = levels::describeGardenLayout(g);
  } else {
    const levels::MarioVariant v = levels::drawMarioVariant(a.seed, int(base.questionBoxes.size()));
    text = levels::marioVariantToml(base, v), description = levels::describeVariant(v);
  }
  levels::parseLevel(text,
                     "variant " + std::to_string(a.seed) + " of " + base.path);  // it loads, or nothing is written
  engine::makeDirectories(a.out);
  const std::string path = (std::filesystem::path(a.out) / "level.toml").string();
  engine::writeFileAtomic(path, text);
  std::printf("variant    %s (seed %llu of %s): %s\n", path.c_str(), static_cast<unsigned long long>(a.seed),
              base.path.c_str(), description.c_str());
  return 0;
}

void addOutputOptions(CLI::App* cmd, OutputOptions* out) {
  cmd->add_option("--frames", out->framesDir, "Write PNG frames (640x360) into this folder");
  cmd->add_option("--video", out->videoPath, "Write an MP4 video (needs ffmpeg)");
  cmd->add_option("--fps", out->fps, "Frames per second of --frames/--video")->check(CLI::Range(1, 100));
  cmd->add_option("--camera", out->camera, "Camera: side or chase")->check(CLI::IsMember({"side", "chase"}));
}

}  // namespace

int main(int argc, char** argv) {
  Eigen::setNbThreads(1);  // matrix products are threaded only inside the PPO update (ai::Trainer)
  CLI::App app{
      "treelearn: a Unitree G1 humanoid in Bullet that learns a tree of skills and plays levels with them.\n"
      "Run 'treelearn <command> --help' for a command's options."};
  app.require_subcommand(1);
  // a seed is a whole number 0..2^64-1 ("-1" would wrap around to 2^64-1), a real option a finite number
  const CLI::Validator seedNumber(
      [](std::string& v) {
        return v.empty() || v[0] == '-' || v[0] == '+' ? std::string("a seed is a whole number >= 0") : "";
      },
      "SEED");
  const CLI::Validator finite(
      [](std::string& v) {
        char* end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        return end == v.c_str() || *end != '\0' || !std::isfinite(x) ? std::string("must be a finite number") : "";
      },
      "FINITE");
  std::string treeFile;
  app.add_option("--tree", treeFile,
                 "Skill tree file for train, eval, ship, tree and play (default assets/skills/tree.toml); "
                 "give it before the command")
      ->check(CLI::ExistingFile);

  PlayArgs play;
  CLI::App* playCmd = app.add_subcommand("play", "Play a level headless and print a summary");
  playCmd->add_option("level", play.level, "Level folder (holding level.toml) or .toml file")->required();
  playCmd->add_option("--keys", play.keys, "Keyboard script (a path, or a file name inside the level folder)");
  playCmd->add_flag("--autopilot", play.autopilot,
                    "Let the autopilot play a game level from what the robot perceives (not with --keys); on a map "
                    "(plane = top, e.g. levels/garden) the garden pilot walks to targets drawn from --seed");
  playCmd->add_option("--targets", play.targets,
                      "The garden pilot's targets instead of random ones: a file with one 'x y' line (metres) per "
                      "target, '#' comments");
  playCmd->add_option("--seconds", play.seconds, "Simulated seconds (default: script end + 2 s, or 10 s)")
      ->check(CLI::Range(0.01, 86400.0));
  playCmd->add_option("--seed", play.seed, "Random seed (default: the key script's seed line, else 1)")
      ->check(seedNumber);
  playCmd->add_option("--record", play.record, "Write a replay file");
  playCmd->add_option("--summary", play.summary, "Also write the summary to this file");
  playCmd->add_option(
      "--log", play.log,
      "Write the centre of mass at 50 Hz to a CSV file (time, skill, x, height, forward speed, y, heading, offset left "
      "of the feet; a garden run adds pelvis, velocity, commands, target, obstacle factor, roll, pitch, events)");
  playCmd->add_option("--expect", play.expect, "Exit 1 unless this holds: alive (no fall) or win")
      ->check(CLI::IsMember({"alive", "win"}));
  addOutputOptions(playCmd, &play.out);

  ReplayArgs replay;
  CLI::App* replayCmd = app.add_subcommand("replay", "Re-simulate a replay file");
  replayCmd->add_option("replay", replay.file, "Replay file written by play --record")->required();
  replayCmd->add_flag("--verify", replay.verify, "Check the recorded state hashes; report the first diverging tick");
  replayCmd->add_option(
      "--keys-out", replay.keysOut,
      "Also write the replay's key events as a key script, with its seed line (e.g. an autopilot run's keys)");
  addOutputOptions(replayCmd, &replay.out);

  VariantArgs variant;
  CLI::App* variantCmd = app.add_subcommand(
      "variant",
      "Write a variant drawn from a seed to OUT/level.toml: of a Mario-style course (stairs, tunnel, question boxes, "
      "ball, ghost speed; ranges in levels/variant.h), or for a map level (levels/garden) a random garden layout "
      "(river and bridge, short staircase, houses, balls; levels/garden_layout.h)");
  variantCmd
      ->add_option("level", variant.level, "The level it varies: a folder or .toml file (levels/mario, levels/garden)")
      ->required();
  variantCmd->add_option("--seed", variant.seed, "Seed of the variant (the same seed writes the same file)")
      ->check(seedNumber)
      ->required();
  variantCmd->add_option("--out", variant.out, "Folder to write level.toml into (created if missing)")->required();

  apps::EntriesRecordOptions entriesRecord;
  apps::EntriesCardOptions entriesCard;
  CLI::App* entriesCmd = app.add_subcommand(
      "entries", "Play's handover states: record them from autopilot runs and key scripts, run the play-entry cards");
  entriesCmd->require_subcommand(1);
  CLI::App* entriesRecordCmd = entriesCmd->add_subcommand(
      "record", "Play a game level by autopilot (and key scripts) and write every handover into OUT/SKILL.entries");
  entriesRecordCmd->add_option("--level", entriesRecord.level, "The game level (default levels/mario)");
  entriesRecordCmd->add_option("--first-seed", entriesRecord.firstSeed, "First autopilot seed (default 1)")
      ->check(seedNumber);
  entriesRecordCmd->add_option("--last-seed", entriesRecord.lastSeed, "Last autopilot seed (default 20)")
      ->check(seedNumber);
  entriesRecordCmd->add_option("--keys", entriesRecord.keys,
                               "Key scripts to play too (a path, or a file name inside the level folder); repeatable");
  entriesRecordCmd->add_option("--out", entriesRecord.out, "Folder for the SKILL.entries files (default runs/entries)");
  entriesRecordCmd->add_option("--threads", entriesRecord.threads, "Runs played side by side (default 2)")
      ->check(CLI::Range(1, 64));
  CLI::App* entriesCardCmd = entriesCmd->add_subcommand(
      "card", "Start each skill from its recorded handover states, replay the keys, and count the ones that held");
  entriesCardCmd->add_option("dir", entriesCard.dir, "Folder holding SKILL.entries files")
      ->required()
      ->check(CLI::ExistingDirectory);
  entriesCardCmd->add_option("--skill", entriesCard.skill, "Only this skill");
  entriesCardCmd
      ->add_option("--model", entriesCard.model,
                   "ONNX file to run as --skill's model instead of the shipped one (a run's export)")
      ->check(CLI::ExistingFile);
  entriesCardCmd->add_option("--threads", entriesCard.threads, "Threads (default 2)")->check(CLI::Range(1, 64));
  entriesCardCmd->add_flag("--verbose", entriesCard.verbose, "List the entries that fell");

  apps::BenchOptions bench;
  CLI::App* benchCmd = app.add_subcommand("bench", "Measure physics, rendering and play throughput");
  benchCmd->add_option("--seconds", bench.seconds, "Simulated seconds per physics measurement")
      ->check(CLI::Range(0.1, 3600.0));
  benchCmd->add_option("--frames", bench.frames, "Frames per rendering measurement")->check(CLI::Range(1, 100000));
  benchCmd->add_option("--csv", bench.csv, "Also write the results as CSV");
  // the autopilot's runs: how many seeds, variants or gardens
  auto runsOption = [&](const char* name, int* n, const char* help) {
    benchCmd->add_option(name, *n, help)->check(CLI::Range(1, 1000));
  };
  runsOption("--autopilot", &bench.autopilotSeeds,
             "Also play levels/mario by autopilot at seeds 1..N (two at a time) and report wins, winning times and "
             "falls");
  runsOption("--variants", &bench.variants,
             "Also play variants 1..N of levels/mario (treelearn variant) by autopilot (two at a time) and report "
             "each one's outcome, time and falls by skill, and the totals");
  runsOption("--gardens", &bench.gardens,
             "Also play levels/garden at seeds 1..N and random garden layouts 1..N (treelearn variant levels/garden; "
             "layout N at seed N) by autopilot for 240 s each (two at a time), and report targets reached, falls and "
             "runs without a fall for each set");

  apps::TrainOptions train;
  CLI::App* trainCmd = app.add_subcommand("train",
                                          "Train a skill with PPO (a branch starts from its parent); the model is "
                                          "exported into the run folder (install it with ship)");
  trainCmd->add_option("skill", train.skill, "Skill name from assets/skills/tree.toml")->required();
  trainCmd->add_option("--steps", train.steps, "Environment steps (default: the skill's budget)")
      ->check(CLI::Range(int64_t(1), int64_t(10000000000)));
  trainCmd->add_flag("--resume", train.resume,
                     "Continue the run in the run folder exactly where its checkpoint stopped");
  trainCmd
      ->add_option("--threads", train.threads,
                   "Threads stepping the environments (default 2; under mpirun, the cores shared by the ranks on "
                   "a machine)")
      ->check(CLI::Range(1, 64));
  trainCmd->add_option("--envs", train.envs, "Parallel environments (must divide the PPO buffer)")
      ->check(CLI::Range(1, 4096));
  trainCmd->add_option("--seed", train.seed, "Run seed (default 1)")->check(seedNumber);
  trainCmd->add_option("--run-dir", train.runDir,
                       "Run folder for log.csv, checkpoint.bin, best.bin and the exported SKILL.onnx and "
                       "SKILL.policy.bin (default runs/SKILL)");
  trainCmd->add_option("--eval-every", train.evalEvery, "Iterations between report-card evaluations (0 = never)")
      ->check(CLI::Range(0, 100000));
  trainCmd
      ->add_option("--eval-episodes", train.evalEpisodes,
                   "Episodes per report-card evaluation during training (default 10; more = a steadier choice of the "
                   "best policy)")
      ->check(CLI::Range(1, 1000));
  trainCmd
      ->add_option("--eval-confirm", train.evalConfirm,
                   "Episodes of a second card, on other episodes, run when an evaluation beats the best confirmed so "
                   "far; its score then picks best.bin (default 0: none; the evaluations always replay the same "
                   "episodes, so their best reads high)")
      ->check(CLI::Range(0, 1000));
  trainCmd
      ->add_option("--reinflate-log-std", train.reinflateLogStd,
                   "Branch init: raise the inherited log-std to at least this")
      ->check(finite & CLI::Range(-5.0, 1.0));
  trainCmd
      ->add_option("--init-log-std", train.initLogStd,
                   "Branch or --init-from fine-tune: set the log-std to this (e.g. -2: less exploration noise around a "
                   "precise prior or policy)")
      ->check(finite & CLI::Range(-5.0, 1.0));
  trainCmd
      ->add_option("--critic-warmup", train.criticWarmup,
                   "Iterations at the start that update only the critic (a branch's inherited critic learns the "
                   "branch's rewards before its advantages move the actor)")
      ->check(CLI::Range(0, 100000));
  trainCmd->add_flag("--freeze-normalizer", train.freezeNormalizer,
                     "Keep the observation normaliser's statistics as loaded (fine-tuning on new states without moving "
                     "the policy's inputs)");
  trainCmd->add_flag("--zero-output", train.zeroOutput,
                     "Branch init: zero the actor's output layer, so the branch starts as its own prior alone (hidden "
                     "layers, critic, normaliser and log-std stay the parent's)");
  trainCmd->add_option("--init-from", train.initFrom,
                       "Start from this policy file (e.g. assets/skills/walk.policy.bin) to fine-tune");
  trainCmd
      ->add_option("--learning-rate", train.learningRate,
                   "Initial learning rate instead of [ppo]'s learning_rate (a branch from its parent: "
                   "branch_learning_rate, 3e-5 by default; e.g. 1e-4 to fine-tune with --init-from)")
      ->check(finite);
  trainCmd->add_option("--models-dir", train.modelsDir,
                       "Folder the other skills' models are read from: the parent's policy, handover and card drivers "
                       "(default: the tree file's folder, assets/skills); nothing is written there");
  trainCmd
      ->add_option("--export-from", train.exportFrom, "With --export-only: best (best.bin) or last (checkpoint.bin)")
      ->check(CLI::IsMember({"best", "last"}));
  trainCmd->add_flag(
      "--export-only", train.exportOnly,
      "Only export the run's policy (--export-from) to the run folder's SKILL.onnx and SKILL.policy.bin (no training)");

  ai::TrainMultiOptions multitask;
  CLI::App* multitaskCmd = app.add_subcommand(
      "multitask",
      "Train one network on several skills at once (the paper's multi-task baseline): each skill's own training "
      "episodes, rewards and terminations from the tree file, the skill told by a one-hot after its observation; "
      "writes RUN/multitask.policy.bin, RUN/skills.txt, RUN/skills.csv (each skill's episodes per iteration) and "
      "log.csv; its cards: eval SKILL --multitask RUN");
  multitaskCmd->add_option("--skills", multitask.skills,
                           "Skills, in one-hot order (default: the paper's six, walk run squat jump crawl one_leg)");
  multitaskCmd->add_option("--steps", multitask.steps, "Environment steps in all, every skill's together (default 1e7)")
      ->check(CLI::Range(int64_t(1), int64_t(1) << 40));
  multitaskCmd->add_option("--envs-per-skill", multitask.envsPerSkill, "Environments per skill (default 4)")
      ->check(CLI::Range(1, 256));
  multitaskCmd
      ->add_option("--threads", multitask.threads,
                   "Threads (default 2; under mpirun, the cores shared by the ranks on a machine)")
      ->check(CLI::Range(1, 64));
  multitaskCmd->add_option("--seed", multitask.seed, "Seed of the fresh weights and the episodes (default 1)")
      ->check(seedNumber);
  multitaskCmd->add_option("--run-dir", multitask.runDir, "Run folder (default runs/multitask)");
  multitaskCmd->add_flag("--resume", multitask.resume, "Continue from RUN/checkpoint.bin");
  multitaskCmd->add_flag(
      "--adaptive-rate", [&](int64_t) { multitask.linearRate = false; },
      "The tree file's KL-adaptive learning rate instead of the paper's linear schedule (Table 2: the paper's "
      "baseline's and the tree's walk's from scratch)");
  multitaskCmd->add_option("--init-from", multitask.initFrom,
                           "Start from this skill's policy file (e.g. assets/skills/walk.policy.bin: inheritance "
                           "without isolation), the one-hot's inputs at zero weight, at [ppo] branch_learning_rate "
                           "with the tree's adaptive rate, instead of fresh weights");
  multitaskCmd->add_option("--models-dir", multitask.modelsDir,
                           "Folder the handover episodes' drivers are read from (default: the tree file's folder)");

  apps::ExperimentOptions experiment;
  CLI::App* experimentCmd = app.add_subcommand("experiment", "Experiments that train and measure several runs");
  experimentCmd->require_subcommand(1);
  CLI::App* compareCmd = experimentCmd->add_subcommand(
      "compare",
      "The paper's comparison (docs/comparison.md): the tree arm (each of walk, run, squat, jump, crawl, one_leg "
      "from its parent's shipped weights, the walk from scratch), one network trained on the six in turn (the "
      "sequential arm), and one multi-task network from scratch at the same steps in all and at the tree's total, "
      "and from the walk's weights; each final policy's rewards in its skill's training episodes and its card into "
      "OUT/results.csv, after each stage the cards of the skills learnt so far into OUT/matrices.csv "
      "(forgetting and retention), and the tree arm's switch matrix into OUT/switches.csv. Given again, it goes on "
      "where it stopped");
  compareCmd->add_option("--out", experiment.out, "Output folder (default runs/compare)");
  compareCmd
      ->add_option("--steps-scale", experiment.stepsScale,
                   "Budget as a share of the paper's 10^7 steps per skill (default 1; 0.001 for a smoke run)")
      ->check(finite & CLI::Range(1e-6, 100.0));
  compareCmd->add_option("--seeds", experiment.seeds, "Seeds 1..N of every arm (default 1)")->check(CLI::Range(1, 20));
  compareCmd->add_option("--threads", experiment.threads, "Threads (default 2)")->check(CLI::Range(1, 64));
  compareCmd->add_option("--reward-envs", experiment.rewardEnvs, "Environments of the rewards measure (default 20)")
      ->check(CLI::Range(1, 256));
  compareCmd
      ->add_option("--reward-rollouts", experiment.rewardRollouts,
                   "Rollouts of one episode's time limit in the rewards measure (default 2)")
      ->check(CLI::Range(1, 100));
  compareCmd->add_option("--card-episodes", experiment.cardEpisodes, "Episodes of each card (default: the card's own)")
      ->check(CLI::Range(1, 10000));
  compareCmd
      ->add_option("--switch-trials", experiment.switchTrials,
                   "Trials of each switch in the tree arm's switch matrix (default 10, as eval switches)")
      ->check(CLI::Range(1, 1000));

  apps::ShipOptions ship;
  CLI::App* shipCmd = app.add_subcommand(
      "ship",
      "Install a trained model: run its report card and, if it passes, copy RUN/SKILL.onnx and RUN/SKILL.policy.bin "
      "into the tree's folder (assets/skills) and record the card there; exit 1 and install nothing if it fails");
  shipCmd->add_option("skill", ship.skill, "Skill name from the tree file")->required();
  shipCmd->add_option("--from", ship.runDir,
                      "Run folder holding the exported SKILL.onnx and SKILL.policy.bin, as train or train "
                      "--export-only wrote them (default runs/SKILL)");
  shipCmd->add_flag("--force", ship.force, "Install even if the card fails (its record then says CARD FAILED)");
  shipCmd->add_option("--threads", ship.threads, "Threads for the card")->check(CLI::Range(1, 64));

  CLI::App* treeCmd = app.add_subcommand("tree", "Show the skill tree: keys, parents, model hashes, card results");

  apps::EvalOptions eval;
  CLI::App* evalCmd = app.add_subcommand("eval", "Run a skill's report card in physics; exit 0 when it passes");
  evalCmd
      ->add_option("skill", eval.skill,
                   "Skill name, 'switches' (every allowed skill switch) or 'all' (every card, then the switches)")
      ->required();
  evalCmd->add_option("--model", eval.model, "ONNX file to evaluate (default: the skill's model in assets/skills)");
  evalCmd
      ->add_option(
          "--episodes", eval.episodes,
          "Episodes (default: the card's own count, 50 for walk); for switches: trials per switch (default 10)")
      ->check(CLI::Range(1, 100000));
  evalCmd->add_option("--seed", eval.seed, "Seed (default 1)")->check(seedNumber);
  evalCmd
      ->add_option("--threads", eval.threads,
                   "Threads (default 2; under mpirun, the cores shared by the ranks on a machine)")
      ->check(CLI::Range(1, 64));
  evalCmd->add_flag("--sweep", eval.sweep, "Walk: hold fixed commands and print achieved against commanded speeds");
  evalCmd->add_flag("--prior-only", eval.priorOnly,
                    "Run the card with zero network output: what the skill's prior does by itself (no model needed)");
  evalCmd->add_option(
      "--sample", eval.samplePolicy,
      "Run the card with actions drawn from this policy file's Gaussian (its mean and log-std: the policy as training "
      "acts, seeded by --seed) instead of the ONNX model's mean; a diagnostic of training against the card");
  evalCmd->add_flag("--verbose", eval.verbose,
                    "Switches: list every failed trial (keys, moment, latency, time of the fall)");
  evalCmd
      ->add_option("--steer", eval.steer,
                   "Stairs or crawl card: keep the robot on course with this gain in place of the card's steer (0: "
                   "unsteered, the robot left to the skill)")
      ->check(CLI::Range(0.0, 100.0));
  evalCmd->add_option(
      "--multitask", eval.multitask,
      "Run the card on a multi-task run's network (the folder `multitask` wrote), told this skill by its "
      "one-hot");
  evalCmd
      ->add_option("--rewards", eval.rewards,
                   "Instead of the card: the model's mean episode return and reward per step in the skill's own "
                   "training episodes (its rewards, commands, pushes and starts), this many rollouts of one episode's "
                   "time limit over 20 environments, deterministic actions (the comparison's measure; with --model or "
                   "--multitask)")
      ->check(CLI::Range(1, 1000));
  evalCmd->add_option("--only", eval.only,
                      "Switches: only the switches into or out of this skill (the same trials as in the full run)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : kExitBadInput;
  }
  const ai::dist::Comm* comm = nullptr;  // the ranks, under mpirun
  try {
    comm = &ai::dist::world();
    const bool card = *evalCmd && eval.skill != "switches" && eval.skill != "all";
    if (comm->size() > 1 && !(*trainCmd && !train.exportOnly) && !*multitaskCmd && !card)
      throw engine::Error("under mpirun only train, multitask and eval SKILL (a card) run across ranks (" +
                          std::to_string(comm->size()) + " started): run this command without mpirun");
    if (comm->size() > 1) {  // ranks that share a machine share its cores, unless --threads says otherwise
      const int threads = ai::dist::threadsPerRank();
      if (!trainCmd->count("--threads")) train.threads = threads;
      if (!multitaskCmd->count("--threads")) multitask.threads = threads;
      if (!evalCmd->count("--threads")) eval.threads = threads;
    }
    robot::setSkillTreePath(treeFile);
    play.seedGiven = playCmd->count("--seed") > 0;
    if (*playCmd) return cmdPlay(play);
    if (*replayCmd) return cmdReplay(replay);
    if (*variantCmd) return cmdVariant(variant);
    if (*benchCmd) return apps::runBench(bench);
    if (*entriesRecordCmd) {
      if (entriesRecord.lastSeed < entriesRecord.firstSeed)
        throw engine::Error("--last-seed " + std::to_string(entriesRecord.lastSeed) + " is before --first-seed " +
                            std::to_string(entriesRecord.firstSeed));
      return apps::runEntriesRecord(entriesRecord);
    }
    if (*entriesCardCmd) return apps::runEntriesCard(entriesCard);
    if (*trainCmd && !train.exportOnly && trainCmd->count("--export-from"))
      throw engine::Error(
          "--export-from picks what --export-only exports: give --export-only too (no training runs then)");
    if (*trainCmd) return train.exportOnly ? apps::runExport(train) : apps::runTrain(train);
    if (*multitaskCmd) return apps::runMultiTask(multitask);
    if (*compareCmd) return apps::runExperimentCompare(experiment);
    if (*shipCmd) return apps::runShip(ship);
    if (*evalCmd && eval.skill != "switches" && !eval.only.empty())
      throw engine::Error("--only picks the switches of one skill: it goes with eval switches");
    if (*evalCmd && eval.skill == "switches" &&
        (eval.priorOnly || eval.sweep || !eval.model.empty() || !eval.samplePolicy.empty() || !eval.multitask.empty()))
      throw engine::Error(
          "eval switches runs the shipped models: it takes no --prior-only, --sweep, --model, --sample or --multitask");
    if (*evalCmd && eval.skill == "switches") {
      apps::SwitchEvalOptions sw;
      if (eval.episodes > 0) sw.trials = eval.episodes;
      sw.seed = eval.seed;
      sw.threads = eval.threads;
      sw.verbose = eval.verbose;
      sw.only = eval.only;
      return apps::runSwitchEval(sw);
    }
    if (*evalCmd && eval.skill == "all") return apps::runEvalAll(eval);
    if (*evalCmd) return apps::runEval(eval);
    if (*treeCmd) return apps::runTree();
  } catch (const std::exception& e) {
    // under mpirun a rank that fails alone would leave the others waiting in a collective: it ends them all
    if (comm && comm->size() > 1) {
      std::fprintf(stderr, "error (rank %d of %d): %s\n", comm->rank(), comm->size(), e.what());
      std::fflush(stderr);
      comm->abort(kExitBadInput);
    }
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  }
  return 0;
}
