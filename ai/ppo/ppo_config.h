// ppo_config.h — every PPO hyperparameter with its default: the paper's Table 2 read with Unity
// ML-Agents semantics (the paper trains in Unity), plus the network and exploration choices ML-Agents
// leaves to its defaults. Loaded from a TOML table with strict keys (snake_case of the field names).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ai/nn/mlp.h"

namespace ai {

struct PpoConfig {
  // ---- rollout and batching (ML-Agents: buffer_size, batch_size, num_epoch) ----
  /// Environment steps per iteration over all environments (Table 2 "replay buffer size"). Each iteration
  /// runs bufferSize / numEnvs steps per environment (rounded down), then updates. Usually 20480.
  int bufferSize = 20480;
  /// Samples per gradient step (Table 2 "batch size"). Each epoch takes floor(buffer / batchSize) shuffled
  /// minibatches (the remainder is skipped, as ML-Agents does). Usually 2048.
  int batchSize = 2048;
  /// Passes over the buffer per iteration (Table 2). Usually 3.
  int numEpoch = 3;
  /// Discount factor (Table 2). 0.995 at 50 Hz is a ~4 s horizon.
  double gamma = 0.995;
  /// GAE lambda (Table 2, ML-Agents "lambd"). Usually 0.95.
  double lambda = 0.95;
  /// Rewards are multiplied by this before GAE (Table 2 "reward scale"). Logged rewards are unscaled. 1.0.
  double rewardScale = 1.0;

  // ---- schedules: each decays linearly from the first value to the *Final value over the run's
  // totalSteps (ML-Agents "linear" schedules); set Final = initial for a constant ----
  /// Adam learning rate (Table 2). 3e-4.
  double learningRate = 3e-4;
  /// Learning rate at the end of the run. 0 (ML-Agents: 1e-10).
  double learningRateFinal = 0.0;
  /// The first learning rate of a branch trained from its parent's weights (ai::trainSkill), in place of
  /// learning_rate. 3e-5: from the walk's weights the squat's first update at 3e-4 has approx KL 1.44 and clips 84 %
  /// of its samples, overwriting much of what the branch inherits; at 3e-5 its KL is 0.014, near desired_kl
  /// (docs/experiments.md). The adaptive rate moves on from it; the linear schedule decays from it.
  double branchLearningRate = 3e-5;
  /// PPO clip range epsilon (Table 2). 0.2.
  double epsilon = 0.2;
  /// Clip range at the end of the run. 0.1 (ML-Agents' epsilon schedule floor).
  double epsilonFinal = 0.1;
  /// Entropy bonus beta (Table 2). 5e-3. Multiplies the entropy per action dimension (the mean over
  /// dimensions, as ML-Agents), so it does not grow with the action count.
  double beta = 5e-3;
  /// Entropy bonus at the end of the run. 1e-5 (ML-Agents' beta schedule floor).
  double betaFinal = 1e-5;
  /// rsl_rl's "adaptive" learning rate instead of the linear one: before every minibatch step the approximate
  /// KL between the rollout policy and the current one moves the rate, KL > 2 desired_kl -> rate / 1.5,
  /// KL < desired_kl / 2 -> rate x 1.5, within [adaptive_lr_min, adaptive_lr_max]; it starts at learning_rate
  /// and carries over between iterations (checkpointed). Off (the paper's linear schedule).
  bool adaptiveLearningRate = false;
  /// The KL per minibatch step the adaptive rate aims at. 0.01 (rsl_rl).
  double desiredKl = 0.01;
  /// Bounds of the adaptive rate. 1e-6 and 1e-3 (rsl_rl: 1e-5 and 1e-2, for its base rate 1e-3).
  double adaptiveLrMin = 1e-6;
  double adaptiveLrMax = 1e-3;

  // ---- loss ----
  /// Weight of the value loss mean((V - R)^2) in policy + c * value - beta * entropy. 0.5 (ML-Agents).
  double valueLossCoef = 0.5;
  /// Clip the value change to +-epsilon around the rollout value (PPO2 value clipping). Off: it is
  /// scale-dependent and slows the critic when returns are large.
  bool clipValueLoss = false;
  /// Normalise advantages to zero mean, unit std per minibatch (cleanrl). On.
  bool normalizeAdvantages = true;
  /// Clip the global gradient norm (actor + critic + log-std together). 1.0. ML-Agents has none; a safety net.
  double maxGradNorm = 1.0;

  // ---- networks ----
  /// Actor hidden layer widths. 512, 512, 512 (our choice for the G1: wider than ML-Agents' Walker 256 x 3).
  std::vector<int> actorHidden = {512, 512, 512};
  /// Critic hidden layer widths. 128, 128.
  std::vector<int> criticHidden = {128, 128};
  /// Hidden activation of both networks ("elu" or "tanh" in TOML). ELU.
  Activation activation = Activation::Elu;
  /// Orthogonal-init gain of the actor's output layer: small, so initial actions are near 0. 0.01 (cleanrl).
  double actorOutputGain = 0.01;
  /// Orthogonal-init gain of the critic's output layer. 1.0 (cleanrl).
  double criticOutputGain = 1.0;
  /// Running mean/std observation normalisation (ML-Agents "normalize"). On. The critic sees the same
  /// normalised observation as the actor (one normaliser, exported with the actor); no separate stats.
  bool normalizeObservations = true;
  /// Normalised observations are clamped to +-this. 5 (ML-Agents).
  double observationClip = 5.0;

  // ---- exploration: a state-independent log-std vector, learned ----
  /// Initial log-std of every action dimension. -0.5 (std 0.61): half a unit of the unbounded policy
  /// output, gentler than ML-Agents' 0 (std 1) for PD-target actions.
  double initialLogStd = -0.5;
  /// Lower clamp of the log-std after each step. -5 (std 0.0067): keeps log-probs finite.
  double logStdMin = -5.0;
  /// Upper clamp of the log-std after each step. 1 (std 2.7).
  double logStdMax = 1.0;
};

/// Parses a PpoConfig from TOML text: keys of the table at the dotted path `table` ("" = the root table; e.g.
/// "skill.standup.ppo", a skill's own overrides) override `base`; a missing table means `base` unchanged. Unknown
/// keys, wrong types and invalid values throw engine::Error "fileName:line: ...".
PpoConfig parsePpoConfig(std::string_view tomlText, const std::string& fileName, const std::string& table = "ppo",
                         const PpoConfig& base = PpoConfig{});

/// Reads path and parses it with parsePpoConfig. Throws engine::Error.
PpoConfig loadPpoConfig(const std::string& path, const std::string& table = "ppo");

/// The effective config as a TOML table "[ppo]" holding every key, parseable by parsePpoConfig.
std::string toToml(const PpoConfig& config);

/// Checks ranges (positive sizes, 0 < gamma <= 1, ...). Throws engine::Error "what: ..." on the first problem.
void validatePpoConfig(const PpoConfig& config, const std::string& what);

/// FNV-1a of toToml(config): stored in checkpoints to refuse resuming with a changed config.
uint64_t ppoConfigHash(const PpoConfig& config);

}  // namespace ai
