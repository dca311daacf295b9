// multi_task_env.cpp — see multi_task_env.h.
#include "ai/env/multi_task_env.h"

#include <cstring>

#include "engine/core/error.h"

namespace ai {

MultiTaskEnv::MultiTaskEnv(std::vector<Task> tasks) : tasks_(std::move(tasks)) {
  if (tasks_.empty()) throw engine::Error("a multi-task environment needs at least one task");
  for (const Task& t : tasks_) {
    if (!t.env || t.env->numEnvs() < 1)
      throw engine::Error("multi-task environment: task '" + t.name + "' has no environments");
    if (&t == &tasks_.front()) {
      taskObservationSize_ = t.env->observationSize();
      actionSize_ = t.env->actionSize();
    } else if (t.env->observationSize() != taskObservationSize_ || t.env->actionSize() != actionSize_) {
      throw engine::Error("multi-task environment: task '" + t.name + "' has " +
                          std::to_string(t.env->observationSize()) + " observations and " +
                          std::to_string(t.env->actionSize()) + " actions, task '" + tasks_.front().name + "' " +
                          std::to_string(taskObservationSize_) + " and " + std::to_string(actionSize_));
    }
    begin_.push_back(numEnvs_);
    numEnvs_ += t.env->numEnvs();
    globalBegin_.push_back(globalEnvs_);
    globalEnvs_ += t.env->globalEnvs();
    termBegin_.push_back(termCount_);
    termCount_ += t.env->rewardTermNames().size();
  }
  stats_.resize(tasks_.size());
}

int MultiTaskEnv::globalColumn(int n) const {
  size_t k = 0;
  while (k + 1 < begin_.size() && n >= begin_[k + 1]) ++k;
  return globalBegin_[k] + tasks_[k].env->globalColumn(n - begin_[k]);
}

std::vector<std::string> MultiTaskEnv::rewardTermNames() const {
  std::vector<std::string> names;
  for (const Task& t : tasks_)
    for (const std::string& term : t.env->rewardTermNames()) names.push_back(t.name + "/" + term);
  return names;
}

Eigen::MatrixXf MultiTaskEnv::withTask(const Eigen::MatrixXf& taskObservations, int k, int taskCount) {
  Eigen::MatrixXf out = Eigen::MatrixXf::Zero(taskObservations.rows() + taskCount, taskObservations.cols());
  out.topRows(taskObservations.rows()) = taskObservations;
  out.row(taskObservations.rows() + k).setOnes();
  return out;
}

void MultiTaskEnv::reset(uint64_t seed, Eigen::MatrixXf* observations) {
  observations->setZero(observationSize(), numEnvs_);
  Eigen::MatrixXf part;
  for (int k = 0; k < taskCount(); ++k) {
    VecEnv& env = *tasks_[size_t(k)].env;
    env.reset(seed ^ (0x9E3779B97F4A7C15ull * uint64_t(k + 1)), &part);
    observations->block(0, begin(k), taskObservationSize_, env.numEnvs()) = part;
    observations->block(taskObservationSize_ + k, begin(k), 1, env.numEnvs()).setOnes();
  }
}

void MultiTaskEnv::step(const Eigen::MatrixXf& actions, StepResult* result) {
  const int rows = observationSize();
  result->observations.setZero(rows, numEnvs_);
  result->finalObservations.setZero(rows, numEnvs_);
  result->rewards.resize(numEnvs_);
  result->terminated.assign(size_t(numEnvs_), 0);
  result->truncated.assign(size_t(numEnvs_), 0);
  result->episodeReturns.clear();
  result->episodeLengths.clear();
  result->rewardTermSums.assign(termCount_, 0.0);
  for (int k = 0; k < taskCount(); ++k) {
    VecEnv& env = *tasks_[size_t(k)].env;
    const int b = begin(k), n = env.numEnvs();
    env.step(actions.middleCols(b, n), &part_);
    result->observations.block(0, b, taskObservationSize_, n) = part_.observations;
    result->observations.block(taskObservationSize_ + k, b, 1, n).setOnes();
    if (part_.finalObservations.rows() == taskObservationSize_ && part_.finalObservations.cols() == n) {
      result->finalObservations.block(0, b, taskObservationSize_, n) = part_.finalObservations;
      result->finalObservations.block(taskObservationSize_ + k, b, 1, n).setOnes();
    }
    result->rewards.segment(b, n) = part_.rewards;
    std::copy(part_.terminated.begin(), part_.terminated.end(), result->terminated.begin() + b);
    std::copy(part_.truncated.begin(), part_.truncated.end(), result->truncated.begin() + b);
    result->episodeReturns.insert(result->episodeReturns.end(), part_.episodeReturns.begin(),
                                  part_.episodeReturns.end());
    result->episodeLengths.insert(result->episodeLengths.end(), part_.episodeLengths.begin(),
                                  part_.episodeLengths.end());
    for (size_t i = 0; i < part_.rewardTermSums.size(); ++i)
      result->rewardTermSums[termBegin_[size_t(k)] + i] = part_.rewardTermSums[i];
    TaskStats& s = stats_[size_t(k)];
    s.episodes += int(part_.episodeReturns.size());
    for (const float r : part_.episodeReturns) s.returnSum += r;
    for (const int l : part_.episodeLengths) s.lengthSum += l;
    s.rewardSum += double(part_.rewards.sum());
    s.steps += n;
  }
}

void MultiTaskEnv::endRollout() {
  for (Task& t : tasks_) t.env->endRollout();
}

std::vector<MultiTaskEnv::TaskStats> MultiTaskEnv::takeTaskStats() {
  std::vector<TaskStats> out(tasks_.size());
  out.swap(stats_);
  return out;
}

// each task's state as an 8-byte length and its bytes, in task order
std::string MultiTaskEnv::saveState() const {
  std::string out;
  for (const Task& t : tasks_) {
    const std::string s = t.env->saveState();
    const uint64_t n = s.size();
    out.append(reinterpret_cast<const char*>(&n), sizeof n);
    out += s;
  }
  return out;
}

void MultiTaskEnv::loadState(const std::string& bytes) {
  size_t at = 0;
  for (Task& t : tasks_) {
    uint64_t n = 0;
    if (bytes.size() - at < sizeof n)
      throw engine::Error("multi-task environment state: cut short before task '" + t.name + "'");
    std::memcpy(&n, bytes.data() + at, sizeof n);
    at += sizeof n;
    if (bytes.size() - at < n) throw engine::Error("multi-task environment state: task '" + t.name + "' is cut short");
    t.env->loadState(bytes.substr(at, size_t(n)));
    at += size_t(n);
  }
  if (at != bytes.size()) throw engine::Error("multi-task environment state: bytes left over after the last task");
}

int MultiTaskEnv::curriculumLesson() const {
  for (const Task& t : tasks_)
    if (t.env->curriculumLesson() != 0) return t.env->curriculumLesson();
  return 0;
}

std::string MultiTaskEnv::curriculumNote() const {
  std::string out;
  for (const Task& t : tasks_) {
    const std::string note = t.env->curriculumNote();
    if (!note.empty()) out += (out.empty() ? "" : "; ") + t.name + ": " + note;
  }
  return out;
}

}  // namespace ai
