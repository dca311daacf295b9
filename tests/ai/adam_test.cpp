// adam_test.cpp — Adam's first steps worked by hand (with bias correction every step moves a parameter by
// lr * g / (|g| + eps) while g is constant), zero gradients, and global-norm clipping before/after.
#include "ai/nn/adam.h"

#include <gtest/gtest.h>

namespace ai {
namespace {

TEST(Adam, FirstStepsMoveByLearningRateTimesSignWithBiasCorrection) {
  Eigen::VectorXf p(3), g(3);
  p << 1.0f, -2.0f, 0.5f;
  g << 0.1f, -3.0f, 0.0f;
  std::vector<TensorRef> params, grads;
  appendTensor(&p, &params);
  appendTensor(&g, &grads);
  Adam adam;
  // step 1: m = 0.1 g, v = 0.001 g^2; m_hat = m / (1 - 0.9) = g, v_hat = v / (1 - 0.999) = g^2
  // p -= 0.01 * g / (|g| + 1e-8): 1 - 0.01*0.1/(0.1 + 1e-8) = 0.9900000010, -2 + 0.01 = -1.99, 0.5 unchanged
  adam.step(params, grads, 0.01f);
  EXPECT_NEAR(p(0), 0.990000001, 1e-6);
  EXPECT_NEAR(p(1), -1.99, 1e-6);
  EXPECT_EQ(p(2), 0.5f);
  EXPECT_EQ(adam.stepCount(), 1);
  // step 2, same g: m = 0.9*0.1g + 0.1g = 0.19 g, bias 1 - 0.81 = 0.19 -> m_hat = g; v = 0.001999 g^2,
  // bias 1 - 0.998001 = 0.001999 -> v_hat = g^2: again 0.01 * sign(g)
  adam.step(params, grads, 0.01f);
  EXPECT_NEAR(p(0), 0.98, 1e-6);
  EXPECT_NEAR(p(1), -1.98, 1e-6);
  EXPECT_EQ(p(2), 0.5f);
}

TEST(Adam, MlpTensorsAreListedWeightThenBiasPerLayer) {
  MlpWeights w = makeMlp({3, 4, 2}, Activation::Elu, 1, 1.0f);
  std::vector<TensorRef> refs;
  appendTensors(&w, &refs);
  ASSERT_EQ(refs.size(), 4u);
  EXPECT_EQ(refs[0].size, 12);  // W0: 4 x 3
  EXPECT_EQ(refs[1].size, 4);   // b0
  EXPECT_EQ(refs[2].size, 8);   // W1: 2 x 4
  EXPECT_EQ(refs[3].data, w.b[1].data());
}

TEST(GradClip, ScalesToMaxNormAndReportsNormBefore) {
  // norm = sqrt(3^2 + 4^2 + 12^2) = sqrt(169) = 13
  Eigen::VectorXf a = Eigen::Vector2f(3.0f, 4.0f), b = Eigen::VectorXf::Constant(1, 12.0f);
  std::vector<TensorRef> grads;
  appendTensor(&a, &grads);
  appendTensor(&b, &grads);
  EXPECT_DOUBLE_EQ(globalGradNorm(grads), 13.0);
  // above the limit: scale 6.5 / (13 + 1e-6) -> (1.5, 2, 6), new norm 6.5
  EXPECT_DOUBLE_EQ(clipGradNorm(grads, 6.5), 13.0);
  EXPECT_NEAR(a(0), 1.5, 1e-6);
  EXPECT_NEAR(a(1), 2.0, 1e-6);
  EXPECT_NEAR(b(0), 6.0, 1e-6);
  EXPECT_NEAR(globalGradNorm(grads), 6.5, 1e-5);
  // below the limit: untouched
  EXPECT_NEAR(clipGradNorm(grads, 20.0), 6.5, 1e-5);
  EXPECT_NEAR(b(0), 6.0, 1e-6);
}

}  // namespace
}  // namespace ai
