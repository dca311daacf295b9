// ppo_config_test.cpp — PpoConfig defaults (the paper's Table 2), TOML overrides, strict keys with
// file:line errors, and the toToml round trip.
#include "ai/ppo/ppo_config.h"

#include <gtest/gtest.h>

#include "ai/ppo/ppo.h"
#include "engine/core/error.h"

namespace ai {
namespace {

std::string errorOf(const std::string& text) {
  try {
    parsePpoConfig(text, "run.toml");
  } catch (const engine::Error& e) {
    return e.what();
  }
  return "";
}

TEST(PpoConfig, DefaultsAreTable2) {
  const PpoConfig c;
  EXPECT_EQ(c.bufferSize, 20480);
  EXPECT_EQ(c.batchSize, 2048);
  EXPECT_EQ(c.numEpoch, 3);
  EXPECT_EQ(c.gamma, 0.995);
  EXPECT_EQ(c.lambda, 0.95);
  EXPECT_EQ(c.learningRate, 3e-4);
  EXPECT_EQ(c.epsilon, 0.2);
  EXPECT_EQ(c.beta, 5e-3);
  EXPECT_EQ(c.rewardScale, 1.0);
  EXPECT_EQ(c.actorHidden, (std::vector<int>{512, 512, 512}));
  EXPECT_EQ(c.criticHidden, (std::vector<int>{128, 128}));
}

TEST(PpoConfig, TableOverridesDefaults) {
  const PpoConfig c = parsePpoConfig(
      "[env]\nx = 1\n[ppo]\nbatch_size = 512\ngamma = 0.99\nactor_hidden = [64, 64]\n"
      "activation = \"tanh\"\nclip_value_loss = true\nreward_scale = 2\n",
      "run.toml");
  EXPECT_EQ(c.batchSize, 512);
  EXPECT_EQ(c.gamma, 0.99);
  EXPECT_EQ(c.actorHidden, (std::vector<int>{64, 64}));
  EXPECT_EQ(c.activation, Activation::Tanh);
  EXPECT_TRUE(c.clipValueLoss);
  EXPECT_EQ(c.rewardScale, 2.0);  // an integer is accepted for a real field
  EXPECT_EQ(c.bufferSize, 20480);
  EXPECT_EQ(toToml(parsePpoConfig("", "empty.toml")), toToml(PpoConfig{}));  // no [ppo]: defaults
}

TEST(PpoConfig, ASkillsOwnTableOverridesTheSharedOneKeyByKey) {
  const std::string text = "[ppo]\nbatch_size = 512\ndesired_kl = 0.01\n[skill.standup.ppo]\ndesired_kl = 0.02\n";
  const PpoConfig shared = parsePpoConfig(text, "tree.toml", "ppo");
  const PpoConfig standup = parsePpoConfig(text, "tree.toml", "skill.standup.ppo", shared);
  EXPECT_EQ(standup.desiredKl, 0.02);
  EXPECT_EQ(standup.batchSize, 512);  // the shared table's, kept
  EXPECT_EQ(toToml(parsePpoConfig(text, "tree.toml", "skill.walk.ppo", shared)), toToml(shared));  // none of its own
  try {
    parsePpoConfig(text + "gama = 0.9\n", "tree.toml", "skill.standup.ppo", shared);
    ADD_FAILURE() << "a misspelt key was accepted";
  } catch (const engine::Error& e) {
    EXPECT_NE(std::string(e.what()).find("tree.toml:6: unknown key 'gama' in [skill.standup.ppo]"), std::string::npos)
        << e.what();
  }
}

TEST(PpoConfig, UnknownKeyWrongTypeAndBadValueReportFileAndLine) {
  EXPECT_EQ(errorOf("[ppo]\ngamma = 0.9\nbatchsize = 3\n"), "run.toml:3: unknown key 'batchsize' in [ppo]");
  EXPECT_EQ(errorOf("[ppo]\n\nnum_epoch = 2.5\n"), "run.toml:3: 'num_epoch' must be an integer");
  EXPECT_EQ(errorOf("[ppo]\nactivation = \"relu\"\n"), "run.toml:2: 'activation' must be \"elu\" or \"tanh\"");
  EXPECT_EQ(errorOf("[ppo]\ngamma = 1.5\n"), "run.toml:2: gamma must be in (0, 1]");
  EXPECT_EQ(errorOf("[ppo]\ngamma = \n"), errorOf("[ppo]\ngamma = \n"));  // parse errors are located too
  EXPECT_EQ(errorOf("[ppo]\ngamma = \n").rfind("run.toml:2:", 0), 0u);
}

// values that would only fail hours into a run (or never finish) are refused before the first step, at their line
TEST(PpoConfig, NonFiniteAndUnworkableValuesAreRefusedAtTheirLine) {
  EXPECT_EQ(errorOf("[ppo]\nobservation_clip = inf\n"), "run.toml:2: 'observation_clip' must be a finite number");
  EXPECT_EQ(errorOf("[ppo]\nepsilon = nan\n"), "run.toml:2: 'epsilon' must be a finite number");
  EXPECT_EQ(errorOf("[ppo]\ndesired_kl = 1e300\n"), "run.toml:2: desired_kl must be below 10");
  EXPECT_EQ(errorOf("[ppo]\n\nactor_hidden = [2147483647]\n"), "run.toml:3: actor_hidden widths must be in [1, 8192]");
  EXPECT_EQ(errorOf("[ppo]\nnum_epoch = 2147483647\n"), "run.toml:2: num_epoch must be at most 1000");
  EXPECT_EQ(errorOf("[ppo]\nlearning_rate = 2.0\n"),
            "run.toml:2: learning_rate, learning_rate_final, branch_learning_rate and adaptive_lr_max must be below 1");
  EXPECT_EQ(errorOf("[ppo]\nbatch_size = 40960\n"),
            "run.toml:2: buffer_size must be at most 10^7 and batch_size at most buffer_size");
}

TEST(PpoConfig, ToTomlRoundTripsEveryField) {
  PpoConfig c;
  c.betaFinal = 1e-5;
  c.learningRate = 0.000123;
  c.criticHidden = {7};
  c.normalizeObservations = false;
  const std::string text = toToml(c);
  EXPECT_NE(text.find("beta_final = 1e-05"), std::string::npos);
  EXPECT_EQ(toToml(parsePpoConfig(text, "roundtrip.toml")), text);
  EXPECT_EQ(ppoConfigHash(parsePpoConfig(text, "roundtrip.toml")), ppoConfigHash(c));
  EXPECT_NE(ppoConfigHash(c), ppoConfigHash(PpoConfig{}));
}

}  // namespace
}  // namespace ai

namespace ai {
namespace {

TEST(AdaptiveLearningRate, KlAboveTwiceTheTargetDividesByOneAndAHalfAndBelowHalfMultiplies) {
  PpoConfig c;                                                  // desired KL 0.01, bounds [1e-6, 1e-3]
  EXPECT_DOUBLE_EQ(adaptLearningRate(3e-4, 0.03, c), 2e-4);     // 0.03 > 0.02
  EXPECT_DOUBLE_EQ(adaptLearningRate(3e-4, 0.004, c), 4.5e-4);  // 0.004 < 0.005
  EXPECT_DOUBLE_EQ(adaptLearningRate(3e-4, 0.01, c), 3e-4);     // within [0.005, 0.02]: unchanged
  EXPECT_DOUBLE_EQ(adaptLearningRate(3e-4, 0.02, c), 3e-4);     // the band's edges stay
  EXPECT_DOUBLE_EQ(adaptLearningRate(9e-4, 0.0, c), 1e-3);      // clamped above
  EXPECT_DOUBLE_EQ(adaptLearningRate(1.2e-6, 1.0, c), 1e-6);    // clamped below
}

TEST(AdaptiveLearningRate, BoundsAreValidated) {
  PpoConfig c;
  c.adaptiveLrMin = 1e-3;
  c.adaptiveLrMax = 1e-4;
  EXPECT_THROW(validatePpoConfig(c, "test"), engine::Error);
  c = PpoConfig{};
  c.desiredKl = 0;
  EXPECT_THROW(validatePpoConfig(c, "test"), engine::Error);
}

}  // namespace
}  // namespace ai
