// skill_card.cpp — a skill's report card (see skill_card.h).
#include "ai/eval/skill_card.h"

#include <cstdio>
#include <filesystem>

#include "ai/onnx/skill_metadata.h"
#include "engine/core/error.h"
#include "robot/skill_runtime.h"

namespace ai {
namespace {

// the model of skill `name` in modelsDir, checked against its tree entry, as the driver of one of a card's stages
DrivingSkill drivingSkill(const SkillContext& l, const std::string& name, const std::string& modelsDir,
                          const std::string& why) {
  const SkillSpec* def = l.tree.find(name);
  const std::string path = modelsDir + "/" + def->model;
  if (!std::filesystem::exists(path))
    throw engine::Error(path + ": the card of '" + l.skill->name + "' needs the model of '" + name + "' (" + why +
                        "): train " + name + " first");
  auto policy = std::make_shared<LoadedPolicy>(loadPolicyOnnx(path));
  checkModelMatchesSkill(*policy, path, l.model, *def, l.tree.path);
  return {def, [policy](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) { policy->act(obs, act); }};
}

}  // namespace

SkillContext loadSkillContext(const std::string& name) {
  SkillContext l;
  l.model = robot::loadRobotModel(robot::defaultRobotConfigPath());
  l.tree = loadTrainingTree(robot::defaultSkillTreePath(), l.model);
  l.skill = l.tree.find(name);
  if (!l.skill) {
    std::string names;
    for (const auto& s : l.tree.skills) names += (names.empty() ? "" : ", ") + s.name;
    throw engine::Error("unknown skill '" + name + "' (the tree at " + l.tree.path + " has: " + names + ")");
  }
  return l;
}

std::vector<const SkillSpec*> handoverRoute(const TrainingTree& tree, const SkillSpec& skill) {
  const std::string from = skill.handoverFrom.empty() ? skill.parent : skill.handoverFrom;
  std::vector<const SkillSpec*> route;
  for (const SkillSpec* at = tree.find(skill.parent);; at = tree.find(at->parent)) {
    route.insert(route.begin(), at);
    if (at->name == from) return route;
  }
}

CardDrivers loadCardDrivers(const SkillContext& l, const std::string& modelsDir) {
  if (const DrivenCard* driven = l.skill->card.driven(); driven && driven->leadIn) {
    CardDrivers d;
    for (const SkillSpec* at : handoverRoute(l.tree, *l.skill)) {
      const DrivingSkill ds = drivingSkill(l, at->name, modelsDir, "its card starts as play enters the skill");
      d.leadIn.push_back({ds.def, ds.policy});
    }
    return d;
  }
  if (l.skill->card.kind() == CardKind::PushUp || l.skill->card.kind() == CardKind::Crawl)
    return {drivingSkill(l, l.skill->parent, modelsDir, "it lies down first"), {}, {}};
  if (l.skill->card.kind() != CardKind::StandUp) return {};
  return {drivingSkill(l, l.skill->parent, modelsDir, "it lies down first"),
          drivingSkill(l, l.skill->up, modelsDir, "it takes over once standing"),
          {}};
}

CardResult runSkillCard(const SkillContext& l, const PolicyFn& act, const CardRun& run, const CardDrivers& drivers) {
  if (run.card.lying()) return runGroundCard(l.model, *l.skill, act, run, drivers.before, drivers.after);
  return runVelocityCard(l.model, *l.skill, act, run, drivers.leadIn);
}

std::string cardText(const CardResult& card) {
  std::string out;
  char line[256];
  for (const CardFigure& f : card.figures) {
    if (f.bar[0] == '(')
      std::snprintf(line, sizeof line, "  %-44s %10.3f   %s\n", f.name.c_str(), f.value, f.bar.c_str());
    else
      std::snprintf(line, sizeof line, "  %-44s %10.3f   bar %-14s %s\n", f.name.c_str(), f.value, f.bar.c_str(),
                    f.pass ? "PASS" : "FAIL");
    out += line;
  }
  return out + (card.pass ? "  CARD PASSED\n" : "  CARD FAILED\n");
}

std::unique_ptr<LoadedPolicy> loadSkillModel(const SkillContext& l, const std::string& path) {
  auto policy = std::make_unique<LoadedPolicy>(loadPolicyOnnx(path));
  if (policy->observationSize() != robot::kObservationSize || policy->actionSize() != robot::kActionSize)
    throw engine::Error(path + ": network sizes do not match the shared layout");
  checkModelMatchesSkill(*policy, path, l.model, *l.skill, l.tree.path);
  return policy;
}

std::string cardHead(const SkillContext& l, const CardRun& run, const std::string& modelShown,
                     const std::string& hash) {
  const CardDef& def = run.card;  // (with eval's overrides)
  const std::string& name = l.skill->name;
  const char* onnxPath = modelShown.c_str();
  char head[1024];  // room for a long model path
  const robot::Range* lie = def.lying() ? &def.lying()->lieSeconds : nullptr;
  if (def.kind() == CardKind::StandUp)
    std::snprintf(head, sizeof head,
                  "%s report card: %d episodes: %s lies down for %g-%g s, then %s (model %s, hash %s), "
                  "then %s takes over once it stands\n",
                  name.c_str(), run.card.episodes, l.skill->parent.c_str(), lie->lo, lie->hi, name.c_str(), onnxPath,
                  hash.c_str(), l.skill->up.c_str());
  else if (const PushUpCard* pushUp = def.as<PushUpCard>())
    std::snprintf(head, sizeof head,
                  "%s report card: %d episodes: %s lies down for %g-%g s, then %s for %g s (model %s, hash %s)\n",
                  name.c_str(), run.card.episodes, l.skill->parent.c_str(), lie->lo, lie->hi, name.c_str(),
                  pushUp->episodeSeconds, onnxPath, hash.c_str());
  else if (const CrawlCard* crawl = def.as<CrawlCard>()) {
    char steer[160] = "";
    if (crawl->steer > 0)
      std::snprintf(steer, sizeof steer,
                    ", steered toward its axis as a player would (wz = -%g x the error, within %g rad/s)", crawl->steer,
                    l.skill->commands.wz.hi);
    std::snprintf(head, sizeof head,
                  "%s report card: %d episodes: %s lies down for %g-%g s, then %s at %g-%g m/s through a "
                  "tunnel %g m wide, its ceiling %g m up%s (model %s, hash %s)\n",
                  name.c_str(), run.card.episodes, l.skill->parent.c_str(), lie->lo, lie->hi, name.c_str(),
                  crawl->vx.lo, crawl->vx.hi, l.skill->terrain.width, l.skill->terrain.ceilingHeight, steer, onnxPath,
                  hash.c_str());
  } else {
    const DrivenCard& driven = *def.driven();
    std::string leadIn;  // "walk 1-3 s, to rest, one_leg 0-2 s, then " for a lead_in card
    if (driven.leadIn) {
      char b[160];
      const std::vector<const SkillSpec*> route = handoverRoute(l.tree, *l.skill);
      for (size_t k = 0; k < route.size(); ++k) {
        const robot::Range& t = k == 0 ? l.skill->handoverSeconds : l.skill->handoverViaSeconds;
        std::snprintf(b, sizeof b, "%s%s %g-%g s", k == 0 ? "each entered as in play: " : ", ", route[k]->name.c_str(),
                      t.lo, t.hi);
        leadIn += b;
      }
      leadIn = " (" + leadIn + ", then " + name + ")";
    }
    if (const StairsCard* stairs = def.as<StairsCard>()) {  // the player's steering, or none
      char b[200];
      if (stairs->steer > 0)
        std::snprintf(b, sizeof b,
                      ", steered square to the stairs as play's heading hold does (wz = -%g x the heading off them, "
                      "within %g rad/s)",
                      stairs->steer, robot::headingHoldLimit(l.skill->commands));
      else
        std::snprintf(b, sizeof b, ", unsteered from a start up to %.0f deg off square to the stairs",
                      stairs->heading * 180.0 / M_PI);
      leadIn += b;
    }
    std::snprintf(head, sizeof head,
                  "%s report card: %d episodes x %g s%s with pushes %s, commands every %g s%s (model %s, hash %s)\n",
                  name.c_str(), run.card.episodes, driven.episodeSeconds, leadIn.c_str(), driven.pushes ? "on" : "off",
                  driven.segmentSeconds,
                  driven.standEpisodes ? ("; " + std::to_string(driven.standEpisodes) + " standing episodes x " +
                                          std::to_string(int(driven.standSeconds)) + " s")
                                             .c_str()
                                       : "",
                  onnxPath, hash.c_str());
  }
  return head;
}

}  // namespace ai
