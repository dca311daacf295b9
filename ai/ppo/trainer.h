// trainer.h — the PPO training loop (rsl_rl's OnPolicyRunner shape): act -> env.step -> store -> GAE ->
// update -> log -> save. Every iteration starts with env.reset(seed derived from run seed and iteration),
// so an iteration boundary holds no hidden simulator state and a resumed run is bit-identical.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "ai/dist/comm.h"
#include "ai/env/vec_env.h"
#include "ai/ppo/ppo.h"
#include "ai/ppo/ppo_config.h"

namespace ai {

/// Reported after every iteration.
struct TrainerProgress {
  int64_t iteration = 0;        ///< completed iterations
  int64_t totalIterations = 0;  ///< iterations the run will take
  int64_t envSteps = 0;         ///< environment steps so far
  int64_t totalSteps = 0;       ///< the run's budget
  double stepsPerSecond = 0;    ///< environment steps per wall second, averaged over this process's iterations
  double etaSeconds = 0;        ///< remaining steps / stepsPerSecond
  double meanReward = 0;        ///< mean unscaled reward per environment step in this iteration
  double meanEpisodeReturn = std::numeric_limits<double>::quiet_NaN();  ///< over episodes ended in this iteration
  double meanEpisodeLength = std::numeric_limits<double>::quiet_NaN();  ///< steps, same episodes
  double evalScore = std::numeric_limits<double>::quiet_NaN();          ///< this iteration's evaluation (NaN: none)
  PpoStats stats;                                                       ///< the update's losses and diagnostics
  std::string curriculumNote;  ///< the environment's curriculum state ("" when it has none)
};

struct TrainerOptions {
  /// Output folder (created): log.csv, checkpoint.bin, best.bin, diverged.bin.
  std::string runDir;
  /// Train until at least this many environment steps (whole iterations); the schedules decay over it.
  int64_t totalSteps = 1000000;
  /// Run seed: initial weights, action noise, minibatch order and the per-iteration env reset seeds.
  uint64_t seed = 1;
  /// Continue from runDir/checkpoint.bin (required to exist); log.csv rows after it are dropped.
  bool resume = false;
  /// Called after every iteration (after logging and saving). Optional.
  std::function<void(const TrainerProgress&)> onIteration;
  /// Scores the policy (higher is better); called every evalEvery iterations. The best-scoring policy is
  /// kept in runDir/best.bin. Optional; must be deterministic for resumed runs to match uninterrupted ones.
  std::function<double(const PolicyState&)> evaluate;
  /// Iterations between evaluations (and always after the last iteration).
  int evalEvery = 10;
  /// Iterations between checkpoints (and always after the last iteration). 1 = every iteration.
  int checkpointEvery = 1;
  /// Threads for the matrix products of the PPO update (Eigen with OpenMP); the rest of the process uses 1.
  int updateThreads = 1;
  /// The first this many iterations of the run update the critic only (PpoUpdater::setActorFrozen).
  int criticWarmupIterations = 0;
  /// The ranks training this run together (ai/dist/comm.h); null: one process. The env steps this rank's share of
  /// the run's environments (VecEnv::globalEnvs, globalColumn). Every rank keeps the same policy, normaliser, optimiser
  /// and random streams: the normaliser is updated from every rank's observations, the action noise drawn for all
  /// environments, the update's sums taken over the ranks. evaluate is called on every rank (it must give every rank
  /// the same score: a card run over the ranks does); rank 0 alone writes the log, checkpoints and best.bin, and every
  /// rank reads the checkpoint on --resume. Must outlive the trainer.
  const dist::Comm* comm = nullptr;
  /// Keep the observation normaliser's statistics as loaded (a fine-tune on new states: the kick taking the walk's
  /// stopped robot moved a 1e5-count normaliser within 3 iterations and the deterministic policy no longer kicked).
  bool freezeNormalizer = false;
};

class Trainer {
 public:
  /// Builds a fresh policy for env's observation and action sizes from options.seed. Throws engine::Error
  /// on an invalid config or options.
  Trainer(VecEnv& env, const PpoConfig& config, TrainerOptions options);

  /// The observation normaliser's count after a branch initialisation (5 iterations of 20,480 samples).
  static constexpr double kBranchNormalizerCount = 1e5;

  /// Branch initialisation: copies actor, critic, normaliser and log-std from parent (shapes must match the
  /// env and config); optimiser state, schedules and step counter start fresh. reinflateLogStd: if not
  /// NaN, each log-std entry becomes max(entry, reinflateLogStd) to restore exploration. Call before run();
  /// a resumed run (options.resume) loads its checkpoint instead.
  /// fineTune: the policy is the same skill's (--init-from), so the normaliser keeps its statistics' weight (its
  /// count) as saved and the run's observations move them as slowly as at the end of the run that saved them; a
  /// branch (false) caps the count at kBranchNormalizerCount so its own observations take over within a few
  /// iterations. (A stairs fine-tune with the cap went from 435-tick training episodes to 129 in 15 iterations at a
  /// KL of 0.01-0.02 per update, its inputs moving under it; with the weight kept, 400-640: docs/skills/stairs.md.)
  void initialiseFrom(const PolicyState& parent, float reinflateLogStd = std::numeric_limits<float>::quiet_NaN(),
                      bool fineTune = false);

  /// Trains to options.totalSteps (resuming first if options.resume). Throws TrainingDiverged after saving
  /// runDir/diverged.bin (checkpoint.bin keeps the last good state); engine::Error on I/O or resume problems.
  void run();

  /// Asks run() to stop after the current iteration (checkpoint saved). Safe from onIteration or a signal handler.
  void requestStop() { stopRequested_ = true; }
  /// True when the last run() ended on a stop request before its steps were done (its checkpoint is written).
  bool stoppedEarly() const { return stoppedEarly_; }

  /// The current policy.
  const PolicyState& policy() const { return policy_; }
  /// Completed iterations.
  int64_t iteration() const { return iteration_; }
  /// Environment steps so far.
  int64_t envSteps() const { return envSteps_; }
  /// The best evaluation score so far (-inf: none; a resumed run's is its checkpoint's once run() has resumed).
  double bestScore() const { return bestScore_; }
  /// Environment steps per environment per iteration (bufferSize / the run's environments).
  int stepsPerEnv() const { return stepsPerEnv_; }

  /// The hash of the policy (networks, normaliser, log-std: FNV-1a of its policy-file bytes), checked to be the same
  /// on every rank (engine::Error naming the ranks otherwise: they no longer train one run). run() checks it at its
  /// end under mpirun.
  uint64_t policyHashOnEveryRank() const;

  /// Column names of log.csv, in order.
  std::vector<std::string> logColumns() const;

 private:
  struct Timing {
    double physics = 0, inference = 0, update = 0;
  };
  struct RolloutStats;

  void collectRollout(RolloutStats* stats, Timing* timing);
  void writeCheckpoint(const std::string& path) const;
  void resumeFromCheckpoint(double* wallOffset);
  std::string logRow(const TrainerProgress& p, const RolloutStats& r, double lr, double wall, double stepsPerSecond,
                     const Timing& timing) const;

  VecEnv& env_;
  PpoConfig config_;
  TrainerOptions options_;
  const dist::Comm& comm_;
  std::vector<int> columns_;  // the run's column of each of this rank's environments
  int stepsPerEnv_ = 0;
  PolicyState policy_;
  PpoUpdater updater_;
  RolloutBuffer buffer_;
  std::mt19937_64 rng_;
  int64_t iteration_ = 0;
  int rolloutLesson_ = 0;  // the curriculum lesson the last rollout trained (logged)
  int64_t envSteps_ = 0;
  double bestScore_ = -std::numeric_limits<double>::infinity();
  std::atomic<bool> stopRequested_{false};
  bool stoppedEarly_ = false;

  // rollout scratch, reused every step
  StepResult step_;
  Eigen::MatrixXf obs_, normObs_, mean_, actions_, values_, finalObs_, finalNorm_, finalValues_;
  Eigen::MatrixXf noise_;               // several ranks: the action noise of all the run's environments
  std::vector<double> normalizerSums_;  // several ranks: this step's observation sums, then every rank's
};

}  // namespace ai
