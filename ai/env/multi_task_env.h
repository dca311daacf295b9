// multi_task_env.h — one VecEnv over several tasks' environments: the multi-task baseline of the paper's comparison
// (one network trained on every skill at once). Task k's environments are the columns [begin(k), begin(k) + n_k);
// each observation is the task's own (observationSize rows, the same for every task) followed by a one-hot of the
// task's index (taskCount rows), so one network can tell the tasks apart. Actions are split the same way, rewards and
// episodes joined. Each task keeps its own episodes, commands, rewards and terminations: its environment is unchanged.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "ai/env/vec_env.h"

namespace ai {

class MultiTaskEnv final : public VecEnv {
 public:
  struct Task {
    std::string name;
    std::unique_ptr<VecEnv> env;
  };
  /// What a task's episodes did since the last takeTaskStats().
  struct TaskStats {
    int episodes = 0;      ///< episodes ended (fell or timed out)
    double returnSum = 0;  ///< sum of their returns
    double lengthSum = 0;  ///< sum of their lengths [steps]
    double rewardSum = 0;  ///< sum of every step's reward, ended episodes or not
    int64_t steps = 0;     ///< environment steps (one per environment per step())
  };

  /// Tasks with at least one environment each, of equal observation and action sizes (engine::Error otherwise).
  explicit MultiTaskEnv(std::vector<Task> tasks);

  int numEnvs() const override { return numEnvs_; }
  /// Under mpirun each task's environments are shared by the ranks: the run's columns are the tasks' run environments
  /// one after another, as one process holds them.
  int globalEnvs() const override { return globalEnvs_; }
  int globalColumn(int n) const override;
  int observationSize() const override { return taskObservationSize() + taskCount(); }
  int actionSize() const override { return actionSize_; }
  /// Every task's terms as "task/term".
  std::vector<std::string> rewardTermNames() const override;
  /// Task k is reset with the seed `seed ^ (0x9E3779B97F4A7C15 * (k + 1))`.
  void reset(uint64_t seed, Eigen::MatrixXf* observations) override;
  void step(const Eigen::MatrixXf& actions, StepResult* result) override;
  void endRollout() override;
  std::string saveState() const override;
  void loadState(const std::string& bytes) override;
  /// The first task's lesson that is not 0 (the tasks' curricula are their own; the note names each).
  int curriculumLesson() const override;
  std::string curriculumNote() const override;

  int taskCount() const { return int(tasks_.size()); }
  const std::string& taskName(int k) const { return tasks_[size_t(k)].name; }
  int begin(int k) const { return begin_[size_t(k)]; }
  int taskObservationSize() const { return taskObservationSize_; }
  /// The per-task statistics gathered since the last call; the counters start again.
  std::vector<TaskStats> takeTaskStats();

  /// The observation a network trained here sees for task k: the task's own (taskObservationSize x n) with the
  /// one-hot rows below (for running the network on one task outside this environment: a report card).
  static Eigen::MatrixXf withTask(const Eigen::MatrixXf& taskObservations, int k, int taskCount);

 private:
  std::vector<Task> tasks_;
  std::vector<int> begin_;
  std::vector<size_t> termBegin_;  // each task's first index in rewardTermSums
  std::vector<int> globalBegin_;   // each task's first column in the run
  int numEnvs_ = 0, globalEnvs_ = 0, taskObservationSize_ = 0, actionSize_ = 0;
  size_t termCount_ = 0;
  std::vector<TaskStats> stats_;
  StepResult part_;  // one task's step, reused
};

}  // namespace ai
