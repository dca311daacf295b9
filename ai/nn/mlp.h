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

}  // namespace ai
