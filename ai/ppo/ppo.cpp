// ppo.cpp — policy construction and the PPO update (clipped surrogate, value loss, entropy bonus), read top
// to bottom: shuffle -> gather minibatch -> actor and critic forward -> losses and their gradients ->
// backward -> finite check -> clip global norm -> Adam -> clamp log-std.
#include "ai/ppo/ppo.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <numeric>
#include <sstream>

#include "ai/ppo/gaussian.h"

namespace ai {
namespace {

uint64_t splitMix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

std::vector<int> layerSizes(int in, const std::vector<int>& hidden, int out) {
  std::vector<int> sizes{in};
  sizes.insert(sizes.end(), hidden.begin(), hidden.end());
  sizes.push_back(out);
  return sizes;
}

double lerp(double from, double to, double t) { return from + (to - from) * t; }

}  // namespace

PolicyState makePolicyState(const PpoConfig& config, int observationSize, int actionSize, uint64_t seed) {
  PolicyState p;
  p.actor = makeMlp(layerSizes(observationSize, config.actorHidden, actionSize), config.activation,
                    splitMix64(seed ^ 0xAC7042ull), float(config.actorOutputGain));
  p.critic = makeMlp(layerSizes(observationSize, config.criticHidden, 1), config.activation,
                     splitMix64(seed ^ 0xC2171Cull), float(config.criticOutputGain));
  // without normalisation the normaliser stays at its prior (mean 0, std 1 in float) and never clips
  p.normalizer =
      RunningNormalizer(observationSize, config.normalizeObservations ? float(config.observationClip) : FLT_MAX);
  p.logStd = Eigen::VectorXf::Constant(actionSize, float(config.initialLogStd));
  return p;
}

void zeroActorOutput(PolicyState* policy) {
  policy->actor.W.back().setZero();
  policy->actor.b.back().setZero();
}

void actDeterministic(const PolicyState& policy, const Eigen::MatrixXf& observations, Eigen::MatrixXf* actions) {
  Eigen::MatrixXf normalised;
  policy.normalizer.normalize(observations, &normalised);
  mlpForward(policy.actor, normalised, actions);
}

PpoCoefficients scheduledCoefficients(const PpoConfig& config, double progress) {
  const double t = std::clamp(progress, 0.0, 1.0);
  PpoCoefficients c;
  c.learningRate = lerp(config.learningRate, config.learningRateFinal, t);
  c.epsilon = lerp(config.epsilon, config.epsilonFinal, t);
  c.beta = lerp(config.beta, config.betaFinal, t);
  return c;
}

double adaptLearningRate(double learningRate, double kl, const PpoConfig& config) {
  if (kl > 2.0 * config.desiredKl)
    learningRate /= 1.5;
  else if (kl < 0.5 * config.desiredKl)
    learningRate *= 1.5;
  return std::clamp(learningRate, config.adaptiveLrMin, config.adaptiveLrMax);
}

PpoUpdater::PpoUpdater(const PpoConfig& config) : config_(config) {}

PpoStats PpoUpdater::update(const RolloutBuffer& buffer, const PpoCoefficients& coefficients, std::mt19937_64* rng,
                            PolicyState* policy) {
  PpoStats stats;
  const dist::Comm& comm = dist::orOneProcess(comm_);
  // the run's samples (over every rank); this rank's index of run sample g, or -1 (its own index on one process)
  const int local = buffer.size(), envSteps = buffer.steps;
  const int total = comm_ ? envSteps * int(runEnvs_.size()) : local;
  const auto localIndex = [&](int g) {
    if (!comm_) return g;
    const int n = runEnvs_[size_t(g / envSteps)];
    return n < 0 ? -1 : g % envSteps + n * envSteps;
  };
  if (total <= 0) return stats;
  const int batch = std::min(config_.batchSize, total);
  const int minibatches = total / batch;
  const Eigen::Index obsSize = buffer.observations.rows(), actSize = buffer.actions.rows();
  permutation_.resize(size_t(total));
  if (config_.adaptiveLearningRate && std::isnan(adaptiveLr_))
    adaptiveLr_ = std::clamp(coefficients.learningRate, config_.adaptiveLrMin, config_.adaptiveLrMax);

  for (int epoch = 0; epoch < config_.numEpoch; ++epoch) {
    // Fisher-Yates with our own index draw (std::shuffle's algorithm is library-specific)
    std::iota(permutation_.begin(), permutation_.end(), 0);
    for (int i = total - 1; i > 0; --i)
      std::swap(permutation_[size_t(i)], permutation_[size_t((*rng)() % uint64_t(i + 1))]);

    for (int mb = 0; mb < minibatches; ++mb) {
      // gather this rank's columns of the minibatch (all of them on one process)
      int mine = 0;
      for (int j = 0; j < batch; ++j) mine += localIndex(permutation_[size_t(mb * batch + j)]) >= 0;
      mbObs_.resize(obsSize, mine);
      mbActions_.resize(actSize, mine);
      mbLogProbs_.resize(mine);
      mbAdvantages_.resize(mine);
      mbReturns_.resize(mine);
      mbValues_.resize(mine);
      for (int j = 0, c = 0; j < batch; ++j) {
        const int i = localIndex(permutation_[size_t(mb * batch + j)]);
        if (i < 0) continue;
        mbObs_.col(c) = buffer.observations.col(i);
        mbActions_.col(c) = buffer.actions.col(i);
        mbLogProbs_(c) = buffer.logProbs(i);
        mbAdvantages_(c) = buffer.advantages.data()[i];
        mbReturns_(c) = buffer.returns.data()[i];
        mbValues_(c++) = buffer.values.data()[i];
      }
      try {
        minibatchStep(coefficients, batch, policy, &stats);
      } catch (const TrainingDiverged& e) {
        throw TrainingDiverged(std::string(e.what()) + " (epoch " + std::to_string(epoch + 1) + ", minibatch " +
                               std::to_string(mb + 1) + ")");
      }
    }
  }

  // means over the gradient steps, explained variance over the whole buffer
  const double steps = std::max(1, stats.minibatches);
  stats.policyLoss /= steps;
  stats.valueLoss /= steps;
  stats.entropy /= steps;
  stats.approxKl /= steps;
  stats.clipFraction /= steps;
  stats.gradNorm /= steps;
  stats.learningRate = config_.adaptiveLearningRate ? adaptiveLr_ : coefficients.learningRate;
  // (sums over the ranks, then divided: on one process, Eigen's mean() to the bit)
  const Eigen::ArrayXd ret = Eigen::Map<const Eigen::ArrayXf>(buffer.returns.data(), local).cast<double>();
  const Eigen::ArrayXd val = Eigen::Map<const Eigen::ArrayXf>(buffer.values.data(), local).cast<double>();
  const Eigen::ArrayXd residual = ret - val;
  double means[2] = {ret.sum(), residual.sum()};
  comm.sum(means, 2);
  means[0] /= double(total), means[1] /= double(total);
  double squares[2] = {(ret - means[0]).square().sum(), (residual - means[1]).square().sum()};
  comm.sum(squares, 2);
  const double varReturns = squares[0] / double(total), varResidual = squares[1] / double(total);
  stats.explainedVariance = varReturns > 0 ? 1.0 - varResidual / varReturns : std::nan("");
  return stats;
}

void PpoUpdater::sumGradients() {
  if (!comm_ || comm_->size() == 1) return;
  size_t n = 0;
  for (const TensorRef& g : gradRefs_) n += size_t(g.size);
  flatGrads_.resize(n);
  size_t at = 0;
  for (const TensorRef& g : gradRefs_) std::copy(g.data, g.data + g.size, flatGrads_.data() + at), at += size_t(g.size);
  comm_->sum(flatGrads_.data(), n);
  at = 0;
  for (const TensorRef& g : gradRefs_)
    std::copy(flatGrads_.data() + at, flatGrads_.data() + at + g.size, g.data), at += size_t(g.size);
}

void PpoUpdater::minibatchStep(const PpoCoefficients& c, int batch, PolicyState* policy, PpoStats* stats) {
  const dist::Comm& comm = dist::orOneProcess(comm_);
  const Eigen::Index dims = policy->logStd.size();
  const float eps = float(c.epsilon);
  const float invBatch = 1.0f / float(batch);

  // advantages normalised within the minibatch (unbiased std, as torch.std), over every rank's share of it
  if (config_.normalizeAdvantages && batch > 1) {
    const Eigen::ArrayXd a = mbAdvantages_.cast<double>();
    const double mean = comm.sum(a.sum()) / double(batch);
    const double stddev = std::sqrt(comm.sum((a - mean).square().sum()) / double(batch - 1));
    mbAdvantages_ = ((a - mean) / (stddev + 1e-8)).cast<float>();
  }

  // actor: new log-probabilities and the probability ratio
  mlpForwardTrain(policy->actor, mbObs_, &actorCache_, &mean_);
  const Eigen::ArrayXf invStd = (-policy->logStd.array()).exp();
  z_ = (mbActions_ - mean_).array().colwise() * invStd;
  const float logProbConstant = float(-double(policy->logStd.sum()) - 0.5 * double(dims) * kLog2Pi);
  const Eigen::ArrayXf logRatio = (-0.5f * z_.square().colwise().sum()).transpose() + logProbConstant - mbLogProbs_;
  const Eigen::ArrayXf ratio = logRatio.exp();

  // clipped surrogate: L = -mean(min(r A, clip(r, 1-eps, 1+eps) A)); the gradient flows only where the
  // unclipped term is the minimum
  const Eigen::ArrayXf surr1 = ratio * mbAdvantages_;
  const Eigen::ArrayXf surr2 = ratio.max(1.0f - eps).min(1.0f + eps) * mbAdvantages_;
  const double policySum = double(surr1.min(surr2).cast<double>().sum());
  const Eigen::ArrayXf dLogProb = (surr1 <= surr2).select(-surr1 * invBatch, 0.0f);

  // d logp / d mean_j = z_j / std_j; d logp / d logStd_j = z_j^2 - 1; the entropy bonus -beta * mean_j(logStd_j + c)
  // adds -beta / D to every log-std gradient
  dMean_ = ((z_.colwise() * invStd).rowwise() * dLogProb.transpose()).matrix();
  grads_.logStd = (z_.square() - 1.0f).matrix() * dLogProb.matrix();
  const double entropy = gaussianEntropy(policy->logStd) / double(dims);

  // critic: L_v = mean((V - R)^2), optionally PPO2-clipped around the rollout value
  mlpForwardTrain(policy->critic, mbObs_, &criticCache_, &value_);
  const Eigen::ArrayXf v = value_.row(0).transpose().array();
  const Eigen::ArrayXf err = v - mbReturns_;
  Eigen::ArrayXf dV;
  double valueSum;
  if (config_.clipValueLoss) {
    const Eigen::ArrayXf change = v - mbValues_;
    const Eigen::ArrayXf errClipped = mbValues_ + change.max(-eps).min(eps) - mbReturns_;
    const Eigen::ArrayXf inside = (change.abs() <= eps).cast<float>();
    valueSum = double(err.square().max(errClipped.square()).cast<double>().sum());
    dV = (err.square() >= errClipped.square()).select(2.0f * err, 2.0f * errClipped * inside);
  } else {
    valueSum = double(err.square().cast<double>().sum());
    dV = 2.0f * err;
  }
  dValue_ = (dV * float(config_.valueLossCoef) * invBatch).matrix().transpose();

  // backward through both networks
  mlpBackward(policy->actor, actorCache_, dMean_, &grads_.actor);
  mlpBackward(policy->critic, criticCache_, dValue_, &grads_.critic);

  // one list of (parameter, gradient) views in a fixed order: actor, critic, log-std
  paramRefs_.clear();
  gradRefs_.clear();
  appendTensors(&policy->actor, &paramRefs_);
  appendTensors(&policy->critic, &paramRefs_);
  appendTensor(&policy->logStd, &paramRefs_);
  appendTensors(&grads_.actor, &gradRefs_);
  appendTensors(&grads_.critic, &gradRefs_);
  appendTensor(&grads_.logStd, &gradRefs_);

  // the samples' gradients and sums over every rank's share of the minibatch; then the entropy bonus, which depends on
  // the log-std alone (added once, after the sum)
  sumGradients();
  grads_.logStd.array() -= float(c.beta / double(dims));
  const Eigen::ArrayXf logRatioTerm = (ratio - 1.0f) - logRatio;
  double sums[4] = {policySum, valueSum, double(logRatioTerm.cast<double>().sum()),
                    double(((ratio - 1.0f).abs() > eps).cast<double>().sum())};
  comm.sum(sums, 4);
  const double policyLoss = -(sums[0] / double(batch)), valueLoss = sums[1] / double(batch);

  // refuse a non-finite step, then clip and apply
  if (actorFrozen_) {  // critic warm-up: nothing moves the actor or its noise (and its gradient does not clip the
                       // critic's)
    for (Eigen::MatrixXf& w : grads_.actor.W) w.setZero();
    for (Eigen::VectorXf& b : grads_.actor.b) b.setZero();
    grads_.logStd.setZero();
  }
  const double gradNorm = clipGradNorm(gradRefs_, config_.maxGradNorm);
  if (!std::isfinite(policyLoss) || !std::isfinite(valueLoss) || !std::isfinite(gradNorm)) {
    std::ostringstream m;
    m << "training diverged: policy loss " << policyLoss << ", value loss " << valueLoss << ", gradient norm "
      << gradNorm;
    throw TrainingDiverged(m.str());
  }
  // the KL of this minibatch under the current parameters (before the step) sets the adaptive rate, as rsl_rl
  const double approxKl = sums[2] / double(batch);
  if (!actorFrozen_ && config_.adaptiveLearningRate) adaptiveLr_ = adaptLearningRate(adaptiveLr_, approxKl, config_);
  adam_.step(paramRefs_, gradRefs_, float(config_.adaptiveLearningRate ? adaptiveLr_ : c.learningRate));
  policy->logStd = policy->logStd.cwiseMax(float(config_.logStdMin)).cwiseMin(float(config_.logStdMax));

  stats->policyLoss += policyLoss;
  stats->valueLoss += valueLoss;
  stats->entropy += entropy;
  stats->approxKl += approxKl;
  stats->clipFraction += sums[3] / double(batch);
  stats->gradNorm += gradNorm;
  ++stats->minibatches;
}

}  // namespace ai
