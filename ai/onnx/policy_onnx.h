// policy_onnx.h — a skill's policy as an ONNX file: the deterministic actor with its observation
// normalisation baked in (obs -> Sub mean -> Div std -> Clip -> Gemm/act ... Gemm -> action), plus the
// skill metadata (DESIGN.md §3) as metadata_props. Inference is our own Eigen code, no ONNX runtime.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "ai/nn/mlp.h"

namespace ai {

/// Everything that goes into a policy file. obsMean/obsStd have actor.inputSize() entries (std > 0).
struct PolicyExport {
  MlpWeights actor;         ///< deterministic actor: its output is the mean action
  Eigen::VectorXf obsMean;  ///< running-normaliser mean, one per observation entry
  Eigen::VectorXf obsStd;   ///< running-normaliser standard deviation (already including epsilon)
  float obsClip = 5.0f;     ///< normalised observations are clipped to [-obsClip, obsClip]
  std::vector<std::pair<std::string, std::string>> metadata;  ///< key/value strings; keys unique
};

/// Writes the policy as an ONNX model (IR 8, opset 13): input "obs" float [batch, obsDim], output "action"
/// float [batch, actDim]. The model passes onnx::checker before it is written; the write is atomic.
/// Throws engine::Error ("path: what is wrong") on inconsistent input, a checker failure or an I/O error.
void savePolicyOnnx(const std::string& path, const PolicyExport& policy);

/// A policy read back from an ONNX file written by savePolicyOnnx.
struct LoadedPolicy {
  MlpWeights actor;                             ///< actor layers, same layout as in training
  Eigen::VectorXf obsMean;                      ///< normaliser mean
  Eigen::VectorXf obsStd;                       ///< normaliser standard deviation
  float obsClip = 5.0f;                         ///< clip range of normalised observations
  std::map<std::string, std::string> metadata;  ///< the file's metadata_props

  /// Number of observation entries the policy expects.
  int observationSize() const { return actor.inputSize(); }
  /// Number of action entries it produces.
  int actionSize() const { return actor.outputSize(); }
  /// Deterministic action for observations (observationSize x batch, one column per sample);
  /// actions becomes actionSize x batch. Throws std::invalid_argument if obs has the wrong row count.
  void act(const Eigen::MatrixXf& obs, Eigen::MatrixXf* actions) const;
};

/// Reads a policy file. Accepts exactly the graph savePolicyOnnx writes (any layer count and widths,
/// ELU or tanh hidden layers); anything else, including random or truncated bytes, throws engine::Error
/// "path: what is wrong".
LoadedPolicy loadPolicyOnnx(const std::string& path);

/// FNV-1a (64 bit) of the file's bytes: the model hash recorded in replays and shown by `treelearn tree`.
/// Throws engine::Error if the file cannot be read.
uint64_t onnxFileHash(const std::string& path);

/// A name or value read from a model file, made safe to print: at most 48 characters, non-printables as '?'.
std::string printable(const std::string& s);

}  // namespace ai
