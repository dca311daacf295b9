// mpi_check.cpp — the data-parallel PPO update checked under mpirun (tests/apps/mpi_cli_test.cpp starts it with
// `mpirun -np N`). One rollout buffer of 8 environments is made from a seed on every rank; each rank keeps its share
// of the environments (dist::envShare) and runs PpoUpdater::update over the ranks, and every rank also runs the
// single-process update on the whole buffer. It prints, on rank 0:
//   ranks N
//   ranks agree 1|0             (every rank ends with the same policy bytes)
//   largest difference D        (ranks' update against the single process's, over every weight)
//   largest weight W
//   approx kl K_ranks K_single
//   normaliser difference V     (its mean and variance from every rank's sums, against one update on all columns)
// and exits 0, or 2 with a message if something throws.
#include <cmath>
#include <cstdio>
#include <random>

#include "ai/dist/comm.h"
#include "ai/nn/byte_io.h"
#include "ai/nn/normalizer.h"
#include "ai/ppo/checkpoint.h"
#include "ai/ppo/ppo.h"
#include "engine/core/hash.h"

namespace {

using namespace ai;

// the largest |a - b| over two lists of tensors of the same shapes, and the largest |a|
void compare(const std::vector<TensorRef>& a, const std::vector<TensorRef>& b, double* diff, double* largest) {
  for (size_t t = 0; t < a.size(); ++t)
    for (Eigen::Index i = 0; i < a[t].size; ++i) {
      *diff = std::max(*diff, std::abs(double(a[t].data[i]) - double(b[t].data[i])));
      *largest = std::max(*largest, std::abs(double(a[t].data[i])));
    }
}

int check() {
  const dist::Comm& comm = dist::world();
  PpoConfig config;
  const int obsSize = 6, actSize = 3, steps = 64, envs = 8;
  config.bufferSize = steps * envs;
  config.batchSize = 128;  // 4 minibatches an epoch
  config.numEpoch = 2;
  config.actorHidden = {32, 32};
  config.criticHidden = {16};

  // the run's buffer, the same on every rank
  std::mt19937_64 draw(11);
  std::normal_distribution<float> normal;
  RolloutBuffer all;
  all.resize(obsSize, actSize, steps, envs);
  for (float* m : {all.observations.data(), all.actions.data()})
    for (Eigen::Index i = 0, n = (m == all.observations.data() ? all.observations : all.actions).size(); i < n; ++i)
      m[i] = normal(draw);
  for (int i = 0; i < all.size(); ++i) {
    all.logProbs(i) = -3.0f + 0.3f * normal(draw);
    all.values.data()[i] = normal(draw);
    all.advantages.data()[i] = normal(draw);
    all.returns.data()[i] = all.values.data()[i] + all.advantages.data()[i];
  }

  // this rank's environments
  const dist::EnvShare share = dist::envShare(envs, comm);
  RolloutBuffer mine;
  mine.resize(obsSize, actSize, steps, share.count);
  std::vector<int> localOf(size_t(envs), -1);
  for (int n = 0; n < share.count; ++n) {
    const int from = share.first + n;
    localOf[size_t(from)] = n;
    mine.observations.middleCols(n * steps, steps) = all.observations.middleCols(from * steps, steps);
    mine.actions.middleCols(n * steps, steps) = all.actions.middleCols(from * steps, steps);
    mine.logProbs.segment(n * steps, steps) = all.logProbs.segment(from * steps, steps);
    mine.values.col(n) = all.values.col(from);
    mine.advantages.col(n) = all.advantages.col(from);
    mine.returns.col(n) = all.returns.col(from);
  }

  const PolicyState start = makePolicyState(config, obsSize, actSize, 7);
  const PpoCoefficients coefficients;
  PolicyState ranks = start, single = start;
  PpoUpdater overRanks(config), oneProcess(config);
  overRanks.setRanks(&comm, localOf);
  std::mt19937_64 rngRanks(5), rngSingle(5);
  const PpoStats a = overRanks.update(mine, coefficients, &rngRanks, &ranks);
  const PpoStats b = oneProcess.update(all, coefficients, &rngSingle, &single);

  ByteWriter w;
  writePolicyState(&w, ranks);
  const std::vector<std::string> hashes = comm.gather(engine::toHex(engine::hashBytes(w.data())));
  bool agree = true;
  for (const std::string& h : hashes) agree = agree && h == hashes.front();

  std::vector<TensorRef> ra, sa;
  appendTensors(&ranks.actor, &ra);
  appendTensors(&ranks.critic, &ra);
  appendTensor(&ranks.logStd, &ra);
  appendTensors(&single.actor, &sa);
  appendTensors(&single.critic, &sa);
  appendTensor(&single.logStd, &sa);
  double diff = 0, largest = 0;
  compare(ra, sa, &diff, &largest);
  // the normaliser: two batches of the 8 environments' observations, each folded in from the ranks' sums
  RunningNormalizer overSums(obsSize), onAll(obsSize);
  for (int step = 0; step < 2; ++step) {
    Eigen::MatrixXf batch(obsSize, envs);
    for (Eigen::Index i = 0; i < batch.size(); ++i) batch.data()[i] = 3.0f + 2.0f * normal(draw);
    std::vector<double> sums;
    overSums.batchSums(batch.middleCols(share.first, share.count), &sums);
    comm.sum(sums.data(), sums.size());
    overSums.foldSums(sums);
    onAll.update(batch);
  }
  const double normaliserDiff = std::max((overSums.mean() - onAll.mean()).cwiseAbs().maxCoeff(),
                                         float((overSums.variance() - onAll.variance()).cwiseAbs().maxCoeff()));
  if (comm.isRoot()) {
    std::printf(
        "ranks %d\nranks agree %d\nlargest difference %.6g\nlargest weight %.6g\napprox kl %.9g %.9g\n"
        "normaliser difference %.6g\n",
        comm.size(), agree ? 1 : 0, diff, largest, a.approxKl, b.approxKl, normaliserDiff);
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

int main() {
  try {
    return check();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    ai::dist::world().abort(2);
  }
}
