// gae.h — generalised advantage estimation over a rollout of T steps x N environments, as a pure
// function. It distinguishes the three ways a trajectory piece ends: a fall (terminated: the next value
// is 0), a time-out (truncated: bootstrap from V(final observation)), and the rollout horizon (bootstrap
// from V(observation after the last step)). Terminated and truncated both cut the GAE chain.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace ai {

/// T x N flags (0 or 1), step t in row t, environment n in column n.
using FlagMatrix = Eigen::Matrix<uint8_t, Eigen::Dynamic, Eigen::Dynamic>;

/// rewards, values (V(s_t)), terminated, truncated, truncatedValues (V(final observation) where truncated,
/// else ignored): T x N. lastValues: N, V of the observation after step T-1 (used where step T-1 neither
/// terminated nor truncated). Writes advantages and returns (= advantages + values), T x N.
/// Accumulates in double.
void computeGae(const Eigen::MatrixXf& rewards, const Eigen::MatrixXf& values, const FlagMatrix& terminated,
                const FlagMatrix& truncated, const Eigen::MatrixXf& truncatedValues, const Eigen::VectorXf& lastValues,
                double gamma, double lambda, Eigen::MatrixXf* advantages, Eigen::MatrixXf* returns);

}  // namespace ai
