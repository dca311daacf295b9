// trainer.cpp — the PPO loop: per iteration reset the envs from a derived seed, collect T steps x N envs with
// one batched forward per step, GAE, update, evaluate, log a CSV row, checkpoint atomically.
#include "ai/ppo/trainer.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ai/nn/byte_io.h"
#include "ai/ppo/checkpoint.h"
#include "ai/ppo/gaussian.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"

namespace ai {
namespace {

using engine::Error;
using Clock = std::chrono::steady_clock;

constexpr uint64_t kTrainerRngSalt = 0x7472616E6572ull;
constexpr uint64_t kResetSeedSalt = 0x72657365745FEEDull;

uint64_t splitMix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string fmt(double v) {
  if (std::isnan(v)) return "nan";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

void requireFinite(const Eigen::MatrixXf& m, const char* what, int64_t iteration, int step) {
  if (!m.allFinite())
    throw TrainingDiverged("the environment returned a non-finite " + std::string(what) + " (iteration " +
                           std::to_string(iteration + 1) + ", step " + std::to_string(step) + ")");
}

}  // namespace

struct Trainer::RolloutStats {
  double rewardSum = 0;         // unscaled, over all env steps
  double episodeReturnSum = 0;  // over finished episodes
  double episodeLengthSum = 0;
  int64_t episodes = 0;
  std::vector<double> termSums;  // per reward term, over all env steps
};

Trainer::Trainer(VecEnv& env, const PpoConfig& config, TrainerOptions options)
    : env_(env),
      config_(config),
      options_(std::move(options)),
      comm_(dist::orOneProcess(options_.comm)),
      updater_(config) {
  validatePpoConfig(config_, "ppo config");
  Eigen::setNbThreads(1);  // products outside the update (batched inference) stay on this thread
  if (options_.runDir.empty()) throw Error("trainer: runDir is empty");
  if (options_.totalSteps <= 0) throw Error("trainer: totalSteps must be positive");
  if (options_.evalEvery < 1 || options_.checkpointEvery < 1)
    throw Error("trainer: evalEvery and checkpointEvery must be at least 1");
  const int envs = env_.numEnvs();
  if (envs < 1 || env_.observationSize() < 1 || env_.actionSize() < 1)
    throw Error("trainer: the environment has no envs, observations or actions");
  const int runEnvs = env_.globalEnvs();
  if (runEnvs != envs * comm_.size())
    throw Error("trainer: " + std::to_string(comm_.size()) + " ranks of " + std::to_string(envs) +
                " environments, but the run has " + std::to_string(runEnvs));
  for (int n = 0; n < envs; ++n) columns_.push_back(env_.globalColumn(n));
  stepsPerEnv_ = config_.bufferSize / runEnvs;
  if (stepsPerEnv_ < 1)
    throw Error("trainer: buffer_size " + std::to_string(config_.bufferSize) + " is smaller than the " +
                std::to_string(runEnvs) + " environments");
  if (comm_.size() > 1) {
    std::vector<int> localOf(size_t(runEnvs), -1);
    for (int n = 0; n < envs; ++n) {
      const int c = columns_[size_t(n)];
      if (c < 0 || c >= runEnvs || localOf[size_t(c)] >= 0)
        throw Error("trainer: the env's run columns are not a share");
      localOf[size_t(c)] = n;
    }
    updater_.setRanks(&comm_, std::move(localOf));
  }
  policy_ = makePolicyState(config_, env_.observationSize(), env_.actionSize(), options_.seed);
  rng_.seed(splitMix64(options_.seed ^ kTrainerRngSalt));
  buffer_.resize(env_.observationSize(), env_.actionSize(), stepsPerEnv_, envs);
}

void Trainer::initialiseFrom(const PolicyState& parent, float reinflateLogStd, bool fineTune) {
  if (parent.observationSize() != env_.observationSize() || parent.actionSize() != env_.actionSize() ||
      parent.normalizer.size() != env_.observationSize() || parent.critic.inputSize() != env_.observationSize())
    throw Error("trainer: the parent policy's observation/action sizes (" + std::to_string(parent.observationSize()) +
                ", " + std::to_string(parent.actionSize()) + ") do not match the environment's (" +
                std::to_string(env_.observationSize()) + ", " + std::to_string(env_.actionSize()) + ")");
  policy_ = parent;
  if (!fineTune) policy_.normalizer.adaptForBranch(kBranchNormalizerCount);
  if (!std::isnan(reinflateLogStd)) policy_.logStd = policy_.logStd.cwiseMax(reinflateLogStd);
  updater_.optimizer().reset();
  updater_.setAdaptiveLearningRate(std::nan(""));
  iteration_ = 0;
  envSteps_ = 0;
  bestScore_ = -std::numeric_limits<double>::infinity();
}

uint64_t Trainer::policyHashOnEveryRank() const {
  ByteWriter w;
  writePolicyState(&w, policy_);
  const uint64_t mine = engine::hashBytes(w.data());
  const std::vector<std::string> all = comm_.gather(engine::toHex(mine));
  for (size_t r = 1; r < all.size(); ++r)
    if (all[r] != all[0])
      throw Error("the ranks' policies differ (rank 0 " + all[0] + ", rank " + std::to_string(r) + " " + all[r] +
                  "): they no longer train one run");
  return mine;
}

std::vector<std::string> Trainer::logColumns() const {
  std::vector<std::string> c = {"iteration",           "env_steps",          "wall_s", "steps_per_s", "mean_reward",
                                "mean_episode_return", "mean_episode_length"};
  for (const std::string& name : env_.rewardTermNames()) c.push_back("reward_" + name);
  for (const char* name : {"entropy", "approx_kl", "clip_fraction", "explained_variance", "policy_loss", "value_loss",
                           "grad_norm", "lr", "rollout_physics_s", "inference_s", "update_s", "eval_score", "lesson"})
    c.push_back(name);
  return c;
}

void Trainer::collectRollout(RolloutStats* stats, Timing* timing) {
  const int envs = env_.numEnvs(), steps = stepsPerEnv_;
  const int obsSize = env_.observationSize();
  const size_t terms = env_.rewardTermNames().size();
  stats->termSums.assign(terms, 0.0);
  buffer_.truncatedValues.setZero();

  // a fresh start from a seed derived from (run seed, iteration): nothing carries over between iterations
  env_.reset(splitMix64(options_.seed ^ splitMix64(uint64_t(iteration_) ^ kResetSeedSalt)), &obs_);
  if (obs_.rows() != obsSize || obs_.cols() != envs)
    throw Error("trainer: env.reset returned observations of the wrong shape");

  for (int t = 0; t < steps; ++t) {
    // batched inference: one forward of actor and critic for all environments
    const Clock::time_point t0 = Clock::now();
    requireFinite(obs_, "observation", iteration_, t);
    if (config_.normalizeObservations && !options_.freezeNormalizer) {
      if (comm_.size() == 1) {
        policy_.normalizer.update(obs_);
      } else {  // every rank's observations: their sums about the mean, added up (173 doubles, whatever the ranks)
        policy_.normalizer.batchSums(obs_, &normalizerSums_);
        comm_.sum(normalizerSums_.data(), normalizerSums_.size());
        policy_.normalizer.foldSums(normalizerSums_);
      }
    }
    policy_.normalizer.normalize(obs_, &normObs_);
    mlpForward(policy_.actor, normObs_, &mean_);
    mlpForward(policy_.critic, normObs_, &values_);
    if (comm_.size() == 1)
      sampleGaussian(&rng_, mean_, policy_.logStd, &actions_);
    else  // the noise of all the run's environments, as one process draws it; this rank's columns of it
      sampleGaussianColumns(&rng_, mean_, policy_.logStd, columns_, env_.globalEnvs(), &noise_, &actions_);
    const Eigen::VectorXf logProbs = gaussianLogProb(actions_, mean_, policy_.logStd);
    for (int n = 0; n < envs; ++n) {
      const int i = buffer_.index(t, n);
      buffer_.observations.col(i) = normObs_.col(n);
      buffer_.actions.col(i) = actions_.col(n);
      buffer_.logProbs(i) = logProbs(n);
      buffer_.values(t, n) = values_(0, n);
    }
    const Clock::time_point t1 = Clock::now();
    timing->inference += std::chrono::duration<double>(t1 - t0).count();

    env_.step(actions_, &step_);
    const Clock::time_point t2 = Clock::now();
    timing->physics += std::chrono::duration<double>(t2 - t1).count();

    // store rewards and how each episode ended
    if (step_.rewards.size() != envs || step_.terminated.size() != size_t(envs) ||
        step_.truncated.size() != size_t(envs) || step_.observations.rows() != obsSize ||
        step_.observations.cols() != envs)
      throw Error("trainer: env.step returned results of the wrong shape");
    requireFinite(step_.rewards, "reward", iteration_, t);
    int truncatedCount = 0;
    for (int n = 0; n < envs; ++n) {
      stats->rewardSum += double(step_.rewards(n));
      buffer_.rewards(t, n) = float(double(step_.rewards(n)) * config_.rewardScale);
      buffer_.terminated(t, n) = step_.terminated[size_t(n)] ? 1 : 0;
      buffer_.truncated(t, n) = step_.truncated[size_t(n)] && !step_.terminated[size_t(n)] ? 1 : 0;
      truncatedCount += buffer_.truncated(t, n);
    }
    for (size_t e = 0; e < step_.episodeReturns.size(); ++e) {
      stats->episodeReturnSum += double(step_.episodeReturns[e]);
      stats->episodeLengthSum += e < step_.episodeLengths.size() ? double(step_.episodeLengths[e]) : 0.0;
      ++stats->episodes;
    }
    for (size_t k = 0; k < terms && k < step_.rewardTermSums.size(); ++k) stats->termSums[k] += step_.rewardTermSums[k];

    // time-outs bootstrap from V(final observation): one batched critic pass over the truncated columns
    if (truncatedCount > 0) {
      finalObs_.resize(obsSize, truncatedCount);
      for (int n = 0, j = 0; n < envs; ++n)
        if (buffer_.truncated(t, n)) finalObs_.col(j++) = step_.finalObservations.col(n);
      requireFinite(finalObs_, "final observation", iteration_, t);
      policy_.normalizer.normalize(finalObs_, &finalNorm_);
      mlpForward(policy_.critic, finalNorm_, &finalValues_);
      for (int n = 0, j = 0; n < envs; ++n)
        if (buffer_.truncated(t, n)) buffer_.truncatedValues(t, n) = finalValues_(0, j++);
    }
    obs_ = step_.observations;
    timing->inference += secondsSince(t2);
  }

  // the figures of the log are the run's: sums over the ranks
  if (comm_.size() > 1) {
    std::vector<double> sums = {stats->rewardSum, stats->episodeReturnSum, stats->episodeLengthSum,
                                double(stats->episodes)};
    sums.insert(sums.end(), stats->termSums.begin(), stats->termSums.end());
    comm_.sum(sums.data(), sums.size());
    stats->rewardSum = sums[0], stats->episodeReturnSum = sums[1], stats->episodeLengthSum = sums[2];
    stats->episodes = int64_t(sums[3]);
    std::copy(sums.begin() + 4, sums.end(), stats->termSums.begin());
  }

  rolloutLesson_ = env_.curriculumLesson();  // the log's lesson column: the lesson this rollout trained
  env_.endRollout();  // the curriculum measures the rollout (episodes still running were cut here)

  // the horizon cut bootstraps from the value of the observation after the last step
  const Clock::time_point t3 = Clock::now();
  requireFinite(obs_, "observation", iteration_, steps);
  policy_.normalizer.normalize(obs_, &normObs_);
  mlpForward(policy_.critic, normObs_, &values_);
  buffer_.lastValues = values_.row(0).transpose();
  computeGae(buffer_.rewards, buffer_.values, buffer_.terminated, buffer_.truncated, buffer_.truncatedValues,
             buffer_.lastValues, config_.gamma, config_.lambda, &buffer_.advantages, &buffer_.returns);
  timing->inference += secondsSince(t3);
}

void Trainer::writeCheckpoint(const std::string& path) const {
  if (!comm_.isRoot()) return;  // every rank holds the same state; rank 0 writes it
  TrainerCheckpoint c;
  c.configHash = ppoConfigHash(config_);
  c.seed = options_.seed;
  c.totalSteps = options_.totalSteps;
  c.iteration = iteration_;
  c.envSteps = envSteps_;
  c.bestScore = bestScore_;
  c.policy = policy_;
  c.optimizer = updater_.optimizer();
  std::ostringstream rng;
  rng << rng_;
  c.rngState = rng.str();
  c.envState = env_.saveState();
  c.adaptiveLearningRate = updater_.adaptiveLearningRate();
  saveCheckpoint(path, c);
}

void Trainer::resumeFromCheckpoint(double* wallOffset) {
  const std::string path = options_.runDir + "/checkpoint.bin";
  TrainerCheckpoint c = loadCheckpoint(path);
  if (c.configHash != ppoConfigHash(config_))
    throw Error(path + ": written with a different PPO config; resume with the same config or start a new run");
  if (c.seed != options_.seed)
    throw Error(path + ": written with seed " + std::to_string(c.seed) + ", not " + std::to_string(options_.seed));
  if (c.policy.observationSize() != env_.observationSize() || c.policy.actionSize() != env_.actionSize())
    throw Error(path + ": the policy's observation/action sizes do not match the environment");
  std::istringstream rng(c.rngState);
  rng >> rng_;
  if (rng.fail()) throw Error(path + ": malformed RNG state");
  env_.loadState(c.envState);
  policy_ = std::move(c.policy);
  updater_.optimizer() = c.optimizer;
  updater_.setAdaptiveLearningRate(c.adaptiveLearningRate);
  iteration_ = c.iteration;
  envSteps_ = c.envSteps;
  bestScore_ = c.bestScore;

  // keep the header and the rows up to the checkpoint's iteration; continue wall time from the last kept row
  if (!comm_.isRoot()) return;
  const std::string logPath = options_.runDir + "/log.csv";
  std::string header;
  for (const std::string& col : logColumns()) header += (header.empty() ? "" : ",") + col;
  std::string kept = header + "\n";
  std::istringstream in(std::filesystem::exists(logPath) ? engine::readFile(logPath, engine::kMaxDataFileBytes) : "");
  std::string line;
  if (in && std::getline(in, line)) {
    if (line != header) throw Error(logPath + ":1: columns differ from this run's; move the old log away to resume");
    while (std::getline(in, line)) {
      const size_t comma = line.find(',');
      if (comma == std::string::npos) break;  // a partial last line
      int64_t it = 0;
      try {
        it = std::stoll(line.substr(0, comma));
      } catch (const std::exception&) {
        break;
      }
      if (it > iteration_) break;
      const size_t c2 = line.find(',', comma + 1), c3 = line.find(',', c2 + 1);
      if (c2 == std::string::npos || c3 == std::string::npos) break;
      *wallOffset = std::atof(line.substr(c2 + 1, c3 - c2 - 1).c_str());
      kept += line + "\n";
    }
  }
  engine::writeFileAtomic(logPath, kept);
}

std::string Trainer::logRow(const TrainerProgress& p, const RolloutStats& r, double lr, double wall,
                            double stepsPerSecond, const Timing& timing) const {
  const double samples = double(buffer_.size()) * comm_.size();  // the run's samples (termSums are over every rank)
  std::string row = std::to_string(p.iteration) + "," + std::to_string(p.envSteps) + "," + fmt(wall) + "," +
                    fmt(stepsPerSecond) + "," + fmt(p.meanReward) + "," + fmt(p.meanEpisodeReturn) + "," +
                    fmt(p.meanEpisodeLength);
  for (double sum : r.termSums) row += "," + fmt(sum / samples);
  for (double v :
       {p.stats.entropy, p.stats.approxKl, p.stats.clipFraction, p.stats.explainedVariance, p.stats.policyLoss,
        p.stats.valueLoss, p.stats.gradNorm, lr, timing.physics, timing.inference, timing.update})
    row += "," + fmt(v);
  row += "," + (std::isnan(p.evalScore) ? std::string() : fmt(p.evalScore));
  row += "," + std::to_string(rolloutLesson_);
  return row + "\n";
}

void Trainer::run() {
  const bool root = comm_.isRoot();  // rank 0 writes the run folder; the others keep no files
  if (root) {
    engine::makeDirectories(options_.runDir);
    engine::removeStaleTemps(options_.runDir);  // a checkpoint write cut short by a kill left its 7 MB temp
  }
  const std::string logPath = options_.runDir + "/log.csv";
  const std::string checkpointPath = options_.runDir + "/checkpoint.bin";
  double wallOffset = 0;
  if (options_.resume) {
    resumeFromCheckpoint(&wallOffset);
  } else if (root) {
    std::string header;
    for (const std::string& col : logColumns()) header += (header.empty() ? "" : ",") + col;
    engine::writeFileAtomic(logPath, header + "\n");
  }
  std::ofstream log;
  if (root) {
    log.open(logPath, std::ios::app);
    if (!log) throw Error(logPath + ": cannot open for appending");
  }

  const int64_t perIteration = int64_t(buffer_.size()) * comm_.size();
  const int64_t totalIterations = (options_.totalSteps + perIteration - 1) / perIteration;
  const Clock::time_point start = Clock::now();
  int64_t stepsThisProcess = 0;
  stopRequested_ = false;
  stoppedEarly_ = false;

  while (envSteps_ < options_.totalSteps) {
    const Clock::time_point iterationStart = Clock::now();
    const PpoCoefficients coefficients =
        scheduledCoefficients(config_, double(envSteps_) / double(options_.totalSteps));

    // act -> step -> store, GAE, update; a non-finite value leaves the last good checkpoint alone and dumps
    // the current state for inspection
    RolloutStats rollout;
    Timing timing;
    PpoStats stats;
    try {
      collectRollout(&rollout, &timing);
      const Clock::time_point updateStart = Clock::now();
      Eigen::setNbThreads(options_.updateThreads);
      updater_.setActorFrozen(iteration_ < options_.criticWarmupIterations);
      stats = updater_.update(buffer_, coefficients, &rng_, &policy_);
      Eigen::setNbThreads(1);
      timing.update = secondsSince(updateStart);
    } catch (const TrainingDiverged& e) {
      const std::string dump = options_.runDir + "/diverged.bin";
      writeCheckpoint(dump);
      throw TrainingDiverged(std::string(e.what()) + " in iteration " + std::to_string(iteration_ + 1) +
                             "; state saved to " + dump + ", last good checkpoint " + checkpointPath);
    }
    ++iteration_;
    envSteps_ += perIteration;
    stepsThisProcess += perIteration;
    const bool last = envSteps_ >= options_.totalSteps;

    // evaluate; keep the best policy
    TrainerProgress p;
    if (options_.evaluate && (iteration_ % options_.evalEvery == 0 || last)) {  // on every rank (a card shares
      p.evalScore = options_.evaluate(policy_);  // its episodes), the same score everywhere
      if (p.evalScore > bestScore_) {
        bestScore_ = p.evalScore;
        PolicyInfo info{ppoConfigHash(config_), iteration_, envSteps_, p.evalScore};
        if (root) savePolicyState(options_.runDir + "/best.bin", policy_, info);
      }
    }

    // log
    const double elapsed = secondsSince(start);
    p.iteration = iteration_;
    p.totalIterations = totalIterations;
    p.envSteps = envSteps_;
    p.totalSteps = options_.totalSteps;
    p.stepsPerSecond = double(stepsThisProcess) / std::max(elapsed, 1e-9);
    p.etaSeconds = double(std::max<int64_t>(0, options_.totalSteps - envSteps_)) / p.stepsPerSecond;
    p.meanReward = rollout.rewardSum / double(perIteration);
    if (rollout.episodes > 0) {
      p.meanEpisodeReturn = rollout.episodeReturnSum / double(rollout.episodes);
      p.meanEpisodeLength = rollout.episodeLengthSum / double(rollout.episodes);
    }
    p.stats = stats;
    p.curriculumNote = env_.curriculumNote();
    const double iterationSeconds = secondsSince(iterationStart);
    if (root) {
      log << logRow(p, rollout, stats.learningRate, wallOffset + elapsed,
                    double(perIteration) / std::max(iterationSeconds, 1e-9), timing);
      log.flush();
      if (!log) throw Error(logPath + ": write failed");
    }

    // save, report, and honour a stop request (asked of any rank, every rank stops)
    const bool stop = comm_.any(stopRequested_);
    if (iteration_ % options_.checkpointEvery == 0 || last || stop) writeCheckpoint(checkpointPath);
    if (options_.onIteration) options_.onIteration(p);
    if (comm_.any(stopRequested_) && !last) {
      if (!stop) writeCheckpoint(checkpointPath);
      stoppedEarly_ = true;
      break;
    }
  }
  if (comm_.size() > 1) policyHashOnEveryRank();  // every rank took every step alike, or the run is not one run
}

}  // namespace ai
