// mlp_backward_test.cpp — mlpForwardTrain matches mlpForward, and mlpBackward matches central finite
// differences of a double-precision reference forward on a small 3-4-5-2 net (ELU and tanh).
#include <gtest/gtest.h>

#include <cmath>

#include "ai/nn/mlp.h"

namespace ai {
namespace {

// reference forward in double: loss = sum(c .* f(x))
double referenceLoss(const MlpWeights& w, const Eigen::MatrixXd& x, const Eigen::MatrixXd& c) {
  Eigen::MatrixXd h = x;
  for (int k = 0; k < w.layers(); ++k) {
    Eigen::MatrixXd z = w.W[size_t(k)].cast<double>() * h;
    z.colwise() += w.b[size_t(k)].cast<double>();
    if (k + 1 < w.layers())
      h = w.activation == Activation::Elu ? z.unaryExpr([](double v) { return v > 0 ? v : std::exp(v) - 1.0; })
                                          : Eigen::MatrixXd(z.array().tanh().matrix());
    else
      h = z;
  }
  return (c.array() * h.array()).sum();
}

void checkGradients(Activation activation) {
  MlpWeights w = makeMlp({3, 4, 5, 2}, activation, 11, 1.0f);
  for (auto& b : w.b) b.setRandom();  // non-zero biases so both ELU branches are visited
  Eigen::MatrixXf x = Eigen::MatrixXf::Random(3, 6) * 2.0f;
  Eigen::MatrixXf c = Eigen::MatrixXf::Random(2, 6);

  MlpCache cache;
  Eigen::MatrixXf out, reference;
  mlpForwardTrain(w, x, &cache, &out);
  mlpForward(w, x, &reference);
  EXPECT_TRUE(out == reference);
  MlpWeights grads;
  mlpBackward(w, cache, c, &grads);

  // central differences in double on a double copy of every parameter: (L(p + h) - L(p - h)) / 2h
  const Eigen::MatrixXd xd = x.cast<double>(), cd = c.cast<double>();
  const double h = 1e-3;
  for (int k = 0; k < w.layers(); ++k) {
    for (int which = 0; which < 2; ++which) {
      float* p = which == 0 ? w.W[size_t(k)].data() : w.b[size_t(k)].data();
      const float* g = which == 0 ? grads.W[size_t(k)].data() : grads.b[size_t(k)].data();
      const Eigen::Index n = which == 0 ? w.W[size_t(k)].size() : w.b[size_t(k)].size();
      for (Eigen::Index i = 0; i < n; ++i) {
        const float saved = p[i];
        p[i] = saved + float(h);
        const double up = referenceLoss(w, xd, cd);
        p[i] = saved - float(h);
        const double down = referenceLoss(w, xd, cd);
        p[i] = saved;
        const double numeric = (up - down) / (double(saved + float(h)) - double(saved - float(h)));
        EXPECT_NEAR(g[i], numeric, 2e-3 * std::max(1.0, std::abs(numeric)))
            << "layer " << k << (which ? " b" : " W") << i;
      }
    }
  }
}

TEST(MlpBackward, EluGradientsMatchFiniteDifferences) { checkGradients(Activation::Elu); }
TEST(MlpBackward, TanhGradientsMatchFiniteDifferences) { checkGradients(Activation::Tanh); }

TEST(MlpBackward, GradientsAreSummedOverTheBatch) {
  MlpWeights w = makeMlp({2, 3, 1}, Activation::Elu, 5, 1.0f);
  Eigen::MatrixXf x = Eigen::MatrixXf::Random(2, 4), one(2, 1), out;
  MlpCache cache;
  MlpWeights all, single, sum = zerosLike(w);
  mlpForwardTrain(w, x, &cache, &out);
  mlpBackward(w, cache, Eigen::MatrixXf::Ones(1, 4), &all);
  for (int j = 0; j < 4; ++j) {
    one = x.col(j);
    mlpForwardTrain(w, one, &cache, &out);
    mlpBackward(w, cache, Eigen::MatrixXf::Ones(1, 1), &single);
    for (int k = 0; k < 2; ++k) {
      sum.W[size_t(k)] += single.W[size_t(k)];
      sum.b[size_t(k)] += single.b[size_t(k)];
    }
  }
  for (int k = 0; k < 2; ++k) {
    EXPECT_TRUE(all.W[size_t(k)].isApprox(sum.W[size_t(k)], 1e-5f));
    EXPECT_TRUE(all.b[size_t(k)].isApprox(sum.b[size_t(k)], 1e-5f));
  }
}

}  // namespace
}  // namespace ai
