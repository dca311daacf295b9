// tree.cpp — `treelearn tree`: the skill tree as the program sees it. For each skill: key, parent (by the
// drawing), model file hash and training steps from its metadata, and the card `treelearn eval` recorded
// for exactly this model file (a record for another hash is shown as stale).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <sstream>

#include "ai/onnx/policy_onnx.h"
#include "ai/onnx/skill_metadata.h"
#include "apps/commands.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"
#include "robot/robot_model.h"

namespace apps {

std::string cardRecordPath(const ai::TrainingTree& tree, const robot::SkillDef& skill) {
  return tree.directory + "/" + skill.name + ".card.txt";
}

namespace {

// "PASS", "FAIL", "stale" (recorded for another model file) or "not evaluated"
std::string cardStatus(const ai::TrainingTree& tree, const ai::SkillSpec& skill, const std::string& modelHash) {
  const std::string path = cardRecordPath(tree, skill);
  if (!std::filesystem::exists(path)) return "not evaluated";
  const std::string text = engine::readFile(path);
  if (text.find("hash " + modelHash + ")") == std::string::npos) return "stale (recorded for another model)";
  if (text.find("CARD PASSED") != std::string::npos) return "PASS";
  if (text.find("CARD FAILED") != std::string::npos) return "FAIL";
  throw engine::Error(path + ": not a card record (no CARD PASSED or CARD FAILED line)");
}

}  // namespace

int runTree() {
  const robot::RobotModel model = robot::loadRobotModel(engine::projectFile("assets/robots/g1_23dof.toml"));
  const ai::TrainingTree tree = ai::loadTrainingTree(robot::defaultSkillTreePath(), model);
  std::printf("skill tree %s (%zu skills)\n", tree.path.c_str(), tree.skills.size());
  std::printf("  %-22s %-4s %-18s %-18s %-10s %s\n", "skill", "key", "model", "hash", "env steps", "card");
  std::function<void(const ai::SkillSpec&, const std::string&, bool, bool)> show = [&](const ai::SkillSpec& s,
                                                                                       const std::string& indent,
                                                                                       bool last, bool root) {
    const std::string label = root ? s.name : indent + (last ? "└─ " : "├─ ") + s.name;
    const std::string path = tree.directory + "/" + s.model;
    std::string hash = "-", steps = "-", card = "no model";
    if (std::filesystem::exists(path)) {
      const ai::LoadedPolicy p = ai::loadPolicyOnnx(path);
      hash = engine::toHex(ai::onnxFileHash(path));
      const auto it = p.metadata.find("treelearn.env_steps");
      if (it != p.metadata.end()) {
        std::ostringstream m;
        m.precision(3);
        m << std::stod(it->second) / 1e6 << " M";
        steps = m.str();
      }
      card = s.card.kind() == ai::CardKind::None ? "no card defined" : cardStatus(tree, s, hash);
      try {
        ai::checkModelMatchesSkill(p, path, model, s, tree.path);
      } catch (const engine::Error&) {
        card = "model does not fit the tree entry: retrain (see treelearn eval " + s.name + ")";
      }
    }
    // the drawing's characters are 3 bytes each in UTF-8 but one column wide
    const int extraBytes =
        int(label.size()) - int(std::count_if(label.begin(), label.end(), [](char c) { return (c & 0xC0) != 0x80; }));
    const std::string key = s.key >= 0 ? std::to_string(s.key) : "-";  // keyless: reached by routing through it
    std::printf("  %-*s %-4s %-18s %-18s %-10s %s\n", 22 + extraBytes, label.c_str(), key.c_str(), s.model.c_str(),
                hash.c_str(), steps.c_str(), card.c_str());
    std::vector<const ai::SkillSpec*> children;
    for (const ai::SkillSpec& c : tree.skills)
      if (c.parent == s.name) children.push_back(&c);
    std::sort(children.begin(), children.end(), [](auto* a, auto* b) { return a->key < b->key; });
    const std::string childIndent = root ? "" : indent + (last ? "   " : "│  ");
    for (size_t i = 0; i < children.size(); ++i) show(*children[i], childIndent, i + 1 == children.size(), false);
  };
  for (const ai::SkillSpec& s : tree.skills)
    if (s.parent.empty()) show(s, "", true, true);
  std::printf("card: the record `treelearn eval SKILL` keeps in %s/SKILL.card.txt for the shipped model\n",
              tree.directory.c_str());
  return 0;
}

}  // namespace apps
