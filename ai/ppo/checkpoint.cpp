// checkpoint.cpp — the versioned, checksummed container and the two payloads (policy file, checkpoint).
#include "ai/ppo/checkpoint.h"

#include <cmath>
#include <cstring>
#include <sstream>
#include <string>

#include "ai/nn/byte_io.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"

namespace ai {
namespace {

constexpr char kPolicyMagic[8] = {'T', 'L', 'P', 'O', 'L', 'I', 'C', 'Y'};
constexpr char kCheckpointMagic[8] = {'T', 'L', 'C', 'H', 'K', 'P', 'T', '1'};
constexpr size_t kHeaderSize = 8 + 4 + 8 + 8;

std::string wrap(const char (&magic)[8], const std::string& payload) {
  ByteWriter w;
  w.bytes(magic, 8);
  w.u32(kCheckpointVersion);
  w.u64(payload.size());
  w.u64(engine::hashBytes(payload));
  w.bytes(payload.data(), payload.size());
  return w.take();
}

// checks the header and returns the payload bytes
std::string_view unwrap(const char (&magic)[8], const std::string& bytes, const std::string& path, const char* kind) {
  if (bytes.size() < kHeaderSize || std::memcmp(bytes.data(), magic, 8) != 0)
    throw engine::Error(path + ": not a treelearn " + kind + " file (bad magic)");
  ByteReader header(std::string_view(bytes).substr(8, kHeaderSize - 8), path);
  const uint32_t version = header.u32();
  const uint64_t length = header.u64();
  const uint64_t checksum = header.u64();
  if (version != kCheckpointVersion)
    throw engine::Error(path + ": " + kind + " version " + std::to_string(version) +
                        " is not supported (this build reads " + std::to_string(kCheckpointVersion) + ")");
  if (length != bytes.size() - kHeaderSize)
    throw engine::Error(path + ": truncated or padded: header says " + std::to_string(length) +
                        " payload bytes, file has " + std::to_string(bytes.size() - kHeaderSize));
  const std::string_view payload = std::string_view(bytes).substr(kHeaderSize);
  if (engine::hashBytes(payload) != checksum) throw engine::Error(path + ": checksum mismatch (the file is corrupted)");
  return payload;
}

void expectEnd(const ByteReader& r) {
  if (!r.atEnd()) r.fail("unexpected trailing data");
}

}  // namespace

void writePolicyState(ByteWriter* out, const PolicyState& policy) {
  out->mlp(policy.actor);
  out->mlp(policy.critic);
  policy.normalizer.save(out);
  out->vector(policy.logStd);
}

PolicyState readPolicyState(ByteReader* in) {
  PolicyState p;
  p.actor = in->mlp();
  p.critic = in->mlp();
  p.normalizer.load(in);
  p.logStd = in->vectorF();
  if (p.actor.layers() == 0 || p.critic.layers() == 0) in->fail("policy without layers");
  if (p.critic.inputSize() != p.actor.inputSize() || p.normalizer.size() != p.actor.inputSize())
    in->fail("actor, critic and normaliser disagree on the observation size");
  if (p.critic.outputSize() != 1) in->fail("critic must have one output");
  if (p.logStd.size() != p.actor.outputSize()) in->fail("log-std size does not match the actor's output");
  // a valid checksum over numbers that cannot have come from training: refused here, with the field, rather than as
  // a NaN model or a first iteration that dies without saying why
  auto finiteMlp = [&](const MlpWeights& m, const char* what) {
    for (int l = 0; l < m.layers(); ++l)
      if (!m.W[size_t(l)].allFinite() || !m.b[size_t(l)].allFinite())
        in->fail(std::string(what) + " layer " + std::to_string(l + 1) + " holds a non-finite weight");
  };
  finiteMlp(p.actor, "actor");
  finiteMlp(p.critic, "critic");
  if (!p.logStd.allFinite()) in->fail("log-std is not finite");
  if (!p.normalizer.mean().allFinite()) in->fail("normaliser mean is not finite");
  if (!p.normalizer.variance().allFinite() || (p.normalizer.variance().array() < 0).any())
    in->fail("normaliser variance is negative or not finite");
  if (!std::isfinite(p.normalizer.count()) || !(p.normalizer.count() > 0))
    in->fail("normaliser count is not a positive number");
  if (!std::isfinite(p.normalizer.clip()) || !(p.normalizer.clip() > 0))
    in->fail("normaliser clip is not a positive number");
  return p;
}

void savePolicyState(const std::string& path, const PolicyState& policy, const PolicyInfo& info) {
  ByteWriter w;
  w.u64(info.configHash);
  w.i64(info.iteration);
  w.i64(info.envSteps);
  w.f64(info.score);
  writePolicyState(&w, policy);
  engine::writeFileAtomic(path, wrap(kPolicyMagic, w.data()));
}

PolicyState loadPolicyState(const std::string& path, PolicyInfo* info) {
  const std::string bytes = engine::readFile(path, engine::kMaxModelFileBytes);
  ByteReader r(unwrap(kPolicyMagic, bytes, path, "policy"), path);
  PolicyInfo i;
  i.configHash = r.u64();
  i.iteration = r.i64();
  i.envSteps = r.i64();
  i.score = r.f64();
  PolicyState p = readPolicyState(&r);
  expectEnd(r);
  if (info) *info = i;
  return p;
}

void saveCheckpoint(const std::string& path, const TrainerCheckpoint& c) {
  ByteWriter w;
  w.u64(c.configHash);
  w.u64(c.seed);
  w.i64(c.totalSteps);
  w.i64(c.iteration);
  w.i64(c.envSteps);
  w.f64(c.bestScore);
  writePolicyState(&w, c.policy);
  c.optimizer.save(&w);
  w.str(c.rngState);
  w.str(c.envState);
  w.f64(c.adaptiveLearningRate);
  engine::writeFileAtomic(path, wrap(kCheckpointMagic, w.data()));
}

TrainerCheckpoint loadCheckpoint(const std::string& path) {
  const std::string bytes = engine::readFile(path, engine::kMaxModelFileBytes);
  ByteReader r(unwrap(kCheckpointMagic, bytes, path, "checkpoint"), path);
  TrainerCheckpoint c;
  c.configHash = r.u64();
  c.seed = r.u64();
  c.totalSteps = r.i64();
  c.iteration = r.i64();
  c.envSteps = r.i64();
  c.bestScore = r.f64();
  c.policy = readPolicyState(&r);
  c.optimizer.load(&r);
  c.rngState = r.str();
  c.envState = r.str();
  if (!r.atEnd()) c.adaptiveLearningRate = r.f64();
  expectEnd(r);
  if (c.iteration < 0 || c.envSteps < 0) r.fail("negative iteration or step count");
  return c;
}

}  // namespace ai
