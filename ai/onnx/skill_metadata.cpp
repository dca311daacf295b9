// skill_metadata.cpp — see skill_metadata.h.
#include "ai/onnx/skill_metadata.h"

#include <sstream>

#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "robot/skill_layout.h"

namespace ai {
namespace {

std::string joinNumbers(const double* v, size_t n) {
  std::ostringstream s;
  s.precision(9);
  for (size_t i = 0; i < n; ++i) s << (i ? "," : "") << v[i];
  return s.str();
}

// the keys that define how a policy's output becomes joint torques; a mismatch means a different controller
const char* const kControllerKeys[] = {
    "treelearn.layout_version",
    "treelearn.observation_size",
    "treelearn.action_size",
    "treelearn.joint_order",
    "treelearn.default_pose",
    "treelearn.action_scale",
    "treelearn.action_clip",
    "treelearn.action_filter",
    "treelearn.kp",
    "treelearn.kd",
    "treelearn.prior",
};

}  // namespace

Metadata skillMetadata(const robot::RobotModel& model, const robot::SkillDef& skill, int64_t envSteps, uint64_t seed) {
  std::string joints;
  robot::JointArray defaults{};
  for (size_t j = 0; j < size_t(robot::kNumJoints); ++j) {
    joints += (j ? "," : "") + model.joints[j].name;
    defaults[j] = model.joints[j].defaultPosition;
  }
  const char* prior = skill.prior.kind == robot::PriorDef::Kind::Phase       ? "phase"
                      : skill.prior.kind == robot::PriorDef::Kind::Pose      ? "pose"
                      : skill.prior.kind == robot::PriorDef::Kind::Jump      ? "jump"
                      : skill.prior.kind == robot::PriorDef::Kind::Kick      ? "kick"
                      : skill.prior.kind == robot::PriorDef::Kind::Keyframes ? "keyframes"
                                                                             : "none";
  std::string keyframes;  // " keys=tick:o0,o1,...;tick:..." for a keyframes prior
  for (const robot::PriorDef::Keyframe& k : skill.prior.keyframes)
    keyframes += (keyframes.empty() ? " keys=" : ";") + std::to_string(k.tick) + ":" +
                 joinNumbers(k.offset.data(), k.offset.size());
  if (skill.prior.cycleTicks > 0)
    keyframes += skill.prior.cycleStartTick > 0 ? " repeat_from=" + std::to_string(skill.prior.cycleStartTick)
                                                : std::string(" repeat");
  std::ostringstream filter;
  filter.precision(9);
  filter << skill.actionFilter;
  return {
      {"treelearn.skill", skill.name},
      {"treelearn.parent", skill.parent},
      {"treelearn.key", std::to_string(skill.key)},
      {"treelearn.layout_version", std::to_string(robot::kLayoutVersion)},
      {"treelearn.observation_size", std::to_string(robot::kObservationSize)},
      {"treelearn.action_size", std::to_string(robot::kActionSize)},
      {"treelearn.joint_order", joints},
      {"treelearn.default_pose", joinNumbers(defaults.data(), defaults.size())},
      {"treelearn.action_scale", joinNumbers(skill.actionScale.data(), skill.actionScale.size())},
      {"treelearn.action_clip", std::to_string(robot::kActionClip)},
      {"treelearn.action_filter", filter.str()},
      {"treelearn.kp", joinNumbers(skill.kp.data(), skill.kp.size())},
      {"treelearn.kd", joinNumbers(skill.kd.data(), skill.kd.size())},
      {"treelearn.control_rate_hz", "100"},
      {"treelearn.physics_substep_s", "0.002"},
      {"treelearn.prior",
       std::string(prior) + " T1=" + std::to_string(skill.prior.halfPeriodTicks) +
           " dh=" + std::to_string(skill.prior.dh) + " d0=" + std::to_string(skill.prior.d0) +
           " stand_still=" + (skill.prior.standStill ? "true" : "false") +
           (skill.prior.standRampTicks != 0 ? " stand_ramp_ticks=" + std::to_string(skill.prior.standRampTicks) : "") +
           (skill.prior.stride != 0 ? " stride=" + std::to_string(skill.prior.stride) : "") +
           (skill.prior.armSwing != 0 ? " arm_swing=" + std::to_string(skill.prior.armSwing) : "") +
           (skill.prior.kind == robot::PriorDef::Kind::Pose || skill.prior.kind == robot::PriorDef::Kind::Jump ||
                    skill.prior.kind == robot::PriorDef::Kind::Kick
                ? " offset=" + joinNumbers(skill.prior.poseOffset.data(), skill.prior.poseOffset.size())
                : "") +
           (skill.prior.kind == robot::PriorDef::Kind::Kick
                ? " swing=" + joinNumbers(skill.prior.swingOffset.data(), skill.prior.swingOffset.size())
                : "") +
           (skill.prior.hasLate ? " late=" + joinNumbers(skill.prior.lateOffset.data(), skill.prior.lateOffset.size())
                                : "") +
           (skill.prior.crouch != 0 ? " crouch=" + std::to_string(skill.prior.crouch) : "") + keyframes},
      {"treelearn.robot_hash", engine::toHex(model.hash)},
      {"treelearn.env_steps", std::to_string(envSteps)},
      {"treelearn.seed", std::to_string(seed)},
  };
}

void checkModelMatchesSkill(const LoadedPolicy& policy, const std::string& modelPath, const robot::RobotModel& model,
                            const robot::SkillDef& skill, const std::string& treePath) {
  // every treelearn export names its skill, robot and controller: a model without them is no skill's model
  auto inFile = [&](const std::string& key) -> const std::string& {
    const auto it = policy.metadata.find(key);
    if (it == policy.metadata.end())
      throw engine::Error(modelPath + ": metadata key '" + key + "' is missing, so the model cannot be checked " +
                          "against skill '" + skill.name + "' of " + treePath +
                          " (treelearn exports every key: train --export-only writes them)");
    return it->second;
  };
  const std::string& name = inFile("treelearn.skill");
  if (name != skill.name)
    throw engine::Error(modelPath + ": is the model of skill '" + printable(name) + "', but " + treePath +
                        " gives it to '" + skill.name + "'");
  const std::string robotHash = engine::toHex(model.hash);
  const std::string& trainedOn = inFile("treelearn.robot_hash");
  if (trainedOn != robotHash)
    throw engine::Error(modelPath + ": skill '" + skill.name + "' was trained for robot model " + printable(trainedOn) +
                        ", but " + model.configPath + " is " + robotHash + ": retrain the skill (treelearn train " +
                        skill.name + ") or restore the robot files");
  const Metadata now = skillMetadata(model, skill, 0, 0);
  for (const char* key : kControllerKeys) {
    const std::string& value = inFile(key);
    for (const auto& [k, v] : now)
      if (k == key && v != value)
        throw engine::Error(modelPath + ": skill '" + skill.name + "' was trained with " + key + " = '" +
                            printable(value) + "' but " + treePath + " now gives '" + v +
                            "': retrain the skill (treelearn train " + skill.name + ") or restore its tree entry");
  }
}

}  // namespace ai
