// mlp.cpp — MLP construction and inference (float32, column-major batches).
#include "ai/nn/mlp.h"

#include <Eigen/QR>
#include <cmath>
#include <random>

namespace ai {

size_t MlpWeights::parameterCount() const {
  size_t n = 0;
  for (size_t k = 0; k < W.size(); ++k) n += size_t(W[k].size() + b[k].size());
  return n;
}

MlpWeights makeMlp(const std::vector<int>& sizes, Activation activation, uint64_t seed, float outputGain) {
  MlpWeights w;
  w.activation = activation;
  std::mt19937_64 rng(seed);
  for (size_t k = 0; k + 1 < sizes.size(); ++k) {
    const int in = sizes[k], out = sizes[k + 1];
    // orthogonal initialisation (as in rsl_rl / cleanrl): QR of a Gaussian matrix, scaled by the gain
    Eigen::MatrixXd g(std::max(in, out), std::min(in, out));
    for (int i = 0; i < g.size(); ++i) {
      // Box-Muller from 53-bit uniforms: portable across standard libraries
      const double u1 = (double(rng() >> 11) + 1.0) * (1.0 / 9007199254740993.0);
      const double u2 = double(rng() >> 11) * (1.0 / 9007199254740992.0);
      g.data()[i] = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
    }
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(g);
    Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(g.rows(), g.cols());
    const Eigen::VectorXd d = qr.matrixQR().diagonal();
    for (int c = 0; c < q.cols(); ++c)
      if (d[c] < 0) q.col(c) *= -1.0;
    const bool last = k + 2 == sizes.size();
    const double gain = last ? double(outputGain) : std::sqrt(2.0);
    Eigen::MatrixXd m = out >= in ? q : Eigen::MatrixXd(q.transpose());
    w.W.push_back((gain * m).cast<float>());
    w.b.push_back(Eigen::VectorXf::Zero(out));
  }
  return w;
}

void mlpForward(const MlpWeights& w, const Eigen::MatrixXf& x, Eigen::MatrixXf* out) {
  Eigen::MatrixXf h = x, z;
  for (int k = 0; k < w.layers(); ++k) {
    z.noalias() = w.W[size_t(k)] * h;
    z.colwise() += w.b[size_t(k)];
    if (k + 1 < w.layers()) {
      if (w.activation == Activation::Elu)
        h = z.cwiseMax(0.0f) + (z.cwiseMin(0.0f).array().exp() - 1.0f).matrix();
      else
        h = z.array().tanh().matrix();
    } else {
      h.swap(z);
    }
  }
  *out = std::move(h);
}

}  // namespace ai
