// skill_metadata.h — the DESIGN.md §3 metadata every skill file carries (layout, joint order, default pose,
// scales, gains, control rate, prior), and the check that a model still fits its skill-tree entry: a model
// trained with one controller (gains, scales, prior) must not silently run under another.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "ai/onnx/policy_onnx.h"
#include "robot/robot_model.h"
#include "robot/skill_tree.h"

namespace ai {

using Metadata = std::vector<std::pair<std::string, std::string>>;

/// The metadata written into a skill's ONNX file.
Metadata skillMetadata(const robot::RobotModel& model, const robot::SkillDef& skill, int64_t envSteps, uint64_t seed);

/// Throws engine::Error naming the model file, the tree file and the first controller setting that differs
/// (layout, joint order, default pose, action scale/clip/filter, gains, prior) between the model's metadata
/// and what the tree entry would write now. Keys a model file does not have are not compared.
void checkModelMatchesSkill(const LoadedPolicy& policy, const std::string& modelPath, const robot::RobotModel& model,
                            const robot::SkillDef& skill, const std::string& treePath);

}  // namespace ai
