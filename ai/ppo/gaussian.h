// gaussian.h — the diagonal Gaussian policy distribution with a state-independent log-std vector:
// log-probabilities per sample, entropy, and standard-normal noise from a seeded std::mt19937_64 via our
// own Box-Muller (std::normal_distribution differs between standard libraries; this does not).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace ai {

/// log(2 pi).
constexpr double kLog2Pi = 1.8378770664093454836;

/// log N(a | mean, exp(logStd)) per column, summed over the action dimensions:
/// -0.5 sum_j ((a_j - mean_j) / std_j)^2 - sum_j logStd_j - 0.5 D log(2 pi). actions, mean: D x batch.
inline Eigen::VectorXf gaussianLogProb(const Eigen::MatrixXf& actions, const Eigen::MatrixXf& mean,
                                       const Eigen::VectorXf& logStd) {
  const Eigen::ArrayXf invStd = (-logStd.array()).exp();
  const float constant = float(-double(logStd.sum()) - 0.5 * double(logStd.size()) * kLog2Pi);
  const Eigen::ArrayXXf z = (actions - mean).array().colwise() * invStd;
  return (-0.5f * z.square().colwise().sum() + constant).matrix().transpose();
}

/// Entropy of the distribution (nats), summed over dimensions: sum_j (0.5 + 0.5 log(2 pi) + logStd_j).
inline double gaussianEntropy(const Eigen::VectorXf& logStd) {
  return double(logStd.size()) * (0.5 + 0.5 * kLog2Pi) + double(logStd.cast<double>().sum());
}

/// Uniform double in (0, 1] from the top 53 bits of one draw.
inline double uniformOpenClosed(std::mt19937_64* rng) {
  return (double((*rng)() >> 11) + 1.0) * (1.0 / 9007199254740992.0);
}

/// Uniform double in [0, 1) from the top 53 bits of one draw.
inline double uniformClosedOpen(std::mt19937_64* rng) { return double((*rng)() >> 11) * (1.0 / 9007199254740992.0); }

/// Fills out (any shape) with independent standard-normal samples, column-major order, two per Box-Muller
/// pair (an odd last element discards the pair's sine half). Consumes 2 * ceil(size / 2) draws.
inline void fillStandardNormal(std::mt19937_64* rng, Eigen::MatrixXf* out) {
  float* p = out->data();
  const Eigen::Index n = out->size();
  for (Eigen::Index i = 0; i < n; i += 2) {
    const double r = std::sqrt(-2.0 * std::log(uniformOpenClosed(rng)));
    const double angle = 6.283185307179586477 * uniformClosedOpen(rng);
    p[i] = float(r * std::cos(angle));
    if (i + 1 < n) p[i + 1] = float(r * std::sin(angle));
  }
}

/// Samples actions = mean + exp(logStd) * noise (D x batch) with noise from fillStandardNormal.
inline void sampleGaussian(std::mt19937_64* rng, const Eigen::MatrixXf& mean, const Eigen::VectorXf& logStd,
                           Eigen::MatrixXf* actions) {
  actions->resize(mean.rows(), mean.cols());
  fillStandardNormal(rng, actions);
  actions->array() = (actions->array().colwise() * logStd.array().exp()) + mean.array();
}

/// sampleGaussian for some columns of a larger batch: draws the noise of all `total` columns (as one process stepping
/// them all would) and keeps column columns[n] for mean's column n. Every rank of a run draws the same stream.
inline void sampleGaussianColumns(std::mt19937_64* rng, const Eigen::MatrixXf& mean, const Eigen::VectorXf& logStd,
                                  const std::vector<int>& columns, int total, Eigen::MatrixXf* noise,
                                  Eigen::MatrixXf* actions) {
  noise->resize(mean.rows(), total);
  fillStandardNormal(rng, noise);
  actions->resize(mean.rows(), mean.cols());
  for (Eigen::Index n = 0; n < mean.cols(); ++n) actions->col(n) = noise->col(columns[size_t(n)]);
  actions->array() = (actions->array().colwise() * logStd.array().exp()) + mean.array();
}

}  // namespace ai
