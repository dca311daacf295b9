// multi_task_env_test.cpp — the multi-task environment on pendulums: each task's columns are its own environment's,
// with the task's one-hot below, and each task's episodes are counted apart.
#include "ai/env/multi_task_env.h"

#include <gtest/gtest.h>

#include "ai/env/pendulum_env.h"
#include "engine/core/error.h"

namespace {

using ai::MultiTaskEnv;
using ai::PendulumEnv;

uint64_t taskSeed(uint64_t seed, int k) { return seed ^ (0x9E3779B97F4A7C15ull * uint64_t(k + 1)); }

MultiTaskEnv twoPendulums() {
  std::vector<MultiTaskEnv::Task> tasks;
  tasks.push_back({"two", std::make_unique<PendulumEnv>(2)});
  tasks.push_back({"three", std::make_unique<PendulumEnv>(3)});
  return MultiTaskEnv(std::move(tasks));
}

TEST(MultiTaskEnv, EachTasksColumnsHoldItsOwnObservationsWithItsOneHotBelow) {
  MultiTaskEnv env = twoPendulums();
  ASSERT_EQ(env.numEnvs(), 5);
  ASSERT_EQ(env.observationSize(), 3 + 2);
  EXPECT_EQ(env.begin(1), 2);
  Eigen::MatrixXf obs;
  env.reset(7, &obs);
  PendulumEnv two(2), three(3);
  Eigen::MatrixXf a, b;
  two.reset(taskSeed(7, 0), &a);
  three.reset(taskSeed(7, 1), &b);
  EXPECT_EQ(obs.block(0, 0, 3, 2), a);
  EXPECT_EQ(obs.block(0, 2, 3, 3), b);
  for (int c = 0; c < 5; ++c) {
    EXPECT_EQ(obs(3, c), c < 2 ? 1.0f : 0.0f) << c;
    EXPECT_EQ(obs(4, c), c < 2 ? 0.0f : 1.0f) << c;
  }
  EXPECT_EQ(MultiTaskEnv::withTask(a, 0, 2), obs.leftCols(2));
}

TEST(MultiTaskEnv, ActionsGoToTheirTasksAndEpisodesAreCountedPerTask) {
  MultiTaskEnv env = twoPendulums();
  PendulumEnv two(2), three(3);
  Eigen::MatrixXf obs, a, b;
  env.reset(3, &obs);
  two.reset(taskSeed(3, 0), &a);
  three.reset(taskSeed(3, 1), &b);
  ai::StepResult r, ra, rb;
  double returnTwo = 0, returnThree = 0;
  // 200 steps: every pendulum episode is truncated once, at the last step
  for (int t = 0; t < PendulumEnv::kEpisodeSteps; ++t) {
    Eigen::MatrixXf actions(1, 5);
    actions << 0.5f, -0.25f, 1.0f, 0.0f, -1.0f;  // a different torque per column
    env.step(actions, &r);
    two.step(actions.leftCols(2), &ra);
    three.step(actions.rightCols(3), &rb);
    ASSERT_EQ(r.rewards.head(2), ra.rewards) << t;
    ASSERT_EQ(r.rewards.tail(3), rb.rewards) << t;
    for (const float x : ra.episodeReturns) returnTwo += x;
    for (const float x : rb.episodeReturns) returnThree += x;
  }
  EXPECT_EQ(r.truncated, (std::vector<uint8_t>{1, 1, 1, 1, 1}));
  EXPECT_EQ(r.finalObservations.block(0, 2, 3, 3), rb.finalObservations);
  EXPECT_EQ(r.finalObservations(4, 3), 1.0f);
  ASSERT_EQ(r.rewardTermSums.size(), 6u);
  EXPECT_EQ(env.rewardTermNames()[3], "three/angle");
  EXPECT_DOUBLE_EQ(r.rewardTermSums[3], rb.rewardTermSums[0]);
  const std::vector<MultiTaskEnv::TaskStats> s = env.takeTaskStats();
  EXPECT_EQ(s[0].episodes, 2);
  EXPECT_EQ(s[1].episodes, 3);
  EXPECT_DOUBLE_EQ(s[0].lengthSum, 2.0 * PendulumEnv::kEpisodeSteps);
  EXPECT_NEAR(s[0].returnSum, returnTwo, 1e-3);
  EXPECT_NEAR(s[1].returnSum, returnThree, 1e-3);
  EXPECT_EQ(s[1].steps, 3 * PendulumEnv::kEpisodeSteps);
  EXPECT_EQ(env.takeTaskStats()[1].episodes, 0);  // the counters start again
}

TEST(MultiTaskEnv, TasksOfDifferentSizesOrNoneAreRefused) {
  struct Wide : ai::VecEnv {  // a pendulum's action, one observation more
    int numEnvs() const override { return 1; }
    int observationSize() const override { return 4; }
    int actionSize() const override { return 1; }
    void reset(uint64_t, Eigen::MatrixXf*) override {}
    void step(const Eigen::MatrixXf&, ai::StepResult*) override {}
  };
  std::vector<MultiTaskEnv::Task> tasks;
  tasks.push_back({"pendulum", std::make_unique<PendulumEnv>(1)});
  tasks.push_back({"wide", std::make_unique<Wide>()});
  try {
    MultiTaskEnv env(std::move(tasks));
    FAIL() << "accepted tasks of different observation sizes";
  } catch (const engine::Error& e) {
    EXPECT_NE(std::string(e.what()).find("task 'wide' has 4 observations"), std::string::npos) << e.what();
  }
  EXPECT_THROW(MultiTaskEnv({}), engine::Error);
}

TEST(MultiTaskEnv, AStateCutShortIsRefused) {
  MultiTaskEnv env = twoPendulums();
  const std::string state = env.saveState();  // two empty task states: two 8-byte lengths
  EXPECT_EQ(state.size(), 16u);
  EXPECT_NO_THROW(env.loadState(state));
  EXPECT_THROW(env.loadState(state.substr(0, 12)), engine::Error);
  EXPECT_THROW(env.loadState(state + "x"), engine::Error);
}

}  // namespace
