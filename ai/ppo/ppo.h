// ppo.h — the policy (actor, critic, observation normaliser, log-std) and the clipped-surrogate PPO update
// over a rollout buffer: loss = policy clip loss + c * value loss - beta * entropy, shuffled minibatches from
// a seeded RNG, one Adam over all tensors, global grad-norm clipping, and a NaN/Inf guard that throws.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "ai/dist/comm.h"
#include "ai/nn/adam.h"
#include "ai/nn/mlp.h"
#include "ai/nn/normalizer.h"
#include "ai/ppo/ppo_config.h"
#include "ai/ppo/rollout_buffer.h"
#include "engine/core/error.h"

namespace ai {

/// Everything that defines a policy and its critic; what a branch skill inherits from its parent.
struct PolicyState {
  MlpWeights actor;              ///< normalised obs -> action mean (actSize)
  MlpWeights critic;             ///< normalised obs -> value (1)
  RunningNormalizer normalizer;  ///< observation statistics shared by actor and critic
  Eigen::VectorXf logStd;        ///< actSize: state-independent log standard deviation (nats)

  /// Observation entries expected.
  int observationSize() const { return actor.inputSize(); }
  /// Action entries produced.
  int actionSize() const { return actor.outputSize(); }
};

/// A fresh policy for config's network shapes: orthogonal init from seed, log-std = initialLogStd,
/// normaliser at its prior (clip = observationClip, or unclipped identity when normalisation is off).
PolicyState makePolicyState(const PpoConfig& config, int observationSize, int actionSize, uint64_t seed);

/// Deterministic actions (the actor's mean) for raw observations (obsSize x batch); normaliser frozen.
void actDeterministic(const PolicyState& policy, const Eigen::MatrixXf& observations, Eigen::MatrixXf* actions);
/// Branch init option: zeroes the actor's output layer, so that the branch starts by adding nothing to its prior
/// (its own prior alone) while keeping the parent's hidden layers, critic, normaliser and log-std. For a branch
/// whose prior drives a different motion than the parent's policy expects (the squat's policy holds the pelvis
/// at the commanded height and fights the jump's crouch).
void zeroActorOutput(PolicyState* policy);

/// Thrown when a loss, gradient, observation or reward is NaN or infinite. The trainer saves the state and stops.
class TrainingDiverged : public engine::Error {
 public:
  explicit TrainingDiverged(const std::string& message) : engine::Error(message) {}
};

/// The schedule values for one update.
struct PpoCoefficients {
  double learningRate = 3e-4;  ///< Adam step size
  double epsilon = 0.2;        ///< clip range
  double beta = 5e-3;          ///< entropy bonus (per action dimension)
};

/// Linear schedules at progress in [0, 1] (fraction of the run's total env steps done).
PpoCoefficients scheduledCoefficients(const PpoConfig& config, double progress);

/// The adaptive rate's next value (PpoConfig::adaptiveLearningRate) after a minibatch whose approximate KL is kl:
/// / 1.5 above 2 desired_kl, x 1.5 below desired_kl / 2, unchanged between; clamped to the config's bounds.
double adaptLearningRate(double learningRate, double kl, const PpoConfig& config);

/// Means over all minibatch steps of one update.
struct PpoStats {
  double policyLoss = 0;         ///< clipped surrogate loss
  double valueLoss = 0;          ///< mean (V - R)^2 (before the coefficient)
  double entropy = 0;            ///< entropy per action dimension (nats)
  double approxKl = 0;           ///< mean((r - 1) - log r), r = new/old probability ratio
  double clipFraction = 0;       ///< fraction of samples with |r - 1| > epsilon
  double explainedVariance = 0;  ///< 1 - Var(R - V) / Var(R) over the buffer, with the rollout's values
  double gradNorm = 0;           ///< global gradient norm before clipping
  int minibatches = 0;           ///< gradient steps taken
  double learningRate = 0;       ///< the rate of the last gradient step (the schedule's, or the adaptive one)
};

/// Gradients of the trainable tensors of a PolicyState.
struct PolicyGradients {
  MlpWeights actor, critic;
  Eigen::VectorXf logStd;
};

/// The PPO update with its optimiser and reusable scratch (no allocation per minibatch once warmed up).
class PpoUpdater {
 public:
  explicit PpoUpdater(const PpoConfig& config);

  /// numEpoch passes of shuffled minibatches over buffer (advantages and returns filled). Shuffling draws
  /// from rng. Throws TrainingDiverged before applying a non-finite step (the policy keeps the last good step).
  PpoStats update(const RolloutBuffer& buffer, const PpoCoefficients& coefficients, std::mt19937_64* rng,
                  PolicyState* policy);

  /// The adaptive learning rate carried between updates (NaN until the first update, which starts it at the
  /// schedule's rate); part of a checkpoint. Unused with the linear schedule.
  double adaptiveLearningRate() const { return adaptiveLr_; }
  void setAdaptiveLearningRate(double lr) { adaptiveLr_ = lr; }

  /// Critic only: the actor and log-std get no step (their gradients are zeroed before Adam, whose moments for
  /// them stay as they were) and the adaptive rate is not adapted (the KL is ~0). For a branch whose inherited
  /// critic must first learn the branch's rewards, before its advantages steer the actor.
  void setActorFrozen(bool frozen) { actorFrozen_ = frozen; }

  /// Data-parallel training (ai/dist/comm.h): the run's buffer has runEnvs.size() environments (one process's
  /// order), and this rank's buffer holds those n with runEnvs[n] >= 0, as its environment runEnvs[n]. Every rank
  /// draws the same shuffle over the run's samples and takes its own of each minibatch; advantage statistics, losses
  /// and gradients are summed over the ranks in rank order, so every rank takes the same Adam step, the step one
  /// process takes on the union of the samples (up to the order of float additions). comm must outlive the updater.
  /// One process: never called.
  void setRanks(const dist::Comm* comm, std::vector<int> runEnvs) {
    comm_ = comm;
    runEnvs_ = std::move(runEnvs);
  }

  /// The optimiser (its state is part of a checkpoint).
  Adam& optimizer() { return adam_; }
  const Adam& optimizer() const { return adam_; }

 private:
  // one gradient step on the minibatch in the mb* members (this rank's share of a minibatch of `batch` samples);
  // adds to stats
  void minibatchStep(const PpoCoefficients& c, int batch, PolicyState* policy, PpoStats* stats);
  // sums the gradients over the ranks (nothing on one process)
  void sumGradients();

  PpoConfig config_;
  Adam adam_;
  double adaptiveLr_ = std::nan("");
  bool actorFrozen_ = false;
  const dist::Comm* comm_ = nullptr;  // null: one process
  std::vector<int> runEnvs_;          // this rank's environment of each of the run's (-1: another rank's)
  std::vector<float> flatGrads_;
  PolicyGradients grads_;
  MlpCache actorCache_, criticCache_;
  std::vector<int> permutation_;
  std::vector<TensorRef> paramRefs_, gradRefs_;
  Eigen::MatrixXf mbObs_, mbActions_, mean_, value_, dMean_, dValue_;
  Eigen::ArrayXXf z_;
  Eigen::ArrayXf mbLogProbs_, mbAdvantages_, mbReturns_, mbValues_;
};

}  // namespace ai
