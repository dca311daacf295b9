// ppo_bench_test.cpp — update throughput at the G1 scale (actor 90-512-512-512-23, critic 90-128-128-1,
// minibatch 2048, buffer 20480, 3 epochs). Disabled by default: timing is never asserted in tests. Run with
// build/treelearn_tests --gtest_also_run_disabled_tests --gtest_filter='PpoBench*'
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "ai/ppo/gaussian.h"
#include "ai/ppo/ppo.h"

namespace ai {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TEST(PpoBench, DISABLED_UpdateThroughputAtG1Scale) {
  const PpoConfig config;  // defaults: 3 x 512 actor, 2 x 128 critic, batch 2048, buffer 20480, 3 epochs
  const int obsSize = 90, actSize = 23, envs = 20, steps = config.bufferSize / envs;
  PolicyState policy = makePolicyState(config, obsSize, actSize, 1);

  // raw fwd + bwd of both networks on one minibatch
  const Eigen::MatrixXf x = Eigen::MatrixXf::Random(obsSize, config.batchSize);
  MlpCache actorCache, criticCache;
  Eigen::MatrixXf mean, value;
  MlpWeights actorGrads, criticGrads;
  const Eigen::MatrixXf dMean = Eigen::MatrixXf::Random(actSize, config.batchSize);
  const Eigen::MatrixXf dValue = Eigen::MatrixXf::Random(1, config.batchSize);
  const int reps = 10;
  auto t0 = std::chrono::steady_clock::now();
  for (int r = 0; r < reps; ++r) {
    mlpForwardTrain(policy.actor, x, &actorCache, &mean);
    mlpForwardTrain(policy.critic, x, &criticCache, &value);
    mlpBackward(policy.actor, actorCache, dMean, &actorGrads);
    mlpBackward(policy.critic, criticCache, dValue, &criticGrads);
  }
  const double fwdBwd = secondsSince(t0);

  // inference for 20 envs, as in a rollout step
  const Eigen::MatrixXf obs20 = Eigen::MatrixXf::Random(obsSize, envs);
  t0 = std::chrono::steady_clock::now();
  for (int r = 0; r < 1000; ++r) {
    mlpForward(policy.actor, obs20, &mean);
    mlpForward(policy.critic, obs20, &value);
  }
  const double inference = secondsSince(t0);

  // a whole PPO update over a synthetic buffer
  RolloutBuffer buffer;
  buffer.resize(obsSize, actSize, steps, envs);
  buffer.observations.setRandom();
  buffer.actions.setRandom();
  buffer.logProbs.setConstant(-20.0f);
  buffer.values.setRandom();
  buffer.advantages.setRandom();
  buffer.returns.setRandom();
  PpoUpdater updater(config);
  std::mt19937_64 rng(1);
  t0 = std::chrono::steady_clock::now();
  const PpoStats stats = updater.update(buffer, scheduledCoefficients(config, 0.0), &rng, &policy);
  const double update = secondsSince(t0);

  std::printf("fwd+bwd actor+critic, minibatch %d: %.1f ms, %.0f samples/s\n", config.batchSize, 1e3 * fwdBwd / reps,
              reps * config.batchSize / fwdBwd);
  std::printf("inference actor+critic, 20 envs: %.1f us per step\n", 1e3 * inference);
  std::printf("full update (%d minibatches): %.2f s, %.0f samples/s, %.0f env steps/s of buffer\n", stats.minibatches,
              update, stats.minibatches * config.batchSize / update, config.bufferSize / update);
}

}  // namespace
}  // namespace ai
