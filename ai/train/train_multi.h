// train_multi.h — `treelearn multitask`: the paper's baseline for Tree Learning, one actor and one critic trained on
// several skills at once (ai::MultiTaskEnv over each skill's own training environment, as `train SKILL` builds it:
// its prior, commands, rewards, terminations, terrain, randomisation and handover episodes from the tree file). The
// network sees the skill's observation and a one-hot of its index in `skills` (docs/comparison.md). PPO is the
// tree's [ppo] table with the tree's networks and the paper's linear learning-rate schedule (Table 2, as the tree's
// walk trained from scratch); each iteration every environment steps as many times as in a skill's own run (the
// tree's buffer over the root's envs: 1024), so the buffer is that times all the environments.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "ai/ppo/trainer.h"
#include "ai/train/train_skill.h"

namespace ai {

/// The paper's six (§4): walk, run, squat, jump, crawl, one-leg stand.
const std::vector<std::string>& paperComparisonSkills();

struct TrainMultiOptions {
  std::vector<std::string> skills = paperComparisonSkills();
  int64_t steps = 10000000;  ///< environment steps in all (every skill's together)
  int envsPerSkill = 4;
  int threads = 2;
  uint64_t seed = 1;
  std::string runDir = "runs/multitask";
  bool resume = false;
  /// the paper's linear learning-rate schedule (Table 2), not the tree file's adaptive one (see train_multi.cpp)
  bool linearRate = true;
  /// start from this policy file of one skill (the walk's: inheritance without isolation) instead of fresh weights:
  /// its first layers take the one-hot's inputs at zero weight, and training follows the tree's branch recipe (the
  /// [ppo] adaptive rate from branch_learning_rate) instead of the linear schedule
  std::string initFrom;
  /// where the handover episodes' drivers are read from (default: the tree file's folder)
  std::string modelsDir;
};

struct TrainMultiResult {
  std::string runDir;
  int64_t iteration = 0, envSteps = 0;
  bool stopped = false;  ///< stopped on request before its steps: checkpointed, nothing exported
};

/// Trains from fresh weights (seed) and writes RUN/multitask.policy.bin (the final policy) and RUN/skills.txt (the
/// skills in one-hot order); RUN/skills.csv holds each skill's episodes per iteration.
TrainMultiResult trainMultiTask(const TrainMultiOptions& options, const Log& log,
                                const std::function<void(Trainer*)>& onTrainer = {});

/// A skill's policy (86 inputs) widened for a multi-task network of `taskCount` skills: the actor's and the critic's
/// first layers get taskCount more input columns at zero weight, the normaliser taskCount more features at mean 0 and
/// variance 1, so that for any one-hot it acts exactly as before.
PolicyState widenedForTasks(const PolicyState& policy, int taskCount);

/// A policy's rewards in its skill's own training episodes (the same measure for every arm of the comparison): the
/// skill's SkillEnv as `train SKILL` builds it (commands, pushes, randomisation, handover and play episodes, its
/// reward terms) with `envs` environments, `rollouts` times reset (seed + r) and run for one episode's time limit (so
/// every episode begun at the reset ends: a fall or the limit; one begun after a fall may be cut and is not counted),
/// the policy acting deterministically.
struct RewardFigures {
  int episodes = 0;          ///< episodes that ended (fell or timed out) within the rollouts
  double meanReturn = 0;     ///< their mean return (NaN: none ended)
  double meanLength = 0;     ///< their mean length [steps]
  double rewardPerStep = 0;  ///< every step's reward, ended episodes or not, over all steps
  double fellShare = 0;      ///< the share of ended episodes that fell
  int64_t steps = 0;
};
RewardFigures measureRewards(const SkillContext& l, const PolicyFn& act, const std::string& modelsDir, int envs,
                             int rollouts, uint64_t seed, int threads, const Log& log);

/// A multi-task run's policy (RUN/multitask.policy.bin) and its skills (RUN/skills.txt).
struct MultiTaskPolicy {
  PolicyState policy;
  std::vector<std::string> skills;
  /// the index of `skill` in skills (engine::Error naming the run's skills if it has none)
  int indexOf(const std::string& skill, const std::string& runDir) const;
};
MultiTaskPolicy loadMultiTaskPolicy(const std::string& runDir);

}  // namespace ai
