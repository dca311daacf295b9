// gae_test.cpp — computeGae on a 3-step rollout worked by hand: plain bootstrap from lastValues, a fall
// cutting the bootstrap, a time-out bootstrapping from V(final observation), and independent columns.
#include "ai/ppo/gae.h"

#include <gtest/gtest.h>

namespace ai {
namespace {

// gamma 0.9, lambda 0.8 (gamma * lambda = 0.72); rewards 1, 2, 3; values 0.5, 1.0, 1.5
struct Rollout {
  Eigen::MatrixXf rewards{{1.0f}, {2.0f}, {3.0f}};
  Eigen::MatrixXf values{{0.5f}, {1.0f}, {1.5f}};
  FlagMatrix terminated = FlagMatrix::Zero(3, 1);
  FlagMatrix truncated = FlagMatrix::Zero(3, 1);
  Eigen::MatrixXf truncatedValues = Eigen::MatrixXf::Zero(3, 1);
  Eigen::VectorXf lastValues = Eigen::VectorXf::Constant(1, 2.0f);
  Eigen::MatrixXf advantages, returns;
  void run() {
    computeGae(rewards, values, terminated, truncated, truncatedValues, lastValues, 0.9, 0.8, &advantages, &returns);
  }
};

TEST(Gae, HorizonCutBootstrapsFromLastValues) {
  Rollout r;
  r.run();
  // delta2 = 3 + 0.9*2.0 - 1.5 = 3.3;  delta1 = 2 + 0.9*1.5 - 1.0 = 2.35;  delta0 = 1 + 0.9*1.0 - 0.5 = 1.4
  // A2 = 3.3;  A1 = 2.35 + 0.72*3.3 = 4.726;  A0 = 1.4 + 0.72*4.726 = 4.80272
  EXPECT_NEAR(r.advantages(2, 0), 3.3, 1e-6);
  EXPECT_NEAR(r.advantages(1, 0), 4.726, 1e-6);
  EXPECT_NEAR(r.advantages(0, 0), 4.80272, 1e-6);
  // returns = A + V: 5.30272, 5.726, 4.8
  EXPECT_NEAR(r.returns(0, 0), 5.30272, 1e-6);
  EXPECT_NEAR(r.returns(1, 0), 5.726, 1e-6);
  EXPECT_NEAR(r.returns(2, 0), 4.8, 1e-6);

  // a different lastValue only moves the last delta: lastValue 0 -> delta2 = 3 - 1.5 = 1.5
  r.lastValues(0) = 0.0f;
  r.run();
  EXPECT_NEAR(r.advantages(2, 0), 1.5, 1e-6);
}

TEST(Gae, TerminalStateCutsBootstrap) {
  Rollout r;
  r.terminated(1, 0) = 1;
  r.truncatedValues(1, 0) = 100.0f;  // ignored: a fall has no future
  r.run();
  // step 1 fell: delta1 = 2 + 0 - 1.0 = 1.0 and nothing flows back across it from step 2
  // A2 = 3.3 (new episode, horizon bootstrap);  A1 = 1.0;  A0 = 1.4 + 0.72*1.0 = 2.12
  EXPECT_NEAR(r.advantages(2, 0), 3.3, 1e-6);
  EXPECT_NEAR(r.advantages(1, 0), 1.0, 1e-6);
  EXPECT_NEAR(r.advantages(0, 0), 2.12, 1e-6);
}

TEST(Gae, TruncationBootstrapsFromFinalObservationValue) {
  Rollout r;
  r.truncated(1, 0) = 1;
  r.truncatedValues(1, 0) = 4.0f;
  r.run();
  // step 1 timed out with V(final obs) = 4: delta1 = 2 + 0.9*4 - 1.0 = 4.6, chain cut after it
  // A2 = 3.3;  A1 = 4.6;  A0 = 1.4 + 0.72*4.6 = 4.712
  EXPECT_NEAR(r.advantages(2, 0), 3.3, 1e-6);
  EXPECT_NEAR(r.advantages(1, 0), 4.6, 1e-6);
  EXPECT_NEAR(r.advantages(0, 0), 4.712, 1e-6);
}

TEST(Gae, TerminatedWinsOverTruncatedAndColumnsAreIndependent) {
  Eigen::MatrixXf rewards(3, 2), values(3, 2), truncatedValues = Eigen::MatrixXf::Constant(3, 2, 4.0f);
  rewards << 1, 1, 2, 2, 3, 3;
  values << 0.5f, 0.5f, 1.0f, 1.0f, 1.5f, 1.5f;
  FlagMatrix terminated = FlagMatrix::Zero(3, 2), truncated = FlagMatrix::Zero(3, 2);
  terminated(1, 1) = 1;
  truncated(1, 1) = 1;
  const Eigen::VectorXf lastValues = Eigen::VectorXf::Constant(2, 2.0f);
  Eigen::MatrixXf adv, ret;
  computeGae(rewards, values, terminated, truncated, truncatedValues, lastValues, 0.9, 0.8, &adv, &ret);
  EXPECT_NEAR(adv(0, 0), 4.80272, 1e-6);  // column 0 as in HorizonCutBootstrapsFromLastValues
  EXPECT_NEAR(adv(1, 1), 1.0, 1e-6);      // column 1 as in TerminalStateCutsBootstrap
  EXPECT_NEAR(adv(0, 1), 2.12, 1e-6);
}

}  // namespace
}  // namespace ai
