// vec_env.h — the only contract between the learner and a simulator: a batch of environments stepped
// together (rsl_rl's VecEnv). Matrices are column-major, one column per environment.
// Environments reset themselves when an episode ends; the step result says how it ended.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace ai {

/// What one step of all environments returned.
struct StepResult {
  Eigen::MatrixXf observations;       ///< obsSize x numEnvs: the next observation (after an automatic reset if done)
  Eigen::VectorXf rewards;            ///< numEnvs
  std::vector<uint8_t> terminated;    ///< 1 = the episode ended in failure (fall): value of the next state is 0
  std::vector<uint8_t> truncated;     ///< 1 = cut by the time limit: bootstrap from finalObservations
  Eigen::MatrixXf finalObservations;  ///< obsSize x numEnvs: the last observation of a truncated episode (else unused)
  /// Per finished episode (terminated or truncated) in this step: its return and length.
  std::vector<float> episodeReturns;
  std::vector<int> episodeLengths;
  /// Sum over all environments of each named reward term in this step (names from rewardTermNames()).
  std::vector<double> rewardTermSums;
};

class VecEnv {
 public:
  virtual ~VecEnv() = default;
  virtual int numEnvs() const = 0;
  virtual int observationSize() const = 0;
  virtual int actionSize() const = 0;
  /// Names of the reward terms reported in StepResult::rewardTermSums (may be empty).
  virtual std::vector<std::string> rewardTermNames() const { return {}; }
  /// Resets every environment with a seed; writes the first observations (obsSize x numEnvs).
  virtual void reset(uint64_t seed, Eigen::MatrixXf* observations) = 0;
  /// Applies actions (actionSize x numEnvs, unbounded policy outputs) and advances one step.
  virtual void step(const Eigen::MatrixXf& actions, StepResult* result) = 0;
  /// The rollout that began at the last reset() is over (the trainer resets every environment for the next
  /// one): episodes still running were cut there. A curriculum takes its measure here.
  virtual void endRollout() {}
  /// Opaque, byte-exact snapshot of all environment state that matters for continuing a run identically
  /// (RNG states, episode counters, curricula; the physics state is re-created by reset semantics).
  virtual std::string saveState() const { return {}; }
  virtual void loadState(const std::string& bytes) { (void)bytes; }
  /// Under mpirun (ai/dist/comm.h) each rank steps a share of the run's environments: how many the run has in all,
  /// and the column that this rank's environment n has in the run (the order one process steps them in). A single
  /// process: numEnvs() and n.
  virtual int globalEnvs() const { return numEnvs(); }
  virtual int globalColumn(int n) const { return n; }
  /// The curriculum's current lesson (0 = first, or no curriculum), logged with every iteration.
  virtual int curriculumLesson() const { return 0; }
  /// A short human-readable note on the curriculum for progress lines ("" when there is none).
  virtual std::string curriculumNote() const { return {}; }
};

}  // namespace ai
