// skill_tree.h — the skill tree as data (assets/skills/tree.toml): per skill its parent, key, prior,
// PD gains, action scales, command ranges, reward weights, terminations, randomisation and training budget.
// Names, not indices; validated at load with file:line errors. Format documented in assets/skills/README.md.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "robot/robot.h"

namespace robot {

/// Feed-forward prior: a cosine phase signal on hip/knee/ankle pitch (paper §3.1), or none.
struct PriorDef {
  enum class Kind { None, Phase } kind = Kind::None;
  int halfPeriodTicks = 40;  ///< T1: ticks per leg phase (gait period = 2 T1 ticks of 0.01 s)
  double dh = 0.0;           ///< stepping amplitude [rad]: hip -= A, knee += 2A, ankle -= A with A = dh u + d0
  double d0 = 0.0;           ///< base offset [rad] added to A
  bool standStill = true;    ///< dh = 0 while the command is zero (the lab's walk stands still)
};

/// A [lo, hi] range.
struct Range {
  double lo = 0, hi = 0;
};

struct CommandDef {
  Range vx, vy, wz;              ///< sampling ranges [m/s, m/s, rad/s]
  double zeroProbability = 0.2;  ///< chance that a sampled command is all zero
  double resampleSeconds = 5.0;  ///< a new command every so often
};

struct RandomisationDef {
  Range friction{1.0, 1.0};     ///< robot/ground friction coefficient
  Range addedMass{0.0, 0.0};    ///< added pelvis mass [kg]
  double pushEverySeconds = 0;  ///< 0 = no pushes
  Range pushSpeed{0.0, 0.0};    ///< horizontal velocity change of a push [m/s]
};

struct TerminationDef {
  double maxTiltDegrees = 30;  ///< |roll| or |pitch| beyond this ends the episode as a fall
  double minHeight = 0.5;      ///< pelvis below this [m] is a fall
  double episodeSeconds = 10;  ///< time limit (a truncation, not a fall)
};

/// One skill of the tree.
struct SkillDef {
  std::string name;
  std::string parent;  ///< "" for the root
  int key = -1;        ///< 0..9
  std::string model;   ///< ONNX file name inside assets/skills/
  PriorDef prior;
  JointArray kp{}, kd{};           ///< PD gains per joint
  JointArray actionScale{};        ///< rad per policy unit, per joint
  double actionFilter = 0.0;       ///< low-pass on the policy output: u = f u + (1 - f) a (0 = none)
  CommandDef commands;
  std::map<std::string, double> rewardWeights;  ///< term name -> weight
  std::map<std::string, int> rewardLines;       ///< term name -> line in the file (for errors)
  TerminationDef termination;
  RandomisationDef randomisation;
  int64_t trainingSteps = 10000000;
  int trainingEnvs = 20;
  bool onlyPositiveRewards = true;  ///< clip each step's total reward at 0 (falling early never pays)
  int line = 0;  ///< where it is defined
};

struct SkillTree {
  std::string path;
  std::string directory;
  std::vector<SkillDef> skills;
  /// The raw [ppo] table as TOML text (parsed by ai::loadPpoConfig) and its line.
  std::string ppoToml;

  /// The skill with this name, or nullptr.
  const SkillDef* find(const std::string& name) const;
};

/// Loads and validates the tree. Joint groups in [gains]/[action_scale] are matched against the model's joint names.
SkillTree loadSkillTree(const std::string& path, const RobotModel& model);

/// Default location: assets/skills/tree.toml.
std::string defaultSkillTreePath();

/// Joint-group names usable in the tree file (hip_pitch, knee, ..., wrist_roll) and whether joint j belongs.
bool jointInGroup(const std::string& jointName, const std::string& group);

}  // namespace robot
