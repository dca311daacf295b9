// checkpoint_test.cpp — policy files and checkpoints round-trip byte-exactly, and truncated, corrupted,
// foreign or future-version files are rejected with a message naming the file.
#include "ai/ppo/checkpoint.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>

#include "ai/nn/byte_io.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"

namespace ai {
namespace {

std::string tempDir() {
  const std::string dir = (std::filesystem::temp_directory_path() / ("tl_ckpt_" + std::to_string(::getpid()))).string();
  engine::makeDirectories(dir);
  return dir;
}

PolicyState smallPolicy() {
  PpoConfig c;
  c.actorHidden = {8};
  c.criticHidden = {6, 5};
  PolicyState p = makePolicyState(c, 3, 2, 99);
  Eigen::MatrixXf batch = Eigen::MatrixXf::Random(3, 10);
  p.normalizer.update(batch);
  return p;
}

std::string errorLoading(const std::string& path) {
  try {
    loadCheckpoint(path);
  } catch (const engine::Error& e) {
    return e.what();
  }
  return "";
}

TEST(Checkpoint, PolicyFileRoundTripsByteExactly) {
  const std::string dir = tempDir();
  const PolicyState p = smallPolicy();
  savePolicyState(dir + "/a.bin", p, PolicyInfo{0x1234, 7, 700, 1.5});
  PolicyInfo info;
  const PolicyState q = loadPolicyState(dir + "/a.bin", &info);
  EXPECT_EQ(info.iteration, 7);
  EXPECT_EQ(info.envSteps, 700);
  EXPECT_EQ(info.score, 1.5);
  EXPECT_TRUE(q.actor.W[1] == p.actor.W[1]);
  EXPECT_TRUE(q.critic.b[2] == p.critic.b[2]);
  EXPECT_TRUE(q.logStd == p.logStd);
  EXPECT_TRUE(q.normalizer.variance() == p.normalizer.variance());
  savePolicyState(dir + "/b.bin", q, info);
  EXPECT_EQ(engine::readFile(dir + "/a.bin"), engine::readFile(dir + "/b.bin"));
  std::filesystem::remove_all(dir);
}

TEST(Checkpoint, DamagedFilesAreRejectedWithReason) {
  const std::string dir = tempDir(), path = dir + "/checkpoint.bin";
  TrainerCheckpoint c;
  c.policy = smallPolicy();
  c.iteration = 3;
  c.rngState = "1 2 3";
  saveCheckpoint(path, c);
  const std::string good = engine::readFile(path);
  EXPECT_EQ(loadCheckpoint(path).iteration, 3);

  engine::writeFileAtomic(path, good.substr(0, good.size() - 10));
  EXPECT_NE(errorLoading(path).find("truncated or padded"), std::string::npos) << errorLoading(path);

  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x40;
  engine::writeFileAtomic(path, flipped);
  EXPECT_EQ(errorLoading(path), path + ": checksum mismatch (the file is corrupted)");

  std::string future = good;
  future[8] = 9;  // version field
  engine::writeFileAtomic(path, future);
  EXPECT_NE(errorLoading(path).find("version 9 is not supported"), std::string::npos);

  savePolicyState(path, c.policy);  // a policy file is not a checkpoint
  EXPECT_EQ(errorLoading(path), path + ": not a treelearn checkpoint file (bad magic)");
  std::filesystem::remove_all(dir);
}

// a file whose checksum is valid but whose numbers cannot have come from training is refused, naming the field
TEST(Checkpoint, NonFiniteWeightsOrStatisticsAreRefusedWithTheField) {
  const std::string dir = tempDir();
  auto errorOf = [&](const std::function<void(PolicyState*)>& spoil) {
    PolicyState p = smallPolicy();
    spoil(&p);
    savePolicyState(dir + "/p.bin", p, {});
    try {
      loadPolicyState(dir + "/p.bin");
    } catch (const engine::Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(errorOf([](PolicyState* p) {
              p->actor.W[1](0, 0) = std::nanf("");
            }).find("actor layer 2 holds a non-finite weight"),
            std::string::npos);
  EXPECT_NE(
      errorOf([](PolicyState* p) { p->critic.b[0](1) = INFINITY; }).find("critic layer 1 holds a non-finite weight"),
      std::string::npos);
  EXPECT_NE(errorOf([](PolicyState* p) { p->logStd(0) = INFINITY; }).find("log-std is not finite"), std::string::npos);
  EXPECT_EQ(errorOf([](PolicyState*) {}), "");
}

TEST(Checkpoint, EveryShippedPolicyFileStillLoads) {
  // the committed assets/skills/*.policy.bin (exported before the export recorded steps, iteration and score: they
  // say 0 and no score) are read by the same loader that reads the new ones; a format change must keep them
  int files = 0;
  for (const auto& f : std::filesystem::directory_iterator(std::string(TREELEARN_SOURCE_DIR) + "/assets/skills")) {
    const std::string name = f.path().filename().string();
    if (name.size() < 11 || name.substr(name.size() - 11) != ".policy.bin") continue;
    PolicyInfo info;
    PolicyState p;
    EXPECT_NO_THROW(p = loadPolicyState(f.path().string(), &info)) << name;
    EXPECT_GT(p.actor.layers(), 0) << name;
    EXPECT_GE(info.envSteps, 0) << name;
    ++files;
  }
  EXPECT_GT(files, 0);
}

}  // namespace
}  // namespace ai
