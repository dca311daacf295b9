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

/// A skill of the tree whose model file is not there (not trained yet): its key does nothing in play.
struct MissingSkill {
  std::string name;
  int key = -1;
  std::string path;
};

struct SkillSet {
  std::vector<SkillRuntime> skills;
  std::vector<MissingSkill> missing;  ///< the tree's skills without a model file, in tree order
  uint64_t hash = 0;  ///< content hash of the tree file and every loaded model (0 = no skills)

  /// The skill bound to a key (0-9), or nullptr.
  const SkillRuntime* byKey(int key) const {
    if (key < 0) return nullptr;  // keyless skills have -1
    for (const SkillRuntime& s : skills)
      if (s.def.key == key) return &s;
    return nullptr;
  }
  /// The key that requests s: its own, or for a keyless skill (the stand-up) the key of the first skill up from
  /// it that has one (walk's 0: from lying, the request routes through the stand-up). -1 if none.
  int requestKey(const SkillRuntime& s) const {
    const SkillRuntime* at = &s;
    for (size_t hops = 0; at && at->def.key < 0 && hops <= skills.size(); ++hops) at = upFrom(*at);
    return at && at->def.key >= 0 ? at->def.key : -1;
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
