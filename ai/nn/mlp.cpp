// mlp.cpp — MLP construction, inference and the training forward/backward passes (float32,
// column-major batches).
#include "ai/nn/mlp.h"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <random>

namespace {
// The build enables OpenMP so that the PPO update can thread Eigen's matrix products (ai::Trainer raises the
// thread count around it). Everywhere else products stay on the calling thread: the same numbers whatever the
// machine, and no threads nested inside the rollout workers.
const bool kEigenSingleThreaded = (Eigen::setNbThreads(1), true);
}  // namespace

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

namespace {

// in-place hidden activation; ELU as max(z,0) + (exp(min(z,0)) - 1): branch-free, measured faster than select
void activateInPlace(Activation a, Eigen::MatrixXf* z) {
  auto za = z->array();
  if (a == Activation::Elu)
    za = za.max(0.0f) + (za.min(0.0f).exp() - 1.0f);
  else
    za = za.tanh();
}

// multiplies g by the activation derivative, written in terms of the activation output h:
// ELU: h > 0 -> 1, else exp(z) = h + 1, i.e. min(h,0) + 1; tanh: 1 - h^2
void multiplyActivationDerivative(Activation a, const Eigen::MatrixXf& h, Eigen::MatrixXf* g) {
  if (a == Activation::Elu)
    g->array() *= h.array().min(0.0f) + 1.0f;
  else
    g->array() *= 1.0f - h.array().square();
}

}  // namespace

MlpWeights zerosLike(const MlpWeights& w) {
  MlpWeights z;
  z.activation = w.activation;
  for (int k = 0; k < w.layers(); ++k) {
    z.W.push_back(Eigen::MatrixXf::Zero(w.W[size_t(k)].rows(), w.W[size_t(k)].cols()));
    z.b.push_back(Eigen::VectorXf::Zero(w.b[size_t(k)].size()));
  }
  return z;
}

void mlpForwardTrain(const MlpWeights& w, const Eigen::MatrixXf& x, MlpCache* cache, Eigen::MatrixXf* out) {
  const int layers = w.layers();
  cache->inputs.resize(size_t(std::max(layers, 1)));
  cache->inputs[0] = x;
  for (int k = 0; k < layers; ++k) {
    const size_t ks = size_t(k);
    const bool last = k + 1 == layers;
    Eigen::MatrixXf& z = last ? *out : cache->inputs[ks + 1];
    z.noalias() = w.W[ks] * cache->inputs[ks];
    z.colwise() += w.b[ks];
    if (!last) activateInPlace(w.activation, &z);
  }
}

void mlpBackward(const MlpWeights& w, const MlpCache& cache, const Eigen::MatrixXf& dOut, MlpWeights* grads) {
  const int layers = w.layers();
  grads->activation = w.activation;
  grads->W.resize(size_t(layers));
  grads->b.resize(size_t(layers));

  // g holds dLoss/dz of layer k; it alternates between the two scratch buffers
  const Eigen::MatrixXf* g = &dOut;
  Eigen::MatrixXf* next = &cache.gradA;
  for (int k = layers - 1; k >= 0; --k) {
    const size_t ks = size_t(k);
    grads->W[ks].noalias() = *g * cache.inputs[ks].transpose();
    grads->b[ks].noalias() = g->rowwise().sum();
    if (k == 0) break;

    // back through the weights, then through the activation of hidden layer k-1
    next->noalias() = w.W[ks].transpose() * *g;
    multiplyActivationDerivative(w.activation, cache.inputs[ks], next);
    g = next;
    next = next == &cache.gradA ? &cache.gradB : &cache.gradA;
  }
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
