// adam.cpp — Adam and global-norm gradient clipping.
#include "ai/nn/adam.h"

#include <cmath>
#include <stdexcept>

#include "ai/nn/byte_io.h"

namespace ai {

using ArrayMap = Eigen::Map<Eigen::ArrayXf>;

void appendTensors(MlpWeights* w, std::vector<TensorRef>* out) {
  for (int k = 0; k < w->layers(); ++k) {
    out->push_back({w->W[size_t(k)].data(), w->W[size_t(k)].size()});
    out->push_back({w->b[size_t(k)].data(), w->b[size_t(k)].size()});
  }
}

void appendTensor(Eigen::VectorXf* v, std::vector<TensorRef>* out) { out->push_back({v->data(), v->size()}); }

double globalGradNorm(const std::vector<TensorRef>& grads) {
  double sum = 0.0;
  for (const TensorRef& g : grads) sum += ArrayMap(g.data, g.size).cast<double>().square().sum();
  return std::sqrt(sum);
}

double clipGradNorm(const std::vector<TensorRef>& grads, double maxNorm) {
  const double norm = globalGradNorm(grads);
  if (norm > maxNorm) {
    const float scale = float(maxNorm / (norm + 1e-6));
    for (const TensorRef& g : grads) ArrayMap(g.data, g.size) *= scale;
  }
  return norm;
}

Adam::Adam(float beta1, float beta2, float epsilon) : beta1_(beta1), beta2_(beta2), epsilon_(epsilon) {}

void Adam::reset() {
  steps_ = 0;
  m_.clear();
  v_.clear();
}

void Adam::step(const std::vector<TensorRef>& params, const std::vector<TensorRef>& grads, float learningRate) {
  if (params.size() != grads.size()) throw std::invalid_argument("Adam::step: parameter and gradient lists differ");
  if (m_.empty()) {
    for (const TensorRef& p : params) {
      m_.push_back(Eigen::VectorXf::Zero(p.size));
      v_.push_back(Eigen::VectorXf::Zero(p.size));
    }
  }
  if (m_.size() != params.size()) throw std::invalid_argument("Adam::step: tensor count changed");
  ++steps_;

  // bias corrections in double, folded into a step size and a second-moment scale (PyTorch's form)
  const double bc1 = 1.0 - std::pow(double(beta1_), double(steps_));
  const double bc2 = 1.0 - std::pow(double(beta2_), double(steps_));
  const float stepSize = float(double(learningRate) / bc1);
  const float invSqrtBc2 = float(1.0 / std::sqrt(bc2));
  for (size_t i = 0; i < params.size(); ++i) {
    if (params[i].size != grads[i].size || params[i].size != m_[i].size())
      throw std::invalid_argument("Adam::step: tensor " + std::to_string(i) + " changed size");
    ArrayMap p(params[i].data, params[i].size), g(grads[i].data, grads[i].size);
    auto m = m_[i].array();
    auto v = v_[i].array();
    m = beta1_ * m + (1.0f - beta1_) * g;
    v = beta2_ * v + (1.0f - beta2_) * g.square();
    p -= stepSize * m / (v.sqrt() * invSqrtBc2 + epsilon_);
  }
}

void Adam::save(ByteWriter* out) const {
  out->f32(beta1_);
  out->f32(beta2_);
  out->f32(epsilon_);
  out->i64(steps_);
  out->u64(m_.size());
  for (size_t i = 0; i < m_.size(); ++i) {
    out->vector(m_[i]);
    out->vector(v_[i]);
  }
}

void Adam::load(ByteReader* in) {
  beta1_ = in->f32();
  beta2_ = in->f32();
  epsilon_ = in->f32();
  steps_ = in->i64();
  const uint64_t n = in->u64();
  if (n > 4096) in->fail("implausible optimiser tensor count " + std::to_string(n));
  m_.clear();
  v_.clear();
  for (uint64_t i = 0; i < n; ++i) {
    m_.push_back(in->vectorF());
    v_.push_back(in->vectorF());
    if (m_.back().size() != v_.back().size()) in->fail("optimiser moments differ in size");
  }
}

}  // namespace ai
