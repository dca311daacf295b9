// train_multi_test.cpp — the multi-task network from a skill's weights: widened for the one-hot, it acts exactly as
// the skill's policy whatever the one-hot says.
#include "ai/train/train_multi.h"

#include <gtest/gtest.h>

#include <random>

#include "ai/env/multi_task_env.h"
#include "ai/ppo/ppo.h"
#include "ai/ppo/ppo_config.h"

namespace {

TEST(TrainMulti, ASkillsPolicyWidenedForTheOneHotActsAsBeforeForEverySkill) {
  ai::PpoConfig config;
  config.actorHidden = {16, 16};
  config.criticHidden = {8};
  ai::PolicyState p = ai::makePolicyState(config, 5, 3, 7);
  // statistics of its own, so that normalising matters
  std::mt19937 rng(3);
  std::normal_distribution<float> n(0.5f, 2.0f);
  Eigen::MatrixXf seen(5, 64);
  for (int i = 0; i < seen.size(); ++i) seen.data()[i] = n(rng);
  p.normalizer.update(seen);
  Eigen::MatrixXf obs(5, 4);
  for (int i = 0; i < obs.size(); ++i) obs.data()[i] = n(rng);

  const ai::PolicyState wide = ai::widenedForTasks(p, 6);
  ASSERT_EQ(wide.observationSize(), 11);
  ASSERT_EQ(wide.critic.inputSize(), 11);
  ASSERT_EQ(wide.normalizer.size(), 11);
  EXPECT_DOUBLE_EQ(wide.normalizer.variance()[10], 1.0);
  EXPECT_EQ(wide.normalizer.count(), p.normalizer.count());
  Eigen::MatrixXf before, after;
  ai::actDeterministic(p, obs, &before);
  for (int k = 0; k < 6; ++k) {
    ai::actDeterministic(wide, ai::MultiTaskEnv::withTask(obs, k, 6), &after);
    EXPECT_EQ(after, before) << "one-hot " << k;
  }
}

}  // namespace
