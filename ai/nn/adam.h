// adam.h — the Adam optimiser (Kingma & Ba, PyTorch's update form) over a list of float tensors, and
// gradient-norm clipping over the same list. Tensors are addressed by (pointer, size) views in a fixed
// order, so an MLP, a second MLP and a log-std vector can share one optimiser.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "ai/nn/mlp.h"

namespace ai {

class ByteWriter;
class ByteReader;

/// A view of one float tensor (not owning). The same list order must be used for parameters and gradients.
struct TensorRef {
  float* data = nullptr;
  Eigen::Index size = 0;
};

/// Appends views of w's tensors in the order W0, b0, W1, b1, ...
void appendTensors(MlpWeights* w, std::vector<TensorRef>* out);
/// Appends a view of a vector.
void appendTensor(Eigen::VectorXf* v, std::vector<TensorRef>* out);

/// sqrt of the sum of squares of every element of every tensor (accumulated in double).
double globalGradNorm(const std::vector<TensorRef>& grads);

/// Scales all gradients by maxNorm / (norm + 1e-6) when their global norm exceeds maxNorm (PyTorch's
/// clip_grad_norm_). Returns the norm before clipping.
double clipGradNorm(const std::vector<TensorRef>& grads, double maxNorm);

/// Adam with per-tensor first and second moments and a shared step count.
class Adam {
 public:
  /// beta1 0.9, beta2 0.999, epsilon 1e-8 (PyTorch defaults).
  explicit Adam(float beta1 = 0.9f, float beta2 = 0.999f, float epsilon = 1e-8f);

  /// One update: m = b1 m + (1-b1) g; v = b2 v + (1-b2) g^2; p -= lr / (1-b1^t) * m / (sqrt(v)/sqrt(1-b2^t) + eps).
  /// Moments are created (zero) on the first call; later calls must pass the same tensor shapes.
  void step(const std::vector<TensorRef>& params, const std::vector<TensorRef>& grads, float learningRate);

  /// Number of steps taken so far.
  int64_t stepCount() const { return steps_; }
  /// Forgets moments and step count (a fresh optimiser).
  void reset();

  /// Appends hyperparameters, step count and moments.
  void save(ByteWriter* out) const;
  /// Reads what save wrote. Throws engine::Error on malformed data.
  void load(ByteReader* in);

 private:
  float beta1_, beta2_, epsilon_;
  int64_t steps_ = 0;
  std::vector<Eigen::VectorXf> m_, v_;
};

}  // namespace ai
