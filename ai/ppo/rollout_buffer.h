// rollout_buffer.h — one iteration's experience: T steps x N environments. Per-sample data (observations,
// actions, log-probs) is stored one column per sample at index t + n * T, the same order as the
// column-major T x N matrices (values, rewards, advantages), so sample i is values.data()[i].
#pragma once

#include <Eigen/Core>

#include "ai/ppo/gae.h"

namespace ai {

struct RolloutBuffer {
  int steps = 0;                    ///< T: steps per environment
  int envs = 0;                     ///< N: environments
  Eigen::MatrixXf observations;     ///< obsSize x T*N: normalised observations, as the policy saw them
  Eigen::MatrixXf actions;          ///< actSize x T*N: sampled (unclipped) actions
  Eigen::VectorXf logProbs;         ///< T*N: log-probability of each action when it was sampled
  Eigen::MatrixXf values;           ///< T x N: V(s_t) at sampling time
  Eigen::MatrixXf rewards;          ///< T x N: scaled rewards
  FlagMatrix terminated;            ///< T x N: 1 = fell at this step
  FlagMatrix truncated;             ///< T x N: 1 = timed out at this step
  Eigen::MatrixXf truncatedValues;  ///< T x N: V(final observation) where truncated, else 0
  Eigen::VectorXf lastValues;       ///< N: V of the observation after the last step
  Eigen::MatrixXf advantages;       ///< T x N: from computeGae
  Eigen::MatrixXf returns;          ///< T x N: advantages + values

  /// Sample count T*N.
  int size() const { return steps * envs; }
  /// Column of step t of environment n.
  int index(int t, int n) const { return t + n * steps; }
  /// Sizes every member (contents unspecified, truncatedValues zero).
  void resize(int obsSize, int actSize, int numSteps, int numEnvs) {
    steps = numSteps;
    envs = numEnvs;
    observations.resize(obsSize, size());
    actions.resize(actSize, size());
    logProbs.resize(size());
    values.resize(steps, envs);
    rewards.resize(steps, envs);
    terminated.resize(steps, envs);
    truncated.resize(steps, envs);
    truncatedValues.setZero(steps, envs);
    lastValues.resize(envs);
    advantages.resize(steps, envs);
    returns.resize(steps, envs);
  }
};

}  // namespace ai
