// mlp.h — a multi-layer perceptron in Eigen (float32) with batched forward and backward passes.
// Activations are column-major: features x batch (one column per sample). Weights are plain data
// (MlpWeights) so the trainer, checkpoints and the ONNX exporter/importer all share one layout.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace ai {

/// Hidden-layer nonlinearity. The output layer is always linear.
enum class Activation { Elu, Tanh };

/// Parameters of an MLP: layer k maps in_k -> out_k as y = W[k] x + b[k]; W[k] is out_k x in_k.
struct MlpWeights {
  std::vector<Eigen::MatrixXf> W;
  std::vector<Eigen::VectorXf> b;
  Activation activation = Activation::Elu;

  int inputSize() const { return W.empty() ? 0 : int(W.front().cols()); }
  int outputSize() const { return W.empty() ? 0 : int(W.back().rows()); }
  int layers() const { return int(W.size()); }
  /// Total number of scalars.
  size_t parameterCount() const;
};

/// Sizes: {input, hidden..., output}. Weights get orthogonal-like scaled random init from a seed
/// (hidden gain sqrt(2), output gain outputGain), biases zero.
MlpWeights makeMlp(const std::vector<int>& sizes, Activation activation, uint64_t seed, float outputGain);

/// Forward pass only (inference): out = f(x), x is input x batch.
void mlpForward(const MlpWeights& w, const Eigen::MatrixXf& x, Eigen::MatrixXf* out);

/// What a training forward pass keeps for the backward pass. Reuse one cache across calls: its
/// matrices keep their storage, so a steady batch size allocates nothing after the first call.
struct MlpCache {
  /// inputs[k] is the input of layer k (inputs[0] = x, inputs[k] = activation of hidden layer k-1).
  std::vector<Eigen::MatrixXf> inputs;
  /// Backward scratch (gradient w.r.t. a layer's pre-activation and its input); not part of the result.
  mutable Eigen::MatrixXf gradA, gradB;
};

/// Training forward pass: out = f(x) as mlpForward, and fills cache for mlpBackward.
void mlpForwardTrain(const MlpWeights& w, const Eigen::MatrixXf& x, MlpCache* cache, Eigen::MatrixXf* out);

/// Backward pass for the cache of the last mlpForwardTrain: dOut = dLoss/dOut (output x batch). Writes
/// dLoss/dW and dLoss/db summed over the batch columns into grads (resized to w's shapes). No gradient
/// w.r.t. the input x is computed.
void mlpBackward(const MlpWeights& w, const MlpCache& cache, const Eigen::MatrixXf& dOut, MlpWeights* grads);

/// Zero-valued tensors with w's shapes and activation (for gradients and optimiser moments).
MlpWeights zerosLike(const MlpWeights& w);

}  // namespace ai
