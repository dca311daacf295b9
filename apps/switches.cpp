// switches.cpp — the skills as `play` loads them (ONNX models into the runtime's SkillSet), and `treelearn eval
// switches`: the switch matrix (game/switch_matrix.h) on levels/flat, printed.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "ai/onnx/policy_onnx.h"
#include "ai/onnx/skill_metadata.h"
#include "apps/commands.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"
#include "engine/loop/clock.h"
#include "game/switch_matrix.h"
#include "levels/level.h"

namespace apps {

robot::SkillSet loadSkills(const robot::RobotModel& model, const std::map<std::string, std::string>& models) {
  robot::SkillSet set;
  ai::loadTrainingTree(robot::defaultSkillTreePath(), model);  // the whole file is checked, not only what play reads
  const robot::SkillTree tree = robot::loadSkillTree(robot::defaultSkillTreePath(), model);
  engine::Hasher h;
  const std::string treeText = engine::readFile(tree.path);
  h.bytes(treeText.data(), treeText.size());
  for (const robot::SkillDef& def : tree.skills) {
    const auto given = models.find(def.name);
    const std::string path = given != models.end() ? given->second : tree.directory + "/" + def.model;
    if (!std::filesystem::exists(path)) {
      set.missing.push_back({def.name, def.key, path});
      continue;
    }
    auto policy = std::make_shared<ai::LoadedPolicy>(ai::loadPolicyOnnx(path));
    if (policy->observationSize() != robot::kObservationSize || policy->actionSize() != robot::kActionSize)
      throw engine::Error(path + ": network sizes do not match the shared observation/action layout");
    ai::checkModelMatchesSkill(*policy, path, model, def, tree.path);
    h.value(ai::onnxFileHash(path));
    set.skills.push_back({def, [policy](const Eigen::MatrixXf& o, Eigen::MatrixXf* a) { policy->act(o, a); }});
  }
  set.hash = set.skills.empty() ? 0 : h.value();
  return set;
}

int runSwitchEval(const SwitchEvalOptions& o) {
  const robot::RobotModel model = robot::loadRobotModel(engine::projectFile("assets/robots/g1_23dof.toml"));
  const robot::SkillSet skills = loadSkills(model);
  const levels::Level level = levels::loadLevel(engine::projectFile("levels/flat"));
  const game::SwitchMatrix m = game::runSwitchMatrix(level, model, skills, {o.trials, o.seed, o.threads, o.only, {}});
  std::printf(
      "switch report: %zu allowed switches%s x %d trials on levels/flat (random moment 2-4 s, from lying 3-5 s, "
      "out of a stand-up 1-4 s into it; random movement keys before and after; success = switched within %.0f s "
      "of the key and no fall for %.0f s after the switch)\n",
      m.rows.size(), o.only.empty() ? "" : (" (of " + std::to_string(m.allowed) + ", those of " + o.only + ")").c_str(),
      o.trials, game::kSwitchMaxWaitSeconds, game::kSwitchAfterSeconds);
  std::printf("  %-22s %8s %9s   %-27s %-27s\n", "switch", "success", "latency", "peak CoM accel [m/s^2]",
              "peak target step [rad]");
  std::printf("  %-22s %8s %9s   %-27s %-27s\n", "", "", "[ticks]", "around switch / 1 s before",
              "around switch / 1 s before");
  bool pass = true;
  double worstLatency = 0;
  for (const game::SwitchRow& row : m.rows) {
    double accA = 0, accB = 0, tgtA = 0, tgtB = 0, latency = 0;
    for (const game::SwitchTrial& t : row.trials) {
      accA = std::max(accA, t.accelAround), accB = std::max(accB, t.accelBefore);
      tgtA = std::max(tgtA, t.targetAround), tgtB = std::max(tgtB, t.targetBefore);
      latency = std::max(latency, t.latencyTicks);
    }
    worstLatency = std::max(worstLatency, latency);
    const double rate = row.successPercent();
    const bool good = rate >= o.barPercent;
    pass = pass && good;
    const std::string name = row.from->def.name + " -> " + row.to->def.name;
    std::printf("  %-22s %7.0f%% %9.0f   %12.1f / %-12.1f %12.3f / %-12.3f %s\n", name.c_str(), rate, latency, accA,
                accB, tgtA, tgtB, good ? "PASS" : "FAIL");
    if (o.verbose)
      for (size_t i = 0; i < row.trials.size(); ++i) {
        const game::SwitchTrial& t = row.trials[i];
        if (t.switched && t.upright) continue;
        auto key = [](char k) { return k ? std::string(1, k) : std::string("none"); };
        char fate[160];
        if (t.upright)
          std::snprintf(fate, sizeof fate, "never switched");
        else if (t.fallTick < t.switchTick)
          std::snprintf(fate, sizeof fate, "fell %.2f s before the key under %s",
                        double(t.switchTick - t.fallTick) * engine::kTickSeconds, t.fallSkill.c_str());
        else
          std::snprintf(
              fate, sizeof fate,
              "fell %.2f s after the key under %s (pelvis %.2f m, forward pitch %.0f deg, side lean %.0f deg)",
              double(t.fallTick - t.switchTick) * engine::kTickSeconds, t.fallSkill.c_str(), t.fallHeight,
              t.fallPitchDeg, t.fallLeanDeg);
        char trialLatency[32] = "none";
        if (t.switched) std::snprintf(trialLatency, sizeof trialLatency, "%.0f ticks", t.latencyTicks);
        std::printf("      trial %zu: key %s before, %s after, switch key at %.2f s, latency %s, %s\n", i,
                    key(t.keyBefore).c_str(), key(t.keyAfter).c_str(), double(t.switchTick) * engine::kTickSeconds,
                    trialLatency, fate);
      }
  }
  for (const std::string& u : m.untried) std::printf("  %s\n", u.c_str());
  std::printf("  worst switch latency: %.0f ticks (%.0f ms) from the key to the new skill's first control step\n",
              worstLatency, worstLatency * engine::kTickSeconds * 1000);
  std::printf("  %s (bar: >= %.0f %% success on every switch)\n", pass ? "SWITCHES PASSED" : "SWITCHES FAILED",
              o.barPercent);
  return pass ? 0 : 1;
}

}  // namespace apps
