// skill_set.h — the learned skills a session can run, loaded once at start. The policies come in as plain
// functions (apps/ builds them from ONNX files with ai/), so game/ does not depend on the learning code.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "robot/skill_tree.h"

namespace game {

/// A deterministic policy: observation (kObservationSize x 1) -> action (kActionSize x 1).
using SkillPolicy = std::function<void(const Eigen::MatrixXf& observation, Eigen::MatrixXf* action)>;

struct SkillRuntime {
  robot::SkillDef def;
  SkillPolicy policy;
};

struct SkillSet {
  std::vector<SkillRuntime> skills;
  uint64_t hash = 0;  ///< content hash of the tree file and every loaded model (0 = no skills)

  /// The skill bound to a key, or nullptr.
  const SkillRuntime* byKey(int key) const {
    for (const SkillRuntime& s : skills)
      if (s.def.key == key) return &s;
    return nullptr;
  }
  /// The loaded skill with this name, or nullptr.
  const SkillRuntime* byName(const std::string& name) const {
    for (const SkillRuntime& s : skills)
      if (s.def.name == name) return &s;
    return nullptr;
  }

  /// The skill a switch up the tree goes to from s: its `up` skill when the tree names one (prone -> standup),
  /// else its parent; nullptr at the root or when that skill has no loaded model.
  const SkillRuntime* upFrom(const SkillRuntime& s) const {
    const std::string& name = s.def.up.empty() ? s.def.parent : s.def.up;
    return name.empty() ? nullptr : byName(name);
  }

  /// The first switch on the way from `from` to `to`: up from `from` (parent by parent, or by a skill's `up`)
  /// until reaching `to` or one of its ancestors, then down along the tree's edges toward `to`. `to` itself
  /// when it is one step away, nullptr when from == to or when a skill on the way has no loaded model.
  const SkillRuntime* nextHop(const SkillRuntime& from, const SkillRuntime& to) const {
    if (&from == &to) return nullptr;
    std::vector<const SkillRuntime*> up;  // from, then each way up while the skills there are loaded
    for (const SkillRuntime* s = &from; s && up.size() <= skills.size(); s = upFrom(*s)) up.push_back(s);
    // walk up from `to` by parents until we meet that chain; remember the child of the meeting point
    const SkillRuntime* below = nullptr;
    for (const SkillRuntime* s = &to; s; s = s->def.parent.empty() ? nullptr : byName(s->def.parent)) {
      for (size_t i = 0; i < up.size(); ++i)
        if (up[i] == s) return i > 0 ? up[1] : below;  // go up first, else down
      below = s;
      if (!s->def.parent.empty() && !byName(s->def.parent)) return nullptr;
    }
    return nullptr;
  }
};

}  // namespace game
