// entries.cpp — `treelearn entries record` (play's handover states from autopilot runs and key scripts) and
// `treelearn entries card` (every skill's play-entry card next to its own card's record).
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "ai/onnx/policy_onnx.h"
#include "ai/onnx/skill_metadata.h"
#include "apps/commands.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/input/key_script.h"
#include "engine/loop/clock.h"
#include "game/entry_card.h"
#include "game/play.h"
#include "levels/level.h"

namespace apps {
namespace {

struct RecordRun {
  uint64_t seed = 1;
  std::string keys;  // a key script's path ("" = the autopilot)
};

// the skill's own card's share of episodes without a fall, from its record next to the model ("-" if none)
std::string recordedCardFigure(const std::string& treeDir, const std::string& skill) {
  const std::string path = treeDir + "/" + skill + ".card.txt";
  if (!std::filesystem::exists(path)) return "-";
  const std::string text = engine::readFile(path);
  size_t at = 0;
  while (at < text.size()) {
    const size_t end = std::min(text.find('\n', at), text.size());
    const std::string line = text.substr(at, end - at);
    at = end + 1;
    if (line.find("without a fall") == std::string::npos && line.find("no fall") == std::string::npos) continue;
    const size_t bar = line.find("bar");
    if (bar == std::string::npos) continue;
    size_t numEnd = line.find_last_not_of(' ', bar - 1);
    size_t numStart = line.find_last_of(' ', numEnd);
    return line.substr(numStart + 1, numEnd - numStart) + " %";
  }
  return "-";
}

}  // namespace

int runEntriesRecord(const EntriesRecordOptions& o) {
  const robot::RobotModel model = robot::loadRobotModel(engine::projectFile("assets/robots/g1_23dof.toml"));
  const robot::SkillSet skills = loadSkills(model);
  const levels::Level level = levels::loadLevel(engine::projectFile(o.level));
  if (!level.isGame())
    throw engine::Error(o.level + ": not a game level (no [rules]): the autopilot plays game levels");
  std::vector<RecordRun> runs;
  for (uint64_t s = o.firstSeed; s <= o.lastSeed; ++s) runs.push_back({s, ""});
  for (const std::string& k : o.keys) runs.push_back({0, k});
  std::vector<std::vector<robot::EntryState>> recorded(runs.size());
  std::atomic<int> next{0}, done{0};
  std::mutex progress;
  auto worker = [&] {
    for (int i; (i = next++) < int(runs.size());) {
      const RecordRun& run = runs[size_t(i)];
      game::PlayOptions po;
      po.skills = &skills;
      po.hashEvery = 0;
      po.ticks = engine::secondsToTicks(level.timeLimit > 0 ? level.timeLimit + 0.5 : 600.0);
      std::string source = "autopilot";
      if (run.keys.empty()) {
        po.autopilot = true;
        po.seed = run.seed;
      } else {
        const std::string path = std::filesystem::exists(run.keys) ? run.keys : level.directory + "/" + run.keys;
        const engine::KeyScript script = engine::parseKeyScriptWithSeed(engine::readFile(path), path);
        po.events = script.events;
        po.seed = script.seed.value_or(1);
        source = std::filesystem::path(path).filename().string();
      }
      game::EntryRecorder recorder(o.level, source, po.seed);
      po.entries = &recorder;
      const game::PlayResult r = game::play(level, model, po);
      recorded[size_t(i)] = recorder.entries();
      const std::lock_guard<std::mutex> lock(progress);
      std::fprintf(stderr, "entries: %d of %zu played (%s seed %llu: %s, %zu entries, %d falls)\n", ++done, runs.size(),
                   source.c_str(), (unsigned long long)po.seed, r.outcome == game::Outcome::Won ? "won" : "lost",
                   recorder.entries().size(), r.telemetry.falls);
    }
  };
  std::vector<std::thread> threads;
  for (int t = 0; t < std::max(1, o.threads); ++t) threads.emplace_back(worker);
  for (std::thread& t : threads) t.join();
  std::map<std::string, std::vector<robot::EntryState>> bySkill;
  for (const auto& list : recorded)
    for (const robot::EntryState& e : list) bySkill[e.skill].push_back(e);
  engine::makeDirectories(o.out);
  std::printf("play entries of %s (autopilot seeds %llu-%llu%s) in %s:\n", o.level.c_str(),
              (unsigned long long)o.firstSeed, (unsigned long long)o.lastSeed, o.keys.empty() ? "" : " and key scripts",
              o.out.c_str());
  std::printf("  %-10s %8s %14s\n", "skill", "entries", "fell in play");
  for (const auto& [skill, list] : bySkill) {
    robot::saveEntries(o.out + "/" + skill + ".entries", list);
    int fell = 0;
    for (const robot::EntryState& e : list) fell += e.fellInPlay ? 1 : 0;
    std::printf("  %-10s %8zu %14d\n", skill.c_str(), list.size(), fell);
  }
  return 0;
}

int runEntriesCard(const EntriesCardOptions& o) {
  const robot::RobotModel model = robot::loadRobotModel(engine::projectFile("assets/robots/g1_23dof.toml"));
  robot::SkillSet skills = loadSkills(model);
  if (!o.model.empty()) {  // one skill's model replaced by another file's (a run's export), as eval --model does
    if (o.skill.empty()) throw engine::Error("--model replaces one skill's model: give the skill too (--skill)");
    auto it = std::find_if(skills.skills.begin(), skills.skills.end(),
                           [&](const robot::Skill& s) { return s.def.name == o.skill; });
    if (it == skills.skills.end()) throw engine::Error("--skill " + o.skill + ": no such skill with a model");
    auto policy = std::make_shared<ai::LoadedPolicy>(ai::loadPolicyOnnx(o.model));
    ai::checkModelMatchesSkill(*policy, o.model, model, it->def, robot::defaultSkillTreePath());
    it->policy = [policy](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) { policy->act(obs, act); };
  }
  const std::string treeDir = std::filesystem::path(robot::defaultSkillTreePath()).parent_path().string();
  std::printf("play-entry cards from %s%s (each skill from play's handover states, its segment's keys replayed):\n",
              o.dir.c_str(), o.model.empty() ? "" : (" with " + o.model + " as " + o.skill).c_str());
  std::printf("  %-10s %-10s %-52s\n", "skill", "card", "play-entry card");
  int skillsRun = 0;
  for (const robot::Skill& s : skills.skills) {
    if (!o.skill.empty() && s.def.name != o.skill) continue;
    const std::string path = o.dir + "/" + s.def.name + ".entries";
    if (!std::filesystem::exists(path)) continue;
    const std::vector<robot::EntryState> entries = robot::loadEntries(path);
    const game::EntryCardResult r = game::runEntryCard(entries, s.def.name, skills, model, o.threads);
    ++skillsRun;
    std::printf("  %-10s %-10s %s\n", s.def.name.c_str(),
                o.model.empty() ? recordedCardFigure(treeDir, s.def.name).c_str() : "(--model)",
                game::entryCardLine(r).c_str());
    if (o.verbose)
      for (size_t i = 0; i < r.trials.size(); ++i)
        if (r.trials[i].fell)
          std::printf("      fell: seed %llu tick %lld (%s), after %.2f s\n", (unsigned long long)entries[i].seed,
                      (long long)entries[i].tick, entries[i].source.c_str(), double(r.trials[i].ticks) * 0.01);
  }
  if (skillsRun == 0)
    throw engine::Error(o.dir + ": no SKILL.entries file" + (o.skill.empty() ? "" : " for " + o.skill) +
                        " (treelearn entries record writes them)");
  return 0;
}

}  // namespace apps
