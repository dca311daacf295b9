// normalizer.cpp — running mean/variance (parallel batch update in double) and clamped normalisation.
#include "ai/nn/normalizer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "ai/nn/byte_io.h"

namespace ai {

RunningNormalizer::RunningNormalizer(int size, float clip)
    : mean_(Eigen::VectorXd::Zero(size)), var_(Eigen::VectorXd::Ones(size)), clip_(clip) {
  refreshCache();
}

void RunningNormalizer::update(const Eigen::MatrixXf& batch) {
  if (batch.rows() != mean_.size()) throw std::invalid_argument("RunningNormalizer::update: wrong feature count");
  const double n = double(batch.cols());
  if (n == 0) return;

  // batch moments in double, then Chan's combination of (mean, var, count) pairs
  const Eigen::MatrixXd x = batch.cast<double>();
  const Eigen::VectorXd batchMean = x.rowwise().mean();
  const Eigen::VectorXd batchVar = (x.colwise() - batchMean).array().square().rowwise().sum().matrix() / n;
  combine(n, batchMean, batchVar);
}

void RunningNormalizer::combine(double n, const Eigen::VectorXd& batchMean, const Eigen::VectorXd& batchVar) {
  const double total = count_ + n;
  const Eigen::VectorXd delta = batchMean - mean_;
  mean_ += delta * (n / total);
  const Eigen::VectorXd m2 = var_ * count_ + batchVar * n + delta.array().square().matrix() * (count_ * n / total);
  var_ = m2 / total;
  count_ = total;
  refreshCache();
}

void RunningNormalizer::batchSums(const Eigen::MatrixXf& batch, std::vector<double>* sums) const {
  if (batch.rows() != mean_.size()) throw std::invalid_argument("RunningNormalizer::batchSums: wrong feature count");
  const Eigen::Index d = mean_.size();
  sums->assign(size_t(1 + 2 * d), 0.0);
  (*sums)[0] = double(batch.cols());
  const Eigen::ArrayXXd shifted = batch.cast<double>().colwise() - mean_;
  Eigen::Map<Eigen::VectorXd>(sums->data() + 1, d) = shifted.rowwise().sum().matrix();
  Eigen::Map<Eigen::VectorXd>(sums->data() + 1 + d, d) = shifted.square().rowwise().sum().matrix();
}

void RunningNormalizer::foldSums(const std::vector<double>& sums) {
  const Eigen::Index d = mean_.size();
  if (sums.size() != size_t(1 + 2 * d)) throw std::invalid_argument("RunningNormalizer::foldSums: wrong size");
  const double n = sums[0];
  if (n == 0) return;
  const Eigen::VectorXd shift = Eigen::Map<const Eigen::VectorXd>(sums.data() + 1, d) / n;
  const Eigen::VectorXd batchMean = mean_ + shift;
  const Eigen::VectorXd batchVar =
      (Eigen::Map<const Eigen::VectorXd>(sums.data() + 1 + d, d) / n - shift.cwiseAbs2()).cwiseMax(0.0);
  combine(n, batchMean, batchVar);
}

void RunningNormalizer::normalize(const Eigen::MatrixXf& x, Eigen::MatrixXf* out) const {
  if (x.rows() != meanF_.size()) throw std::invalid_argument("RunningNormalizer::normalize: wrong feature count");
  out->resize(x.rows(), x.cols());
  out->array() = ((x.colwise() - meanF_).array().colwise() * invStdF_.array()).max(-clip_).min(clip_);
}

Eigen::VectorXf RunningNormalizer::stddev() const {
  return (var_.array() + kVarianceEpsilon).sqrt().matrix().cast<float>();
}

void RunningNormalizer::refreshCache() {
  meanF_ = mean_.cast<float>();
  invStdF_ = (1.0 / (var_.array() + kVarianceEpsilon).sqrt()).matrix().cast<float>();
}

void RunningNormalizer::save(ByteWriter* out) const {
  out->f32(clip_);
  out->f64(count_);
  out->vector(mean_);
  out->vector(var_);
}

void RunningNormalizer::load(ByteReader* in) {
  clip_ = in->f32();
  count_ = in->f64();
  mean_ = in->vectorD();
  var_ = in->vectorD();
  if (mean_.size() != var_.size()) in->fail("normaliser mean and variance differ in size");
  if (!(count_ > 0) || !(clip_ > 0)) in->fail("normaliser count and clip must be positive");
  refreshCache();
}

void RunningNormalizer::adaptForBranch(double maxCount) {
  for (int i = 0; i < int(var_.size()); ++i)
    if (var_[i] < 1e-6) {
      mean_[i] = 0.0;
      var_[i] = 1.0;
    }
  count_ = std::min(count_, maxCount);
  refreshCache();
}

void RunningNormalizer::appendFeatures(int extra) {
  const Eigen::Index n = mean_.size();
  mean_.conservativeResize(n + extra);
  var_.conservativeResize(n + extra);
  mean_.tail(extra).setZero();
  var_.tail(extra).setOnes();
  refreshCache();
}

}  // namespace ai
