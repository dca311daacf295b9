// onnx_test.cpp — policy files: the loaded network computes what training computed, the file passes the
// ONNX checker, metadata survives, and bad bytes or failed writes never crash or leave files behind.
#include <gtest/gtest.h>
#include <stdlib.h>

#include "ai/onnx/policy_onnx.h"

// treelearn_tests links libonnx through tl_ai but does not inherit its compile definitions
#ifndef ONNX_NAMESPACE
#define ONNX_NAMESPACE onnx
#endif
#ifndef ONNX_ML
#define ONNX_ML 1
#endif
#include <onnx/checker.h>
#include <onnx/onnx_pb.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"

namespace ai {
namespace {

namespace fs = std::filesystem;

// a fresh empty folder under the system temp dir, removed at scope exit
struct TempDir {
  fs::path path;
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "treelearn_onnx_XXXXXX").string();
    path = ::mkdtemp(pattern.data());
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
};

Eigen::MatrixXf uniform(int rows, int cols, float lo, float hi, std::mt19937* rng) {
  std::uniform_real_distribution<float> u(lo, hi);
  Eigen::MatrixXf m(rows, cols);
  for (int i = 0; i < m.size(); ++i) m.data()[i] = u(*rng);
  return m;
}

// a random policy; biases are random too (makeMlp leaves them zero) so the bias path is tested
PolicyExport randomPolicy(const std::vector<int>& sizes, Activation activation, uint32_t seed) {
  std::mt19937 rng(seed);
  PolicyExport p;
  p.actor = makeMlp(sizes, activation, seed, 0.5f);
  for (auto& b : p.actor.b) b = uniform(int(b.size()), 1, -0.3f, 0.3f, &rng);
  p.obsMean = uniform(sizes.front(), 1, -2.0f, 2.0f, &rng);
  p.obsStd = uniform(sizes.front(), 1, 0.1f, 3.0f, &rng);
  p.obsClip = 5.0f;
  return p;
}

// what training computes: normalise, clip, then the MLP
Eigen::MatrixXf referenceActions(const PolicyExport& p, const Eigen::MatrixXf& obs) {
  Eigen::MatrixXf x = ((obs.colwise() - p.obsMean).array().colwise() / p.obsStd.array()).matrix();
  x = x.cwiseMax(-p.obsClip).cwiseMin(p.obsClip);
  Eigen::MatrixXf out;
  mlpForward(p.actor, x, &out);
  return out;
}

void expectSameNetwork(const PolicyExport& p, const LoadedPolicy& loaded, uint32_t seed) {
  ASSERT_EQ(loaded.observationSize(), p.actor.inputSize());
  ASSERT_EQ(loaded.actionSize(), p.actor.outputSize());
  EXPECT_EQ(loaded.actor.activation, p.actor.activation);
  EXPECT_EQ(loaded.obsClip, p.obsClip);
  std::mt19937 rng(seed);
  // obs within mean +- 60 std units: most entries normalise beyond the clip range of 5
  Eigen::MatrixXf obs = uniform(loaded.observationSize(), 256, -60.0f, 60.0f, &rng);
  obs.leftCols(128) = uniform(loaded.observationSize(), 128, -3.0f, 3.0f, &rng);
  Eigen::MatrixXf actions;
  loaded.act(obs, &actions);
  const Eigen::MatrixXf expected = referenceActions(p, obs);
  ASSERT_EQ(actions.rows(), expected.rows());
  ASSERT_EQ(actions.cols(), 256);
  EXPECT_LE((actions - expected).cwiseAbs().maxCoeff(), 1e-5f);
  EXPECT_GT(expected.cwiseAbs().maxCoeff(), 1e-2f);  // the comparison is not between two zero matrices
}

TEST(Onnx, LoadedModelMatchesTrainingNetwork) {
  TempDir dir;
  const PolicyExport p = randomPolicy({90, 512, 512, 512, 23}, Activation::Elu, 7);
  savePolicyOnnx(dir.file("walk.onnx"), p);
  const LoadedPolicy loaded = loadPolicyOnnx(dir.file("walk.onnx"));
  expectSameNetwork(p, loaded, 11);
  for (int k = 0; k < p.actor.layers(); ++k) {
    EXPECT_EQ(loaded.actor.W[size_t(k)], p.actor.W[size_t(k)]) << "layer " << k;
    EXPECT_EQ(loaded.actor.b[size_t(k)], p.actor.b[size_t(k)]) << "layer " << k;
  }
  EXPECT_EQ(loaded.obsMean, p.obsMean);
  EXPECT_EQ(loaded.obsStd, p.obsStd);
  EXPECT_EQ(onnxFileHash(dir.file("walk.onnx")), engine::hashBytes(engine::readFile(dir.file("walk.onnx"))));
}

TEST(Onnx, FilePassesTheOnnxChecker) {
  TempDir dir;
  const PolicyExport p = randomPolicy({12, 16, 16, 4}, Activation::Elu, 3);
  savePolicyOnnx(dir.file("p.onnx"), p);
  onnx::ModelProto model;
  ASSERT_TRUE(model.ParseFromString(engine::readFile(dir.file("p.onnx"))));
  EXPECT_NO_THROW(onnx::checker::check_model(model));
  EXPECT_EQ(model.ir_version(), 8);
  EXPECT_EQ(model.producer_name(), "treelearn");
  ASSERT_EQ(model.opset_import_size(), 1);
  EXPECT_EQ(model.opset_import(0).domain(), "");
  EXPECT_EQ(model.opset_import(0).version(), 13);
  // the graph a standard runtime would execute
  std::vector<std::string> ops;
  for (const auto& n : model.graph().node()) ops.push_back(n.op_type());
  EXPECT_EQ(ops, (std::vector<std::string>{"Sub", "Div", "Clip", "Gemm", "Elu", "Gemm", "Elu", "Gemm"}));
  const auto& in = model.graph().input(0).type().tensor_type();
  EXPECT_EQ(model.graph().input(0).name(), "obs");
  EXPECT_EQ(in.shape().dim(0).dim_param(), "batch");
  EXPECT_EQ(in.shape().dim(1).dim_value(), 12);
  const auto& out = model.graph().output(0).type().tensor_type();
  EXPECT_EQ(model.graph().output(0).name(), "action");
  EXPECT_EQ(out.shape().dim(0).dim_param(), "batch");
  EXPECT_EQ(out.shape().dim(1).dim_value(), 4);
}

TEST(Onnx, MetadataRoundTrips) {
  TempDir dir;
  PolicyExport p = randomPolicy({6, 8, 3}, Activation::Elu, 5);
  p.metadata = {{"skill", "walk"},
                {"joint_order", "left_hip_pitch,left_hip_roll,left_hip_yaw"},
                {"control_dt", "0.01"},
                {"empty", ""},
                {"unicode", "\xe8\xb5\xb0 \xe8\xb7\xaf"}};
  savePolicyOnnx(dir.file("m.onnx"), p);
  const LoadedPolicy loaded = loadPolicyOnnx(dir.file("m.onnx"));
  ASSERT_EQ(loaded.metadata.size(), p.metadata.size());
  for (const auto& kv : p.metadata) EXPECT_EQ(loaded.metadata.at(kv.first), kv.second) << kv.first;

  p.metadata.push_back({"skill", "run"});
  EXPECT_THROW(savePolicyOnnx(dir.file("dup.onnx"), p), engine::Error);
  EXPECT_FALSE(fs::exists(dir.file("dup.onnx")));
}

TEST(Onnx, TanhNetworkRoundTrips) {
  TempDir dir;
  const PolicyExport p = randomPolicy({20, 32, 24, 5}, Activation::Tanh, 9);
  savePolicyOnnx(dir.file("t.onnx"), p);
  const LoadedPolicy loaded = loadPolicyOnnx(dir.file("t.onnx"));
  EXPECT_EQ(loaded.actor.activation, Activation::Tanh);
  expectSameNetwork(p, loaded, 13);

  // a single linear layer has no activation node at all
  const PolicyExport linear = randomPolicy({7, 2}, Activation::Elu, 10);
  savePolicyOnnx(dir.file("l.onnx"), linear);
  expectSameNetwork(linear, loadPolicyOnnx(dir.file("l.onnx")), 14);
}

// loading must throw engine::Error naming the file; any other outcome (success, other exception, crash) fails
void expectRejected(const std::string& path, const std::string& label) {
  try {
    loadPolicyOnnx(path);
    ADD_FAILURE() << label << ": accepted";
  } catch (const engine::Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << label << ": " << e.what();
  }
}

TEST(Onnx, RandomBytesAndTruncatedFilesAreRejected) {
  TempDir dir;
  const std::string bad = dir.file("bad.onnx");
  std::mt19937 rng(1234);
  for (int i = 0; i < 200; ++i) {
    std::string bytes(size_t(rng() % 4096), '\0');
    for (char& c : bytes) c = char(rng() & 0xff);
    engine::writeFileAtomic(bad, bytes);
    expectRejected(bad, "random buffer " + std::to_string(i));
  }

  PolicyExport p = randomPolicy({10, 16, 4}, Activation::Elu, 21);
  p.metadata = {{"skill", "walk"}};
  savePolicyOnnx(dir.file("good.onnx"), p);
  const std::string good = engine::readFile(dir.file("good.onnx"));
  ASSERT_NO_THROW(loadPolicyOnnx(dir.file("good.onnx")));
  int count = 0;
  for (size_t n = 0; n < good.size(); n += 97, ++count) {
    engine::writeFileAtomic(bad, std::string_view(good).substr(0, n));
    expectRejected(bad, "truncated to " + std::to_string(n) + " bytes");
  }
  EXPECT_GT(count, 10);

  // a valid model that is not a policy: the graph has the wrong activation in one layer
  onnx::ModelProto model;
  const PolicyExport deep = randomPolicy({10, 16, 16, 4}, Activation::Elu, 22);
  savePolicyOnnx(dir.file("deep.onnx"), deep);
  ASSERT_TRUE(model.ParseFromString(engine::readFile(dir.file("deep.onnx"))));
  model.mutable_graph()->mutable_node(6)->set_op_type("Tanh");
  model.mutable_graph()->mutable_node(6)->clear_attribute();
  std::string bytes;
  ASSERT_TRUE(model.SerializeToString(&bytes));
  engine::writeFileAtomic(bad, bytes);
  expectRejected(bad, "mixed activations");

  // a weight of the wrong shape
  ASSERT_TRUE(model.ParseFromString(engine::readFile(dir.file("deep.onnx"))));
  for (auto& t : *model.mutable_graph()->mutable_initializer())
    if (t.name() == "w1") t.set_dims(1, 15), t.mutable_raw_data()->resize(16 * 15 * 4);
  ASSERT_TRUE(model.SerializeToString(&bytes));
  engine::writeFileAtomic(bad, bytes);
  try {
    loadPolicyOnnx(bad);
    ADD_FAILURE() << "wrong weight shape accepted";
  } catch (const engine::Error& e) {
    EXPECT_NE(std::string(e.what()).find("node 5 (Gemm) weight 'w1' has shape [16,15], expected [*,16]"),
              std::string::npos)
        << e.what();
  }
}

TEST(Onnx, BytesAppendedToAModelAreRefused) {
  TempDir dir;
  savePolicyOnnx(dir.file("good.onnx"), randomPolicy({10, 16, 4}, Activation::Elu, 23));
  const std::string good = engine::readFile(dir.file("good.onnx"));
  // 'x' is 0x78: the tag of field 15 as a varint, so a tail of x's parses as 512 unknown fields, not as an error
  engine::writeFileAtomic(dir.file("tail.onnx"), good + std::string(1024, 'x'));
  try {
    loadPolicyOnnx(dir.file("tail.onnx"));
    ADD_FAILURE() << "a model with 1 KiB appended loaded";
  } catch (const engine::Error& e) {
    EXPECT_NE(std::string(e.what()).find("tail.onnx: holds data that is no part of an ONNX model"), std::string::npos)
        << e.what();
  }
}

TEST(Onnx, FailedSaveLeavesNoFile) {
  TempDir dir;
  const PolicyExport p = randomPolicy({6, 8, 3}, Activation::Elu, 5);
  // the parent folder does not exist
  const std::string missing = dir.file("no_such_folder/p.onnx");
  EXPECT_THROW(savePolicyOnnx(missing, p), engine::Error);
  EXPECT_FALSE(fs::exists(missing));
  // the path is an existing folder: the rename fails, the folder stays, no temp file is left
  fs::create_directory(dir.file("folder.onnx"));
  EXPECT_THROW(savePolicyOnnx(dir.file("folder.onnx"), p), engine::Error);
  EXPECT_TRUE(fs::is_directory(dir.file("folder.onnx")));
  // an inconsistent export is refused before anything is written
  PolicyExport broken = p;
  broken.obsStd[2] = 0.0f;
  EXPECT_THROW(savePolicyOnnx(dir.file("broken.onnx"), broken), engine::Error);
  EXPECT_FALSE(fs::exists(dir.file("broken.onnx")));
  size_t entries = 0;
  for (const auto& entry : fs::directory_iterator(dir.path)) entries += entry.path().filename() != "folder.onnx";
  EXPECT_EQ(entries, 0u);
}

}  // namespace
}  // namespace ai
