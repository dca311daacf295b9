// train_skill.h — `treelearn train SKILL` in-process: the skill's training environment (handover episodes under
// the models it starts from), PPO from its parent's weights (or a policy file), report-card evaluations that choose
// the best policy, and the export into the run folder. Never writes into the tree's folder: `treelearn ship` does.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>

#include "ai/env/skill_env.h"
#include "ai/eval/skill_card.h"
#include "ai/ppo/checkpoint.h"
#include "ai/ppo/trainer.h"

namespace ai {

/// Where progress lines go (each ends in a newline); apps/ prints them.
using Log = std::function<void(const std::string& line)>;

struct TrainSkillOptions {
  int64_t steps = 0;  ///< 0 = the skill's budget from the tree file
  bool resume = false;
  int threads = 2;
  int envs = 0;  ///< 0 = the skill's setting
  uint64_t seed = 1;
  std::string runDir;     ///< default runs/SKILL
  int evalEvery = 10;     ///< iterations between report-card evaluations (0 = never)
  int evalEpisodes = 10;  ///< episodes of each training evaluation (the card's own count is for `eval`)
  /// > 0: an evaluation that beats the best confirmed score so far is run again on this many other episodes, and
  /// that score decides the best policy (0: the evalEpisodes card alone, always on the same episodes)
  int evalConfirm = 0;
  double reinflateLogStd = std::nan("");  ///< branch init: raise the log-std to at least this
  double initLogStd = std::nan("");       ///< branch init: set every log-std entry to this (less or more exploration)
  bool freezeNormalizer = false;          ///< keep the loaded observation statistics
  int criticWarmup = 0;     ///< iterations that update the critic only (a branch's inherited critic learns first)
  bool zeroOutput = false;  ///< branch init: the actor's output layer starts at zero (the branch begins as its prior)
  std::string initFrom;     ///< start from this policy file (PolicyState) instead of fresh weights or the parent
  /// with initFrom: start as a branch does from its parent (the normaliser's weight capped, [ppo]
  /// branch_learning_rate) rather than as a fine-tune of the same skill (the sequential arm of the comparison)
  bool initAsBranch = false;
  double learningRate = std::nan("");  ///< override of the [ppo] initial learning rate (fine-tuning)
  bool linearRate = false;  ///< the paper's linear learning-rate schedule instead of a KL-adaptive [ppo] (from scratch)
  /// where the other skills' models are read from (the parent's policy, handover and card drivers; default: the
  /// tree file's folder). The run's own model is written into runDir, never here.
  std::string modelsDir;
};

struct TrainSkillResult {
  std::string runDir;
  int64_t iterationsRun = 0;            ///< in this call (a resumed run at or past its steps runs none)
  int64_t iteration = 0, envSteps = 0;  ///< where the run stands now
  int64_t steps = 0;                    ///< the steps it was asked to reach
  bool stopped = false;                 ///< stopped on request before its steps: checkpointed, nothing exported
};

/// The skill's training environment options: its handover episodes' drivers (the parent's or handover_from's
/// shipped model and the skills routed through after it, a child's for handover_back), read from modelsDir; says in
/// `log` what its episodes start from. engine::Error when a driver has no model yet.
SkillEnvOptions skillEnvOptions(const SkillContext& l, const std::string& modelsDir, int envs, int threads,
                                const Log& log);

/// Trains the skill and exports its best-by-evaluation policy (else the final one) into the run folder.
/// `onTrainer` sees the trainer once it exists and nullptr when training ends (apps/ stops it on Ctrl-C).
TrainSkillResult trainSkill(const SkillContext& skill, const TrainSkillOptions& options, const Log& log,
                            const std::function<void(Trainer*)>& onTrainer = {});

/// The run folder's exported model and policy file: RUN/SKILL.onnx, RUN/SKILL.policy.bin.
std::string exportedModelPath(const std::string& runDir, const SkillSpec& skill);
std::string exportedPolicyPath(const std::string& runDir, const SkillSpec& skill);

/// Writes the ONNX model (with the skill's metadata) and the policy file (with where it came from: `info`).
void exportSkill(const robot::RobotModel& model, const SkillSpec& skill, const PolicyState& policy,
                 const std::string& onnxPath, const std::string& policyPath, const PolicyInfo& info, uint64_t seed);

/// Exports `policy` into the run folder and says (in `log`) how to ship it.
void exportToRun(const SkillContext& l, const std::string& runDir, const PolicyState& policy, const PolicyInfo& info,
                 uint64_t seed, const std::string& source, const Log& log);

/// Exports the run's best.bin (`exportFrom` "best") or its checkpoint's policy ("last") into the run folder.
void exportFromRun(const SkillContext& l, const std::string& runDir, const std::string& exportFrom, uint64_t seed,
                   const Log& log);

}  // namespace ai
