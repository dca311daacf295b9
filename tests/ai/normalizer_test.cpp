// normalizer_test.cpp — RunningNormalizer: mean and variance of a known set (with the 1e-4 prior count),
// batch-order independence, clipping, frozen normalisation.
#include "ai/nn/normalizer.h"

#include <gtest/gtest.h>

namespace ai {
namespace {

TEST(RunningNormalizer, MeanAndVarianceOfKnownSetIncludePriorCount) {
  RunningNormalizer norm(2);
  Eigen::MatrixXf batch(2, 4);
  batch << 1, 2, 3, 4, 10, 10, 10, 10;
  norm.update(batch);
  // prior (mean 0, var 1, count c = 1e-4) merged with the batch (mean 2.5, var 1.25, count 4):
  // mean = 4*2.5 / 4.0001 = 2.4999375;  var = (c*1 + 4*1.25 + 2.5^2 * c*4/4.0001) / 4.0001 = 5.000725 / 4.0001
  // = 1.2501500
  const double c = 1e-4, total = 4.0 + c;
  EXPECT_NEAR(norm.mean()(0), 10.0 / total, 1e-6);
  EXPECT_NEAR(norm.variance()(0), (c + 5.0 + 6.25 * c * 4.0 / total) / total, 1e-12);
  EXPECT_NEAR(norm.variance()(0), 1.2501500, 1e-6);
  // constant feature: mean 40/4.0001 = 9.99975, var = (c + 0 + 100 * c*4/4.0001) / 4.0001 = 0.0025249
  EXPECT_NEAR(norm.mean()(1), 9.99975, 1e-4);
  EXPECT_NEAR(norm.variance()(1), (c + 100.0 * c * 4.0 / total) / total, 1e-12);
  EXPECT_DOUBLE_EQ(norm.count(), total);
  EXPECT_NEAR(norm.stddev()(0), std::sqrt(1.2501500 + 1e-8), 1e-6);
}

TEST(RunningNormalizer, TwoBatchesEqualOneBatch) {
  RunningNormalizer a(1), b(1);
  Eigen::MatrixXf all(1, 5), first(1, 2), second(1, 3);
  all << 1, 2, 3, 4, 10;
  first << 1, 2;
  second << 3, 4, 10;
  a.update(all);
  b.update(first);
  b.update(second);
  EXPECT_NEAR(a.mean()(0), b.mean()(0), 1e-6);
  EXPECT_NEAR(a.variance()(0), b.variance()(0), 1e-9);
}

TEST(RunningNormalizer, NormalizesAndClipsToFive) {
  RunningNormalizer norm(1);  // prior: mean 0, var 1 -> (x - 0) / sqrt(1 + 1e-8)
  EXPECT_EQ(norm.clip(), 5.0f);
  Eigen::MatrixXf x(1, 3), out;
  x << 2.0f, 7.0f, -9.0f;
  norm.normalize(x, &out);
  EXPECT_NEAR(out(0, 0), 2.0, 1e-6);
  EXPECT_EQ(out(0, 1), 5.0f);
  EXPECT_EQ(out(0, 2), -5.0f);
}

}  // namespace
}  // namespace ai

TEST(RunningNormalizer, BranchAdaptationNeutralisesFeaturesTheParentNeverSawVary) {
  ai::RunningNormalizer n(3);
  Eigen::MatrixXf batch(3, 4);
  batch << 1, 2, 3, 4,  // varies
      0, 0, 0, 0,       // a command slot the parent never used
      5, 5, 5, 5;       // constant but not zero
  for (int i = 0; i < 1000; ++i) n.update(batch);
  EXPECT_GT(n.count(), 3999.0);
  n.adaptForBranch(100.0);
  EXPECT_DOUBLE_EQ(n.count(), 100.0);
  EXPECT_NEAR(n.mean()[0], 2.5, 1e-6);  // kept
  EXPECT_NEAR(n.variance()[0], 1.25, 1e-6);
  EXPECT_EQ(n.mean()[1], 0.0f);  // neutral: values pass at their own scale
  EXPECT_EQ(n.variance()[1], 1.0);
  EXPECT_EQ(n.variance()[2], 1.0);
  Eigen::MatrixXf x(3, 1), out;
  x << 2.5f, 0.7f, 5.0f;
  n.normalize(x, &out);
  EXPECT_NEAR(out(1, 0), 0.7f, 1e-4);  // not 0.7 / 1e-4, clipped to 5
}

TEST(RunningNormalizer, ABatchFoldedFromItsPartsSumsEqualsOneUpdateOnIt) {
  // the data-parallel path: two halves (two ranks) summed about the running mean, folded in once
  ai::RunningNormalizer parts(2), whole(2);
  Eigen::MatrixXf first(2, 4), second(2, 4);
  first << 1, 2, 3, 4, 10, 10, 10, 14;  // feature 0: mean 2.5, variance 1.25; feature 1: mean 11, variance 3
  second << 5, 6, 7, 8, -1, 1, -1, 1;
  for (const Eigen::MatrixXf* batch : {&first, &second}) {
    std::vector<double> left, right;
    parts.batchSums(batch->leftCols(2), &left);
    parts.batchSums(batch->rightCols(2), &right);
    for (size_t k = 0; k < left.size(); ++k) left[k] += right[k];
    EXPECT_EQ(left[0], 4.0);  // the count
    parts.foldSums(left);
    whole.update(*batch);
  }
  EXPECT_NEAR(whole.mean()[0], 4.5, 1e-4);  // 1..8 (the prior's count 1e-4 is all but nothing)
  EXPECT_NEAR(whole.variance()[0], 5.25, 1e-3);
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(parts.mean()[k], whole.mean()[k], 1e-6);
    EXPECT_NEAR(parts.variance()[k], whole.variance()[k], 1e-9);
  }
  EXPECT_DOUBLE_EQ(parts.count(), whole.count());
}
