// gaussian_test.cpp — diagonal Gaussian log-probability and entropy for a 2-D case worked by hand, and the
// portable Box-Muller sampler (moments, determinism, draw count).
#include "ai/ppo/gaussian.h"

#include <gtest/gtest.h>

namespace ai {
namespace {

TEST(Gaussian, LogProbOfTwoDimensionalCaseMatchesHandValue) {
  // mean (0, 1), log-std (0, ln 2) -> std (1, 2); action (1, 0) -> z = (1, -0.5), sum z^2 = 1.25
  // log p = -0.5*1.25 - (0 + ln 2) - 0.5*2*ln(2 pi) = -0.625 - 0.693147 - 1.837877 = -3.156024
  Eigen::MatrixXf actions(2, 2), mean(2, 2);
  actions << 1.0f, 0.0f, 0.0f, 1.0f;  // column 1: the action equals the mean
  mean << 0.0f, 0.0f, 1.0f, 1.0f;
  const Eigen::VectorXf logStd = Eigen::Vector2f(0.0f, std::log(2.0f));
  const Eigen::VectorXf lp = gaussianLogProb(actions, mean, logStd);
  ASSERT_EQ(lp.size(), 2);
  EXPECT_NEAR(lp(0), -3.156024, 1e-5);
  // column 1: z = 0 -> log p = -0.693147 - 1.837877 = -2.531024
  EXPECT_NEAR(lp(1), -2.531024, 1e-5);
}

TEST(Gaussian, EntropyOfTwoDimensionalCaseMatchesHandValue) {
  // H = sum_j (0.5 + 0.5 ln(2 pi) + log std_j) = 2*(0.5 + 0.918939) + (0 + ln 2) = 2.837877 + 0.693147 = 3.531024
  const Eigen::VectorXf logStd = Eigen::Vector2f(0.0f, std::log(2.0f));
  EXPECT_NEAR(gaussianEntropy(logStd), 3.531024, 1e-6);
}

TEST(Gaussian, BoxMullerSamplesHaveUnitMomentsAndAreSeeded) {
  std::mt19937_64 a(42), b(42);
  Eigen::MatrixXf x(1, 200001), y(1, 200001);
  fillStandardNormal(&a, &x);
  fillStandardNormal(&b, &y);
  EXPECT_TRUE(x == y);
  // standard error of the mean over 2e5 samples: 1/sqrt(2e5) = 0.0022
  EXPECT_NEAR(x.mean(), 0.0, 0.01);
  EXPECT_NEAR((x.array() - x.mean()).square().mean(), 1.0, 0.01);
  // an odd count consumes a whole pair for the last element: 2 * 100001 draws
  std::mt19937_64 c(42);
  c.discard(2 * 100001);
  EXPECT_EQ(a(), c());
}

TEST(Gaussian, SampleIsMeanPlusStdTimesNoise) {
  std::mt19937_64 a(7), b(7);
  Eigen::MatrixXf mean(2, 3), noise(2, 3), actions;
  mean << 1, 2, 3, 4, 5, 6;
  const Eigen::VectorXf logStd = Eigen::Vector2f(0.0f, std::log(0.5f));
  sampleGaussian(&a, mean, logStd, &actions);
  fillStandardNormal(&b, &noise);
  EXPECT_NEAR(actions(0, 1), 2.0f + noise(0, 1), 1e-6);
  EXPECT_NEAR(actions(1, 2), 6.0f + 0.5f * noise(1, 2), 1e-6);
}

}  // namespace
}  // namespace ai
