// skill_set.h — the learned skills a session can run, loaded once at start. The policies come in as plain
// functions (apps/ builds them from ONNX files with ai/), so game/ does not depend on the learning code.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
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
};

}  // namespace game
