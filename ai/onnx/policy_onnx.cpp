// policy_onnx.cpp — ONNX export and import of a policy (protobuf schema from libonnx, checker from onnx).
// The importer walks the graph node by node and accepts only the exporter's own structure, so every
// accepted file means exactly what LoadedPolicy::act computes.
#include "ai/onnx/policy_onnx.h"

#include <onnx/checker.h>
#include <onnx/onnx_pb.h>

#include <cmath>
#include <cstring>
#include <set>
#include <stdexcept>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"

namespace ai {
std::string printable(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size() && i < 48; ++i) out += (s[i] >= 32 && s[i] < 127) ? s[i] : '?';
  if (s.size() > 48) out += "...";
  return out;
}

namespace {

constexpr int64_t kIrVersion = 8;
constexpr int64_t kOpsetVersion = 13;
const char* const kInputName = "obs";
const char* const kOutputName = "action";

[[noreturn]] void fail(const std::string& path, const std::string& message) {
  throw engine::Error(engine::located(path, 0, message));
}

std::string firstLine(const std::string& s) { return printable(s.substr(0, s.find('\n'))); }

// [2,3] with -1 printed as '*' (any size)
std::string shapeString(const std::vector<int64_t>& dims) {
  std::string out = "[";
  for (size_t i = 0; i < dims.size(); ++i) {
    if (i) out += ',';
    out += dims[i] < 0 ? std::string("*") : std::to_string(dims[i]);
  }
  return out + "]";
}

// ---- export ------------------------------------------------------------------------------------------

void appendLittleEndian(std::string* out, float v) {
  uint32_t u;
  std::memcpy(&u, &v, 4);
  for (int i = 0; i < 4; ++i) out->push_back(char((u >> (8 * i)) & 0xffu));
}

// adds a float initializer; values are given in row-major order by get(i)
template <typename Get>
void addInitializer(onnx::GraphProto* g, const std::string& name, const std::vector<int64_t>& dims, int64_t count,
                    Get get) {
  onnx::TensorProto* t = g->add_initializer();
  t->set_name(name);
  t->set_data_type(onnx::TensorProto::FLOAT);
  for (int64_t d : dims) t->add_dims(d);
  std::string raw;
  raw.reserve(size_t(count) * 4);
  for (int64_t i = 0; i < count; ++i) appendLittleEndian(&raw, get(i));
  t->set_raw_data(std::move(raw));
}

onnx::NodeProto* addNode(onnx::GraphProto* g, const std::string& op, const std::string& name,
                         const std::vector<std::string>& inputs, const std::string& output) {
  onnx::NodeProto* n = g->add_node();
  n->set_op_type(op);
  n->set_name(name);
  for (const std::string& in : inputs) n->add_input(in);
  n->add_output(output);
  return n;
}

void setTensorType(onnx::ValueInfoProto* v, const std::string& name, int64_t features) {
  v->set_name(name);
  onnx::TypeProto_Tensor* tt = v->mutable_type()->mutable_tensor_type();
  tt->set_elem_type(onnx::TensorProto::FLOAT);
  tt->mutable_shape()->add_dim()->set_dim_param("batch");
  tt->mutable_shape()->add_dim()->set_dim_value(features);
}

bool allFinite(const Eigen::MatrixXf& m) { return m.allFinite(); }

void validateExport(const std::string& path, const PolicyExport& p) {
  auto bad = [&](const std::string& what) { fail(path, "cannot export: " + what); };
  const MlpWeights& a = p.actor;
  if (a.W.empty()) bad("the actor has no layers");
  if (a.W.size() != a.b.size())
    bad("the actor has " + std::to_string(a.W.size()) + " weight matrices but " + std::to_string(a.b.size()) +
        " bias vectors");
  for (size_t k = 0; k < a.W.size(); ++k) {
    const std::string layer = "layer " + std::to_string(k);
    if (a.W[k].rows() == 0 || a.W[k].cols() == 0) bad(layer + " has an empty weight matrix");
    if (a.b[k].size() != a.W[k].rows())
      bad(layer + " bias has " + std::to_string(a.b[k].size()) + " entries, expected " + std::to_string(a.W[k].rows()));
    if (k > 0 && a.W[k].cols() != a.W[k - 1].rows())
      bad(layer + " takes " + std::to_string(a.W[k].cols()) + " inputs but layer " + std::to_string(k - 1) +
          " produces " + std::to_string(a.W[k - 1].rows()));
    if (!allFinite(a.W[k]) || !allFinite(a.b[k])) bad(layer + " contains NaN or Inf");
  }
  const int n = a.inputSize();
  if (p.obsMean.size() != n || p.obsStd.size() != n)
    bad("normaliser has " + std::to_string(p.obsMean.size()) + " means and " + std::to_string(p.obsStd.size()) +
        " standard deviations, expected " + std::to_string(n));
  if (!p.obsMean.allFinite()) bad("normaliser mean contains NaN or Inf");
  if (!p.obsStd.allFinite() || !(p.obsStd.array() > 0.0f).all())
    bad("normaliser standard deviations must be finite and > 0");
  if (!std::isfinite(p.obsClip) || !(p.obsClip > 0.0f)) bad("observation clip must be finite and > 0");
  std::set<std::string> keys;
  for (const auto& kv : p.metadata) {
    if (kv.first.empty()) bad("empty metadata key");
    if (!keys.insert(kv.first).second) bad("metadata key '" + kv.first + "' appears twice");
  }
}

// onnx::checker on a model; any complaint becomes engine::Error naming the file
void runChecker(const std::string& path, const onnx::ModelProto& model) {
  try {
    onnx::checker::check_model(model);
  } catch (const onnx::checker::ValidationError& e) {
    fail(path, std::string("fails the ONNX checker: ") + firstLine(e.what()));
  } catch (const std::exception& e) {
    fail(path, std::string("fails the ONNX checker: ") + firstLine(e.what()));
  }
}

// ---- import ------------------------------------------------------------------------------------------

float readLittleEndian(const char* p) {
  uint32_t u = 0;
  for (int i = 0; i < 4; ++i) u |= uint32_t(uint8_t(p[i])) << (8 * i);
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

struct Tensor {
  std::vector<int64_t> dims;
  std::vector<float> values;  // row-major
};

// Walks a parsed graph. Every message starts "path: ".
class GraphReader {
 public:
  GraphReader(const std::string& path, const onnx::GraphProto& g) : path_(path), g_(g) {}

  [[noreturn]] void fail(const std::string& message) const { ai::fail(path_, message); }

  void read(LoadedPolicy* out) {
    indexInitializers();
    const int64_t obsDim = ioFeatures(g_.input(), "input", kInputName);
    const int64_t actDim = ioFeatures(g_.output(), "output", kOutputName);
    defined_.insert(kInputName);
    current_ = kInputName;

    // normalisation: Sub(obs, mean) -> Div(., std) -> Clip(., min, max)
    const onnx::NodeProto& sub = node("Sub", 2);
    noAttributes(sub);
    Tensor mean = initializer(sub.input(1), {obsDim}, "mean");
    advance(sub);

    const onnx::NodeProto& div = node("Div", 2);
    noAttributes(div);
    Tensor stdev = initializer(div.input(1), {obsDim}, "standard deviation");
    for (size_t i = 0; i < stdev.values.size(); ++i)
      if (!(stdev.values[i] > 0.0f))
        fail(where() + " standard deviation '" + printable(div.input(1)) + "' has a non-positive entry at index " +
             std::to_string(i));
    advance(div);

    const onnx::NodeProto& clip = node("Clip", 3);
    noAttributes(clip);
    const float lo = initializer(clip.input(1), {}, "min").values[0];
    const float hi = initializer(clip.input(2), {}, "max").values[0];
    if (!(hi > 0.0f) || lo != -hi)
      fail(where() + " clips to [" + std::to_string(lo) + ", " + std::to_string(hi) + "], expected [-c, c] with c > 0");
    advance(clip);

    out->obsMean = Eigen::Map<const Eigen::VectorXf>(mean.values.data(), Eigen::Index(obsDim));
    out->obsStd = Eigen::Map<const Eigen::VectorXf>(stdev.values.data(), Eigen::Index(obsDim));
    out->obsClip = hi;

    // layers: Gemm, then Elu|Tanh before every Gemm but the last; the last Gemm writes "action"
    MlpWeights& actor = out->actor;
    actor = MlpWeights();
    std::string activationNode;  // "node k (Elu)" of the first activation, for consistency messages
    int64_t width = obsDim;
    for (;;) {
      const onnx::NodeProto& gemm = node("Gemm", 3);
      gemmAttributes(gemm);
      const bool last = gemm.output(0) == kOutputName;
      Tensor w = initializer(gemm.input(1), {last ? actDim : -1, width}, "weight");
      const int64_t rows = w.dims[0];
      Tensor b = initializer(gemm.input(2), {rows}, "bias");
      Eigen::MatrixXf wm(rows, width);
      for (int64_t r = 0; r < rows; ++r)
        for (int64_t c = 0; c < width; ++c) wm(r, c) = w.values[size_t(r * width + c)];
      actor.W.push_back(std::move(wm));
      actor.b.push_back(Eigen::Map<const Eigen::VectorXf>(b.values.data(), Eigen::Index(rows)));
      advance(gemm);
      width = rows;
      if (last) break;

      if (k_ >= g_.node_size()) fail("graph ends after node " + std::to_string(k_ - 1) + " without producing 'action'");
      const onnx::NodeProto& act = g_.node(k_);
      Activation a;
      if (act.op_type() == "Elu")
        a = Activation::Elu;
      else if (act.op_type() == "Tanh")
        a = Activation::Tanh;
      else
        fail("node " + std::to_string(k_) + " is " + printable(act.op_type()) + ", expected Elu or Tanh");
      node(act.op_type().c_str(), 1);
      if (a == Activation::Elu)
        eluAttributes(act);
      else
        noAttributes(act);
      if (activationNode.empty()) {
        actor.activation = a;
        activationNode = where();
      } else if (a != actor.activation) {
        fail(where() + " differs from " + activationNode + ": all hidden layers must use one activation");
      }
      advance(act);
    }
    if (k_ != g_.node_size())
      fail("node " + std::to_string(k_) + " (" + printable(g_.node(k_).op_type()) +
           ") follows the final Gemm that writes 'action'");
    for (const auto& kv : initializers_)
      if (!used_.count(kv.first)) fail("initializer '" + printable(kv.first) + "' is not used by any node");
  }

 private:
  void indexInitializers() {
    if (g_.sparse_initializer_size() > 0) fail("graph has sparse initializers");
    for (const onnx::TensorProto& t : g_.initializer()) {
      if (t.name() == kInputName) fail("an initializer is named 'obs', like the graph input");
      if (!initializers_.emplace(t.name(), &t).second) fail("two initializers are named '" + printable(t.name()) + "'");
    }
  }

  // the feature count of the graph's only input or output, a float tensor [batch, n]
  int64_t ioFeatures(const google::protobuf::RepeatedPtrField<onnx::ValueInfoProto>& list, const char* role,
                     const char* name) const {
    if (list.size() != 1)
      fail("graph has " + std::to_string(list.size()) + " " + role + "s, expected 1 ('" + name + "')");
    const onnx::ValueInfoProto& v = list.Get(0);
    const std::string what = std::string("graph ") + role + " '" + printable(v.name()) + "'";
    if (v.name() != name) fail(what + " should be named '" + name + "'");
    if (!v.has_type() || !v.type().has_tensor_type()) fail(what + " is not a tensor");
    const onnx::TypeProto_Tensor& tt = v.type().tensor_type();
    if (tt.elem_type() != onnx::TensorProto::FLOAT)
      fail(what + " has element type " + std::to_string(tt.elem_type()) + ", expected FLOAT (1)");
    if (!tt.has_shape() || tt.shape().dim_size() != 2) fail(what + " is not a 2-D tensor [batch, features]");
    const auto& batch = tt.shape().dim(0);
    const auto& features = tt.shape().dim(1);
    if (!batch.has_dim_param() || batch.dim_param().empty())
      fail(what + " has a fixed batch size, expected a symbolic one");
    if (!features.has_dim_value() || features.dim_value() <= 0 || features.dim_value() > (int64_t(1) << 24))
      fail(what + " has no valid feature count in dimension 1");
    return features.dim_value();
  }

  std::string where() const {
    return "node " + std::to_string(k_) + " (" + printable(k_ < g_.node_size() ? g_.node(k_).op_type() : "") + ")";
  }

  // the node at k_, checked to be `op` reading the current value plus nInputs - 1 more, writing one output
  const onnx::NodeProto& node(const char* op, int nInputs) const {
    if (k_ >= g_.node_size()) fail("graph ends after node " + std::to_string(k_ - 1) + "; expected a " + op + " node");
    const onnx::NodeProto& n = g_.node(k_);
    if (n.op_type() != op) fail("node " + std::to_string(k_) + " is " + printable(n.op_type()) + ", expected " + op);
    if (!n.domain().empty() && n.domain() != "ai.onnx")
      fail(where() + " is in domain '" + printable(n.domain()) + "', expected the default domain");
    if (n.input_size() != nInputs)
      fail(where() + " has " + std::to_string(n.input_size()) + " inputs, expected " + std::to_string(nInputs));
    if (n.output_size() != 1) fail(where() + " has " + std::to_string(n.output_size()) + " outputs, expected 1");
    if (n.input(0) != current_)
      fail(where() + " reads '" + printable(n.input(0)) + "', expected '" + printable(current_) + "'");
    return n;
  }

  void advance(const onnx::NodeProto& n) {
    const std::string& out = n.output(0);
    if (out.empty() || initializers_.count(out) || !defined_.insert(out).second)
      fail(where() + " writes '" + printable(out) + "', a name that is empty or already defined");
    current_ = out;
    ++k_;
  }

  void noAttributes(const onnx::NodeProto& n) const {
    if (n.attribute_size() > 0) fail(where() + " has unexpected attribute '" + printable(n.attribute(0).name()) + "'");
  }

  void gemmAttributes(const onnx::NodeProto& n) const {
    bool transB = false;
    for (const onnx::AttributeProto& a : n.attribute()) {
      const bool isInt = a.type() == onnx::AttributeProto::INT, isFloat = a.type() == onnx::AttributeProto::FLOAT;
      if (a.name() == "transB" && isInt && a.i() == 1)
        transB = true;
      else if (a.name() == "transA" && isInt && a.i() == 0)
        continue;
      else if ((a.name() == "alpha" || a.name() == "beta") && isFloat && a.f() == 1.0f)
        continue;
      else
        fail(where() + " has unsupported attribute '" + printable(a.name()) +
             "' (expected transB=1 and default alpha, beta, transA)");
    }
    if (!transB) fail(where() + " lacks transB=1 (weights are stored [out, in])");
  }

  void eluAttributes(const onnx::NodeProto& n) const {
    for (const onnx::AttributeProto& a : n.attribute())
      if (a.name() != "alpha" || a.type() != onnx::AttributeProto::FLOAT || a.f() != 1.0f)
        fail(where() + " has unsupported attribute '" + printable(a.name()) + "' (only alpha=1 is supported)");
  }

  // initializer `name` as floats, checked against `expected` (-1 = any size); `role` names it in messages
  Tensor initializer(const std::string& name, const std::vector<int64_t>& expected, const std::string& role) {
    const std::string what = where() + " " + role + " '" + printable(name) + "'";
    const auto it = initializers_.find(name);
    if (it == initializers_.end()) fail(what + " is not an initializer");
    if (!used_.insert(name).second) fail(what + " is used by more than one node");
    const onnx::TensorProto& t = *it->second;
    if (t.data_type() != onnx::TensorProto::FLOAT)
      fail(what + " has data type " + std::to_string(t.data_type()) + ", expected FLOAT (1)");
    if (t.data_location() == onnx::TensorProto::EXTERNAL || t.external_data_size() > 0 || t.has_segment())
      fail(what + " does not store its data inline");
    Tensor out;
    out.dims.assign(t.dims().begin(), t.dims().end());
    bool shapeOk = out.dims.size() == expected.size();
    for (size_t i = 0; shapeOk && i < expected.size(); ++i)
      shapeOk = out.dims[i] > 0 && (expected[i] < 0 || out.dims[i] == expected[i]);
    if (!shapeOk) fail(what + " has shape " + shapeString(out.dims) + ", expected " + shapeString(expected));
    int64_t count = 1;
    for (int64_t d : out.dims) {
      if (d > (int64_t(1) << 28) || count > (int64_t(1) << 28) / d) fail(what + " is too large");
      count *= d;
    }
    if (t.int32_data_size() || t.int64_data_size() || t.double_data_size() || t.uint64_data_size() ||
        t.string_data_size())
      fail(what + " stores its values in a non-float field");
    if (!t.raw_data().empty()) {
      if (t.float_data_size() > 0) fail(what + " has both raw_data and float_data");
      if (int64_t(t.raw_data().size()) != count * 4)
        fail(what + " has " + std::to_string(t.raw_data().size()) + " bytes of data, expected " +
             std::to_string(count * 4));
      out.values.resize(size_t(count));
      for (int64_t i = 0; i < count; ++i) out.values[size_t(i)] = readLittleEndian(t.raw_data().data() + 4 * i);
    } else {
      if (int64_t(t.float_data_size()) != count)
        fail(what + " has " + std::to_string(t.float_data_size()) + " values, expected " + std::to_string(count));
      out.values.assign(t.float_data().begin(), t.float_data().end());
    }
    for (size_t i = 0; i < out.values.size(); ++i)
      if (!std::isfinite(out.values[i])) fail(what + " has a NaN or Inf at index " + std::to_string(i));
    return out;
  }

  const std::string& path_;
  const onnx::GraphProto& g_;
  std::map<std::string, const onnx::TensorProto*> initializers_;
  std::set<std::string> used_;     // initializers read so far
  std::set<std::string> defined_;  // graph input and node outputs so far
  std::string current_;            // the value the next node must read
  int k_ = 0;                      // index of the next node
};

}  // namespace

void savePolicyOnnx(const std::string& path, const PolicyExport& p) {
  validateExport(path, p);
  const MlpWeights& a = p.actor;

  onnx::ModelProto model;
  model.set_ir_version(kIrVersion);
  model.set_producer_name("treelearn");
  onnx::OperatorSetIdProto* opset = model.add_opset_import();
  opset->set_domain("");
  opset->set_version(kOpsetVersion);
  for (const auto& kv : p.metadata) {
    onnx::StringStringEntryProto* e = model.add_metadata_props();
    e->set_key(kv.first);
    e->set_value(kv.second);
  }

  onnx::GraphProto* g = model.mutable_graph();
  g->set_name("policy");
  setTensorType(g->add_input(), kInputName, a.inputSize());
  setTensorType(g->add_output(), kOutputName, a.outputSize());

  const int64_t n = a.inputSize();
  addInitializer(g, "obs_mean", {n}, n, [&](int64_t i) { return p.obsMean[Eigen::Index(i)]; });
  addInitializer(g, "obs_std", {n}, n, [&](int64_t i) { return p.obsStd[Eigen::Index(i)]; });
  addInitializer(g, "obs_clip_min", {}, 1, [&](int64_t) { return -p.obsClip; });
  addInitializer(g, "obs_clip_max", {}, 1, [&](int64_t) { return p.obsClip; });
  addNode(g, "Sub", "normalise_sub", {kInputName, "obs_mean"}, "obs_centered");
  addNode(g, "Div", "normalise_div", {"obs_centered", "obs_std"}, "obs_scaled");
  addNode(g, "Clip", "normalise_clip", {"obs_scaled", "obs_clip_min", "obs_clip_max"}, "obs_normalised");

  std::string x = "obs_normalised";
  for (int k = 0; k < a.layers(); ++k) {
    const std::string id = std::to_string(k);
    const Eigen::MatrixXf& w = a.W[size_t(k)];
    const Eigen::VectorXf& b = a.b[size_t(k)];
    const int64_t cols = w.cols();
    addInitializer(g, "w" + id, {w.rows(), cols}, w.size(), [&](int64_t i) { return w(i / cols, i % cols); });
    addInitializer(g, "b" + id, {b.size()}, b.size(), [&](int64_t i) { return b[Eigen::Index(i)]; });
    const bool last = k + 1 == a.layers();
    const std::string z = last ? std::string(kOutputName) : "z" + id;
    onnx::NodeProto* gemm = addNode(g, "Gemm", "layer" + id + "_gemm", {x, "w" + id, "b" + id}, z);
    onnx::AttributeProto* transB = gemm->add_attribute();
    transB->set_name("transB");
    transB->set_type(onnx::AttributeProto::INT);
    transB->set_i(1);
    if (last) break;
    x = "h" + id;
    if (a.activation == Activation::Elu) {
      onnx::AttributeProto* alpha = addNode(g, "Elu", "layer" + id + "_elu", {z}, x)->add_attribute();
      alpha->set_name("alpha");
      alpha->set_type(onnx::AttributeProto::FLOAT);
      alpha->set_f(1.0f);
    } else {
      addNode(g, "Tanh", "layer" + id + "_tanh", {z}, x);
    }
  }

  std::string bytes;
  if (!model.SerializeToString(&bytes)) fail(path, "cannot export: protobuf serialisation failed");
  runChecker(path, model);
  engine::writeFileAtomic(path, bytes);
}

LoadedPolicy loadPolicyOnnx(const std::string& path) {
  const std::string bytes = engine::readFile(path, engine::kMaxModelFileBytes);
  onnx::ModelProto model;
  if (bytes.empty() || !model.ParseFromString(bytes)) fail(path, "not an ONNX model (protobuf parse failed)");
  if (!model.has_graph()) fail(path, "not an ONNX model (no graph)");
  // protobuf keeps bytes it has no field for: text or junk appended to a model parses as unknown fields
  if (!model.unknown_fields().empty() || !model.graph().unknown_fields().empty())
    fail(path, "holds data that is no part of an ONNX model (bytes appended to it, or a newer format)");
  runChecker(path, model);

  if (model.ir_version() < 7) fail(path, "IR version " + std::to_string(model.ir_version()) + " is older than 7");
  if (model.opset_import_size() != 1 ||
      !(model.opset_import(0).domain().empty() || model.opset_import(0).domain() == "ai.onnx") ||
      model.opset_import(0).version() != kOpsetVersion)
    fail(path, "expected exactly one opset import: the default domain at version 13");
  if (model.functions_size() > 0 || model.training_info_size() > 0)
    fail(path, "model has local functions or training info, which policy files never contain");

  LoadedPolicy out;
  for (const onnx::StringStringEntryProto& e : model.metadata_props())
    if (!out.metadata.emplace(e.key(), e.value()).second)
      fail(path, "metadata key '" + printable(e.key()) + "' appears twice");
  GraphReader(path, model.graph()).read(&out);
  return out;
}

void LoadedPolicy::act(const Eigen::MatrixXf& obs, Eigen::MatrixXf* actions) const {
  if (obs.rows() != observationSize())
    throw std::invalid_argument("LoadedPolicy::act: observations have " + std::to_string(obs.rows()) +
                                " rows, the policy expects " + std::to_string(observationSize()));
  // same operations and order as the ONNX graph: (obs - mean) / std, clipped
  const Eigen::MatrixXf x =
      ((obs.colwise() - obsMean).array().colwise() / obsStd.array()).cwiseMax(-obsClip).cwiseMin(obsClip).matrix();
  mlpForward(actor, x, actions);
}

uint64_t onnxFileHash(const std::string& path) {
  return engine::hashBytes(engine::readFile(path, engine::kMaxModelFileBytes));
}

}  // namespace ai
