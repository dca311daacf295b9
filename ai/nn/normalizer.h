// normalizer.h — running per-feature mean and variance of observations (Chan et al.'s parallel update in
// double, as gym's RunningMeanStd) and the clamped normalisation the actor and critic see. Updated only
// while collecting training rollouts; frozen (read-only) in evaluation, play and the exported ONNX graph.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace ai {

class ByteWriter;
class ByteReader;

class RunningNormalizer {
 public:
  /// Initial count: a small pseudo-count so the first batch all but replaces the prior (mean 0, var 1).
  static constexpr double kInitialCount = 1e-4;
  /// Added to the variance before the square root.
  static constexpr double kVarianceEpsilon = 1e-8;

  RunningNormalizer() = default;
  /// size features; normalised values are clamped to [-clip, clip] (usually 5, as ML-Agents).
  explicit RunningNormalizer(int size, float clip = 5.0f);

  /// Folds a batch (size x batch, one column per sample) into the statistics.
  void update(const Eigen::MatrixXf& batch);
  /// A batch spread over processes (data-parallel training): each computes its columns' sums about the current mean
  /// (the same everywhere), the sums are added up, and foldSums folds the whole batch in as update() would (equal up to
  /// rounding). sums gets 1 + 2 size() entries: the count, then sum(x - mean) and sum((x - mean)^2) per feature.
  void batchSums(const Eigen::MatrixXf& batch, std::vector<double>* sums) const;
  void foldSums(const std::vector<double>& sums);
  /// out = clamp((x - mean) / sqrt(var + 1e-8), -clip, clip), column by column. out may not alias x.
  void normalize(const Eigen::MatrixXf& x, Eigen::MatrixXf* out) const;

  /// Number of features.
  int size() const { return int(mean_.size()); }
  /// Running mean per feature (float copy, for export).
  Eigen::VectorXf mean() const { return mean_.cast<float>(); }
  /// sqrt(var + 1e-8) per feature (float copy, for export).
  Eigen::VectorXf stddev() const;
  /// Running variance per feature (double).
  const Eigen::VectorXd& variance() const { return var_; }
  /// Samples seen, plus kInitialCount.
  double count() const { return count_; }
  /// Clamp range of normalised values.
  float clip() const { return clip_; }

  /// Prepares a parent's statistics for a branch: a feature the parent never saw vary (variance below 1e-6,
  /// e.g. a command slot it does not use) gets mean 0 and variance 1, so that the branch's values reach the
  /// network at their own scale instead of divided by ~1e-4 and clipped; the count is capped at maxCount so
  /// that the branch's own observations take over the statistics within a few iterations.
  void adaptForBranch(double maxCount);

  /// Appends `extra` features at mean 0 and variance 1 (a network widened for new inputs after the old ones: the
  /// multi-task network's one-hot after a skill's observation); the count stays.
  void appendFeatures(int extra);

  /// Appends the statistics.
  void save(ByteWriter* out) const;
  /// Reads what save wrote. Throws engine::Error on malformed data.
  void load(ByteReader* in);

 private:
  void refreshCache();  // recomputes the float mean and 1/std used by normalize
  // Chan et al.'s combination of the statistics with a batch of n samples' mean and (biased) variance
  void combine(double n, const Eigen::VectorXd& batchMean, const Eigen::VectorXd& batchVar);

  Eigen::VectorXd mean_, var_;
  double count_ = kInitialCount;
  float clip_ = 5.0f;
  Eigen::VectorXf meanF_, invStdF_;
};

}  // namespace ai
