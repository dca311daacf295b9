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

  /// The first switch on the way from `from` to `to` along the tree's edges (up to their common ancestor,
  /// then down): `to` itself when they are parent and child, nullptr when from == to or when a skill on the
  /// way has no loaded model.
  const SkillRuntime* nextHop(const SkillRuntime& from, const SkillRuntime& to) const {
    if (&from == &to) return nullptr;
    std::vector<std::string> up;  // from, its parent, ..., the root
    for (const SkillRuntime* s = &from; s; s = s->def.parent.empty() ? nullptr : byName(s->def.parent)) {
      up.push_back(s->def.name);
      if (!s->def.parent.empty() && !byName(s->def.parent)) return nullptr;
    }
    // walk up from `to` until we meet from's chain; remember the child of the meeting point
    const SkillRuntime* below = nullptr;
    for (const SkillRuntime* s = &to; s; s = s->def.parent.empty() ? nullptr : byName(s->def.parent)) {
      for (size_t i = 0; i < up.size(); ++i)
        if (up[i] == s->def.name) return i > 0 ? byName(up[1]) : below;  // go up first, else down
      below = s;
      if (!s->def.parent.empty() && !byName(s->def.parent)) return nullptr;
    }
    return nullptr;
  }
};

}  // namespace game
