// trainer_test.cpp — end-to-end PPO on pendulum swing-up: it learns within a fixed budget, two runs with
// the same seed are bit-identical, an interrupted and resumed run equals an uninterrupted one, and a
// non-finite value stops training with TrainingDiverged and a state dump.
#include "ai/ppo/trainer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ai/env/pendulum_env.h"
#include "ai/ppo/checkpoint.h"
#include "engine/core/file_io.h"

namespace ai {
namespace {

std::string freshDir(const std::string& name) {
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("tl_trainer_" + std::to_string(::getpid()) + "_" + name)).string();
  std::filesystem::remove_all(dir);
  return dir;
}

// small networks and pendulum-friendly settings (gamma 0.95: a ~1 s horizon at 20 Hz)
PpoConfig pendulumConfig() {
  PpoConfig c;
  c.bufferSize = 3200;  // 16 envs x 200 steps: one episode per env per iteration
  c.batchSize = 320;
  c.numEpoch = 10;
  c.gamma = 0.95;
  c.lambda = 0.95;
  c.learningRate = 1e-3;
  c.learningRateFinal = 1e-4;
  c.epsilonFinal = 0.2;
  c.beta = 0.0;
  c.betaFinal = 0.0;
  c.actorHidden = {64, 64};
  c.criticHidden = {64, 64};
  c.maxGradNorm = 0.5;
  return c;
}

// deterministic evaluation: mean return of 4 full episodes with the mean action
double evaluatePendulum(const PolicyState& policy) {
  PendulumEnv env(4);
  Eigen::MatrixXf obs, actions;
  StepResult step;
  env.reset(12345, &obs);
  double total = 0;
  for (int t = 0; t < PendulumEnv::kEpisodeSteps; ++t) {
    actDeterministic(policy, obs, &actions);
    env.step(actions, &step);
    total += step.rewards.sum();
    obs = step.observations;
  }
  return total / 4.0;
}

// log rows without the wall-clock columns (wall_s, steps_per_s, rollout_physics_s, inference_s, update_s)
std::string deterministicColumns(const std::string& csv) {
  std::istringstream in(csv);
  std::string line, out;
  std::vector<std::string> header;
  while (std::getline(in, line)) {
    std::istringstream cells(line);
    std::string cell;
    size_t i = 0;
    while (std::getline(cells, cell, ',')) {
      if (header.size() <= i) header.push_back(cell);
      const std::string& name = header[i++];
      if (name != "wall_s" && name != "steps_per_s" && name != "rollout_physics_s" && name != "inference_s" &&
          name != "update_s")
        out += cell + ",";
    }
    out += "\n";
  }
  return out;
}

TEST(Trainer, PpoSolvesPendulumSwingUpWithin200kSteps) {
  // measured (Release, one core): ~4 s; returns cross -400 near 70k steps and reach -120..-230 by 150k
  // for seeds 1-6
  const std::string dir = freshDir("learn");
  PendulumEnv env(16);
  TrainerOptions options;
  options.runDir = dir;
  options.totalSteps = 200000;
  options.seed = 1;
  options.checkpointEvery = 1000;
  double lastReturn = -1e9;
  options.onIteration = [&](const TrainerProgress& p) { lastReturn = p.meanEpisodeReturn; };
  const auto start = std::chrono::steady_clock::now();
  Trainer trainer(env, pendulumConfig(), options);
  trainer.run();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double evalReturn = evaluatePendulum(trainer.policy());
  std::printf("pendulum: %lld steps in %.1f s, last training return %.1f, deterministic eval return %.1f\n",
              (long long)trainer.envSteps(), seconds, lastReturn, evalReturn);
  // random actions score about -1200 per episode; a swing-up policy about -150 to -400
  EXPECT_GT(lastReturn, -400.0);
  EXPECT_GT(evalReturn, -400.0);
  std::filesystem::remove_all(dir);
}

// 6 iterations of 3200 steps, evaluation every 2 iterations
TrainerOptions shortRun(const std::string& dir) {
  TrainerOptions options;
  options.runDir = dir;
  options.totalSteps = 6 * 3200;
  options.seed = 7;
  options.evaluate = evaluatePendulum;
  options.evalEvery = 2;
  return options;
}

void trainShort(const std::string& dir, const std::function<void(TrainerOptions*)>& tweak = {},
                const PpoConfig& config = pendulumConfig()) {
  PendulumEnv env(16);
  TrainerOptions options = shortRun(dir);
  if (tweak) tweak(&options);
  Trainer trainer(env, config, options);
  trainer.run();
}

// a short run with checkpoints every 2 iterations that dies (an exception) after iteration 3
bool crashesAfterIterationThree(const std::string& dir, const PpoConfig& config = pendulumConfig()) {
  struct Crash {};
  try {
    trainShort(
        dir,
        [](TrainerOptions* o) {
          o->checkpointEvery = 2;
          o->onIteration = [](const TrainerProgress& p) {
            if (p.iteration == 3) throw Crash{};
          };
        },
        config);
  } catch (const Crash&) {
    return true;
  }
  return false;
}

TEST(Trainer, SameSeedGivesBitIdenticalCheckpointAndLog) {
  const std::string a = freshDir("det_a"), b = freshDir("det_b"), c = freshDir("det_c");
  trainShort(a);
  trainShort(b);
  trainShort(c, [](TrainerOptions* o) { o->seed = 8; });
  EXPECT_EQ(engine::readFile(a + "/checkpoint.bin"), engine::readFile(b + "/checkpoint.bin"));
  EXPECT_EQ(engine::readFile(a + "/best.bin"), engine::readFile(b + "/best.bin"));
  const std::string logA = deterministicColumns(engine::readFile(a + "/log.csv"));
  EXPECT_EQ(logA, deterministicColumns(engine::readFile(b + "/log.csv")));
  EXPECT_EQ(std::count(logA.begin(), logA.end(), '\n'), 7);  // header + 6 rows
  EXPECT_NE(engine::readFile(a + "/checkpoint.bin"), engine::readFile(c + "/checkpoint.bin"));
  for (const std::string& d : {a, b, c}) std::filesystem::remove_all(d);
}

TEST(Trainer, ResumedRunEqualsUninterruptedRun) {
  const std::string straight = freshDir("straight"), crashed = freshDir("crashed"), stopped = freshDir("stopped");
  trainShort(straight);

  // crash after iteration 3 with checkpoints every 2 iterations: the resume restarts from iteration 2 and
  // drops log row 3
  EXPECT_TRUE(crashesAfterIterationThree(crashed));
  EXPECT_EQ(loadCheckpoint(crashed + "/checkpoint.bin").iteration, 2);
  trainShort(crashed, [](TrainerOptions* o) {
    o->checkpointEvery = 2;
    o->resume = true;
  });

  // a requested stop after iteration 3 saves a checkpoint there; resume continues from it
  {
    PendulumEnv env(16);
    TrainerOptions options = shortRun(stopped);
    Trainer* self = nullptr;
    options.onIteration = [&](const TrainerProgress& p) {
      if (p.iteration == 3) self->requestStop();
    };
    Trainer trainer(env, pendulumConfig(), options);
    self = &trainer;
    trainer.run();
    EXPECT_EQ(trainer.iteration(), 3);
  }
  trainShort(stopped, [](TrainerOptions* o) { o->resume = true; });

  const std::string expected = engine::readFile(straight + "/checkpoint.bin");
  const std::string expectedLog = deterministicColumns(engine::readFile(straight + "/log.csv"));
  for (const std::string& d : {crashed, stopped}) {
    EXPECT_EQ(engine::readFile(d + "/checkpoint.bin"), expected) << d;
    EXPECT_EQ(engine::readFile(d + "/best.bin"), engine::readFile(straight + "/best.bin")) << d;
    EXPECT_EQ(deterministicColumns(engine::readFile(d + "/log.csv")), expectedLog) << d;
  }
  for (const std::string& d : {straight, crashed, stopped}) std::filesystem::remove_all(d);
}

TEST(Trainer, ResumeKeepsTheAdaptiveLearningRate) {
  // the adaptive rate lives between iterations: a run resumed from iteration 2 must continue with the rate it
  // had there, or its later updates (and checkpoint) differ from the uninterrupted run's
  PpoConfig adaptive = pendulumConfig();
  adaptive.adaptiveLearningRate = true;
  adaptive.learningRate = 3e-4;  // inside the bounds [1e-6, 1e-3], so that the rate can move either way
  const std::string straight = freshDir("adaptive_straight"), crashed = freshDir("adaptive_crashed");
  trainShort(straight, {}, adaptive);
  EXPECT_TRUE(crashesAfterIterationThree(crashed, adaptive));
  const TrainerCheckpoint atTwo = loadCheckpoint(crashed + "/checkpoint.bin");
  EXPECT_EQ(atTwo.iteration, 2);
  EXPECT_NE(atTwo.adaptiveLearningRate, adaptive.learningRate);  // it moved (the pendulum's KL is not 0.01)
  trainShort(
      crashed,
      [](TrainerOptions* o) {
        o->checkpointEvery = 2;
        o->resume = true;
      },
      adaptive);
  EXPECT_EQ(engine::readFile(crashed + "/checkpoint.bin"), engine::readFile(straight + "/checkpoint.bin"));
  EXPECT_EQ(deterministicColumns(engine::readFile(crashed + "/log.csv")),
            deterministicColumns(engine::readFile(straight + "/log.csv")));
  // and it differs from the linear schedule's run
  const std::string linear = freshDir("adaptive_linear");
  trainShort(linear);
  EXPECT_NE(engine::readFile(linear + "/checkpoint.bin"), engine::readFile(straight + "/checkpoint.bin"));
  for (const std::string& d : {straight, crashed, linear}) std::filesystem::remove_all(d);
}

TEST(Trainer, ResumeRefusesChangedConfigOrMissingCheckpoint) {
  const std::string dir = freshDir("refuse");
  PendulumEnv env(16);
  TrainerOptions options = shortRun(dir);
  options.resume = true;
  EXPECT_THROW(Trainer(env, pendulumConfig(), options).run(), engine::Error);  // no checkpoint yet
  trainShort(dir, [](TrainerOptions* o) { o->totalSteps = 3200; });
  PpoConfig changed = pendulumConfig();
  changed.gamma = 0.9;
  try {
    Trainer(env, changed, options).run();
    ADD_FAILURE() << "resume with a changed config must fail";
  } catch (const engine::Error& e) {
    EXPECT_NE(std::string(e.what()).find("different PPO config"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

TEST(Trainer, BranchInitialisationCopiesParentAndReinflatesLogStd) {
  PendulumEnv env(16);
  PolicyState parent = makePolicyState(pendulumConfig(), 3, 1, 3);
  parent.logStd(0) = -2.0f;
  Trainer trainer(env, pendulumConfig(), shortRun(freshDir("branch")));
  trainer.initialiseFrom(parent, -1.0f);
  EXPECT_TRUE(trainer.policy().actor.W[0] == parent.actor.W[0]);
  EXPECT_TRUE(trainer.policy().critic.W[2] == parent.critic.W[2]);
  EXPECT_EQ(trainer.policy().logStd(0), -1.0f);  // max(-2, -1)
  trainer.initialiseFrom(parent);                // NaN: keep
  EXPECT_EQ(trainer.policy().logStd(0), -2.0f);
}

TEST(Trainer, AFineTuneKeepsTheNormalizersWeightWhereABranchCapsIt) {
  PendulumEnv env(16);
  PolicyState saved = makePolicyState(pendulumConfig(), 3, 1, 3);
  const Eigen::MatrixXf states = Eigen::MatrixXf::Random(3, 4000) * 2.0f;
  for (int k = 0; k < 100; ++k) saved.normalizer.update(states);  // 400,000 samples seen by the run that saved it
  ASSERT_GT(saved.normalizer.count(), 4e5);
  Trainer trainer(env, pendulumConfig(), shortRun(freshDir("finetune")));
  trainer.initialiseFrom(saved, std::nanf(""), /*fineTune=*/true);
  EXPECT_EQ(trainer.policy().normalizer.count(), saved.normalizer.count());
  EXPECT_TRUE(trainer.policy().normalizer.mean() == saved.normalizer.mean());
  trainer.initialiseFrom(saved);  // a branch: its own observations take over within a few iterations
  EXPECT_EQ(trainer.policy().normalizer.count(), Trainer::kBranchNormalizerCount);
  EXPECT_TRUE(trainer.policy().normalizer.mean() == saved.normalizer.mean());
}

TEST(Trainer, ZeroedOutputLayerActsAsNothingButKeepsTheParentsFeatures) {
  PolicyState parent = makePolicyState(pendulumConfig(), 3, 1, 3);
  const Eigen::MatrixXf obs = Eigen::MatrixXf::Random(3, 5);
  Eigen::MatrixXf before, after;
  actDeterministic(parent, obs, &before);
  ASSERT_GT(before.cwiseAbs().maxCoeff(), 0.0f);
  PolicyState branch = parent;
  zeroActorOutput(&branch);
  actDeterministic(branch, obs, &after);
  EXPECT_EQ(after.cwiseAbs().maxCoeff(), 0.0f);         // adds nothing to the prior
  EXPECT_TRUE(branch.actor.W[0] == parent.actor.W[0]);  // hidden layers, critic and log-std are the parent's
  EXPECT_TRUE(branch.critic.W[2] == parent.critic.W[2]);
  EXPECT_TRUE(branch.logStd == parent.logStd);
}

TEST(Trainer, CriticWarmupMovesOnlyTheCriticThenTheActorLearns) {
  PendulumEnv env(16);
  TrainerOptions options = shortRun(freshDir("warmup"));
  options.totalSteps = 2 * 3200;  // two iterations, both warm-up
  options.criticWarmupIterations = 2;
  options.evaluate = nullptr;
  Trainer trainer(env, pendulumConfig(), options);
  const PolicyState start = trainer.policy();
  trainer.run();
  EXPECT_TRUE(trainer.policy().actor.W[0] == start.actor.W[0]);
  EXPECT_TRUE(trainer.policy().actor.b.back() == start.actor.b.back());
  EXPECT_TRUE(trainer.policy().logStd == start.logStd);
  EXPECT_FALSE(trainer.policy().critic.W[0] == start.critic.W[0]);
  // without the warm-up the same run moves the actor
  PendulumEnv env2(16);
  options.criticWarmupIterations = 0;
  options.runDir = freshDir("warmup_none");
  Trainer plain(env2, pendulumConfig(), options);
  plain.run();
  EXPECT_FALSE(plain.policy().actor.W[0] == start.actor.W[0]);
}

TEST(Trainer, AFrozenNormalizerKeepsTheLoadedStatisticsWhileTheActorLearns) {
  PendulumEnv env(16);
  TrainerOptions options = shortRun(freshDir("frozen"));
  options.totalSteps = 2 * 3200;
  options.evaluate = nullptr;
  options.freezeNormalizer = true;
  Trainer trainer(env, pendulumConfig(), options);
  const PolicyState start = trainer.policy();
  trainer.run();
  EXPECT_TRUE(trainer.policy().normalizer.mean() == start.normalizer.mean());
  EXPECT_TRUE(trainer.policy().normalizer.variance() == start.normalizer.variance());
  EXPECT_FALSE(trainer.policy().actor.W[0] == start.actor.W[0]);
  // unfrozen, the same run moves the statistics toward the pendulum's states
  PendulumEnv env2(16);
  options.freezeNormalizer = false;
  options.runDir = freshDir("frozen_not");
  Trainer plain(env2, pendulumConfig(), options);
  plain.run();
  EXPECT_FALSE(plain.policy().normalizer.mean() == start.normalizer.mean());
}

TEST(Trainer, NonFiniteValueStopsWithTrainingDivergedAndDumpsState) {
  const std::string dir = freshDir("nan");
  PendulumEnv env(16);
  PolicyState parent = makePolicyState(pendulumConfig(), 3, 1, 3);
  parent.critic.W[2](0, 0) = std::nanf("");  // NaN values -> NaN returns -> NaN value loss
  Trainer trainer(env, pendulumConfig(), shortRun(dir));
  trainer.initialiseFrom(parent);
  try {
    trainer.run();
    ADD_FAILURE() << "expected TrainingDiverged";
  } catch (const TrainingDiverged& e) {
    EXPECT_NE(std::string(e.what()).find("training diverged: policy loss"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("in iteration 1"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(std::filesystem::exists(dir + "/diverged.bin"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/checkpoint.bin"));
  std::filesystem::remove_all(dir);
}

// a pendulum whose rewards turn NaN after 50 steps
class NanRewardEnv final : public VecEnv {
 public:
  int numEnvs() const override { return inner_.numEnvs(); }
  int observationSize() const override { return 3; }
  int actionSize() const override { return 1; }
  void reset(uint64_t seed, Eigen::MatrixXf* obs) override { inner_.reset(seed, obs), steps_ = 0; }
  void step(const Eigen::MatrixXf& actions, StepResult* result) override {
    inner_.step(actions, result);
    if (++steps_ > 50) result->rewards(3) = std::nanf("");
  }

 private:
  PendulumEnv inner_{4};
  int steps_ = 0;
};

TEST(Trainer, NonFiniteRewardStopsWithTrainingDiverged) {
  const std::string dir = freshDir("nanreward");
  NanRewardEnv env;
  Trainer trainer(env, pendulumConfig(), shortRun(dir));
  try {
    trainer.run();
    ADD_FAILURE() << "expected TrainingDiverged";
  } catch (const TrainingDiverged& e) {
    EXPECT_NE(std::string(e.what()).find("non-finite reward (iteration 1, step 50)"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ai
