// ppo_config.cpp — PpoConfig <-> TOML (toml++), strict keys, located errors. One field list drives the
// parser, the writer and the hash, so a new field cannot be forgotten in one of them.
#include "ai/ppo/ppo_config.h"

#include <toml++/toml.h>

#include <charconv>
#include <cmath>
#include <set>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"

namespace ai {
namespace {

using engine::Error;
using engine::located;

// calls f(key, field) for every field, in the order toToml writes them
template <typename Config, typename F>
void visitFields(Config& c, F&& f) {
  f("buffer_size", c.bufferSize);
  f("batch_size", c.batchSize);
  f("num_epoch", c.numEpoch);
  f("gamma", c.gamma);
  f("lambda", c.lambda);
  f("reward_scale", c.rewardScale);
  f("learning_rate", c.learningRate);
  f("learning_rate_final", c.learningRateFinal);
  f("branch_learning_rate", c.branchLearningRate);
  f("epsilon", c.epsilon);
  f("epsilon_final", c.epsilonFinal);
  f("beta", c.beta);
  f("beta_final", c.betaFinal);
  f("adaptive_learning_rate", c.adaptiveLearningRate);
  f("desired_kl", c.desiredKl);
  f("adaptive_lr_min", c.adaptiveLrMin);
  f("adaptive_lr_max", c.adaptiveLrMax);
  f("value_loss_coef", c.valueLossCoef);
  f("clip_value_loss", c.clipValueLoss);
  f("normalize_advantages", c.normalizeAdvantages);
  f("max_grad_norm", c.maxGradNorm);
  f("actor_hidden", c.actorHidden);
  f("critic_hidden", c.criticHidden);
  f("activation", c.activation);
  f("actor_output_gain", c.actorOutputGain);
  f("critic_output_gain", c.criticOutputGain);
  f("normalize_observations", c.normalizeObservations);
  f("observation_clip", c.observationClip);
  f("initial_log_std", c.initialLogStd);
  f("log_std_min", c.logStdMin);
  f("log_std_max", c.logStdMax);
}

int lineOf(const toml::node& n) { return int(n.source().begin.line); }

// reads one TOML value into a field; throws a located error on a type mismatch
struct FieldReader {
  const toml::node& node;
  const std::string& file;
  const std::string& key;

  [[noreturn]] void fail(const std::string& expected) const {
    throw Error(located(file, lineOf(node), "'" + key + "' must be " + expected));
  }
  void operator()(int& v) const {
    const auto i = node.value_exact<int64_t>();
    if (!i || *i < INT32_MIN || *i > INT32_MAX) fail("an integer");
    v = int(*i);
  }
  void operator()(double& v) const {
    if (!node.is_number() || !std::isfinite(*node.value<double>())) fail("a finite number");
    v = *node.value<double>();
  }
  void operator()(bool& v) const {
    if (!node.is_boolean()) fail("true or false");
    v = *node.value<bool>();
  }
  void operator()(std::vector<int>& v) const {
    const toml::array* a = node.as_array();
    if (!a) fail("an array of integers");
    v.clear();
    for (const toml::node& e : *a) {
      const auto i = e.value_exact<int64_t>();
      if (!i || *i < INT32_MIN || *i > INT32_MAX) fail("an array of integers");
      v.push_back(int(*i));
    }
  }
  void operator()(Activation& v) const {
    const auto s = node.value_exact<std::string>();
    if (s && *s == "elu")
      v = Activation::Elu;
    else if (s && *s == "tanh")
      v = Activation::Tanh;
    else
      fail("\"elu\" or \"tanh\"");
  }
};

std::string formatDouble(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, r.ptr);
  if (s.find_first_of(".eni") == std::string::npos) s += ".0";  // keep it a TOML float
  return s;
}

// writes one field as "key = value\n"
struct FieldWriter {
  std::string* out;
  void line(const char* key, const std::string& value) const { *out += std::string(key) + " = " + value + "\n"; }
  void operator()(const char* key, int v) const { line(key, std::to_string(v)); }
  void operator()(const char* key, double v) const { line(key, formatDouble(v)); }
  void operator()(const char* key, bool v) const { line(key, v ? "true" : "false"); }
  void operator()(const char* key, const std::vector<int>& v) const {
    std::string s = "[";
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + std::to_string(v[i]);
    line(key, s + "]");
  }
  void operator()(const char* key, Activation v) const { line(key, v == Activation::Elu ? "\"elu\"" : "\"tanh\""); }
};

}  // namespace

void validatePpoConfig(const PpoConfig& c, const std::string& what) {
  auto require = [&](bool ok, const std::string& message) {
    if (!ok) throw Error(what + ": " + message);
  };
  require(c.bufferSize > 0, "buffer_size must be positive");
  require(c.batchSize > 0, "batch_size must be positive");
  require(c.numEpoch > 0, "num_epoch must be positive");
  require(c.gamma > 0 && c.gamma <= 1, "gamma must be in (0, 1]");
  require(c.lambda >= 0 && c.lambda <= 1, "lambda must be in [0, 1]");
  require(c.rewardScale > 0 && std::isfinite(c.rewardScale), "reward_scale must be positive");
  require(c.learningRate >= 0 && c.learningRateFinal >= 0 && c.branchLearningRate >= 0,
          "learning rates must be non-negative");
  require(c.desiredKl > 0, "desired_kl must be positive");
  require(c.adaptiveLrMin > 0 && c.adaptiveLrMin <= c.adaptiveLrMax,
          "adaptive_lr_min must be positive and at most adaptive_lr_max");
  require(c.epsilon > 0 && c.epsilonFinal > 0, "epsilon and epsilon_final must be positive");
  require(c.beta >= 0 && c.betaFinal >= 0, "beta and beta_final must be non-negative");
  require(c.valueLossCoef >= 0, "value_loss_coef must be non-negative");
  require(c.maxGradNorm > 0, "max_grad_norm must be positive");
  require(!c.actorHidden.empty() && !c.criticHidden.empty(), "actor_hidden and critic_hidden need at least one layer");
  // sizes a 2-core machine can hold and finish: a layer of 2^31 units ends in bad_alloc, 2^31 epochs never end
  require(c.bufferSize <= 10000000 && c.batchSize <= c.bufferSize,
          "buffer_size must be at most 10^7 and batch_size at most buffer_size");
  require(c.numEpoch <= 1000, "num_epoch must be at most 1000");
  require(c.actorHidden.size() <= 16 && c.criticHidden.size() <= 16,
          "actor_hidden and critic_hidden have at most 16 layers");
  for (int h : c.actorHidden) require(h > 0 && h <= 8192, "actor_hidden widths must be in [1, 8192]");
  for (int h : c.criticHidden) require(h > 0 && h <= 8192, "critic_hidden widths must be in [1, 8192]");
  require(c.learningRate < 1 && c.learningRateFinal < 1 && c.branchLearningRate < 1 && c.adaptiveLrMax < 1,
          "learning_rate, learning_rate_final, branch_learning_rate and adaptive_lr_max must be below 1");
  require(c.desiredKl < 10, "desired_kl must be below 10");
  require(c.epsilon < 10 && c.epsilonFinal < 10, "epsilon and epsilon_final must be below 10");
  require(c.beta < 10 && c.betaFinal < 10, "beta and beta_final must be below 10");
  require(c.logStdMin >= -20 && c.logStdMax <= 5, "log_std_min and log_std_max must lie in [-20, 5]");
  require(c.actorOutputGain > 0 && c.criticOutputGain > 0, "output gains must be positive");
  require(c.observationClip > 0, "observation_clip must be positive");
  require(c.logStdMin < c.logStdMax, "log_std_min must be below log_std_max");
  require(c.initialLogStd >= c.logStdMin && c.initialLogStd <= c.logStdMax,
          "initial_log_std must lie in [log_std_min, log_std_max]");
}

PpoConfig parsePpoConfig(std::string_view tomlText, const std::string& fileName, const std::string& table,
                         const PpoConfig& base) {
  toml::table root;
  try {
    root = toml::parse(tomlText, fileName);
  } catch (const toml::parse_error& e) {
    throw Error(located(fileName, int(e.source().begin.line), std::string(e.description())));
  }
  PpoConfig config = base;
  const toml::table* t = &root;
  if (!table.empty()) {
    const toml::node* node = root.at_path(table).node();
    if (!node) return config;
    t = node->as_table();
    if (!t) throw Error(located(fileName, lineOf(*node), "'" + table + "' must be a table"));
  }

  // every key must name a field; each field takes its value from its key if present
  std::set<std::string> known;
  visitFields(config, [&](const char* key, auto&) { known.insert(key); });
  for (const auto& [k, v] : *t) {
    if (!known.count(std::string(k.str())))
      throw Error(located(fileName, int(k.source().begin.line),
                          "unknown key '" + std::string(k.str()) + "'" + (table.empty() ? "" : " in [" + table + "]")));
  }
  visitFields(config, [&](const char* key, auto& field) {
    if (const toml::node* n = t->get(key)) {
      const std::string k = key;
      FieldReader{*n, fileName, k}(field);
    }
  });
  try {
    validatePpoConfig(config, fileName);
  } catch (const Error& e) {
    // point at the offending key's line when we can name it
    const std::string message = std::string(e.what()).substr(fileName.size() + 2);
    int line = 0;
    visitFields(config, [&](const char* key, auto&) {
      if (line == 0 && message.find(key) != std::string::npos)
        if (const toml::node* n = t->get(key)) line = lineOf(*n);
    });
    throw Error(located(fileName, line, message));
  }
  return config;
}

PpoConfig loadPpoConfig(const std::string& path, const std::string& table) {
  return parsePpoConfig(engine::readFile(path), path, table);
}

std::string toToml(const PpoConfig& config) {
  std::string out = "[ppo]\n";
  FieldWriter writer{&out};
  visitFields(config, [&](const char* key, const auto& field) { writer(key, field); });
  return out;
}

uint64_t ppoConfigHash(const PpoConfig& config) { return engine::hashBytes(toToml(config)); }

}  // namespace ai
