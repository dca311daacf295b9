// mpi_cli_test.cpp — training and cards over MPI ranks (ai/dist/comm.h) as a user starts them, `mpirun -np N
// build/treelearn train|multitask|eval ...`: the ranks end in step, a run is the same run to run and after a resume,
// one rank is the run without mpirun bit for bit, the ranks' update is the single process's update on all their
// samples, and a card shared by the ranks is the recorded card to the bit. These are built when the project is built
// with MPI (scripts/setup.sh builds it so; Open MPI's settings for root and containers are given here). A build
// without MPI (the sanitizer build) gets the last test instead: started by mpirun, it refuses to run.
#ifdef TREELEARN_MPI_TESTS
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "engine/core/file_io.h"
#include "tests/cli_run.h"

namespace {

using cli::CliRun;

// Open MPI refuses root without the two ALLOW variables; shared memory and loopback are enough on one machine, and
// containers lack the kernel's cross-memory attach
const std::string kMpirun =
    "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,vader "
    "OMPI_MCA_btl_vader_single_copy_mechanism=none mpirun --bind-to none --oversubscribe ";

CliRun mpirun(int ranks, const std::string& args) {
  return cli::shell(kMpirun + "-np " + std::to_string(ranks) + " " + TREELEARN_BINARY + " " + args);
}

std::string field(const std::string& out, const std::string& name) {
  const size_t at = out.find(name + " ");
  if (at == std::string::npos) return "";
  return out.substr(at + name.size() + 1, out.find('\n', at) - at - name.size() - 1);
}

TEST(MpiCli, TheRanksUpdateIsTheOneProcessUpdateOnAllTheirSamples) {
  for (int ranks : {2, 4}) {  // 2 or 4 of the 8 environments each
    const CliRun r = cli::shell(kMpirun + "-np " + std::to_string(ranks) + " " + TREELEARN_MPI_CHECK);
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(field(r.out, "ranks"), std::to_string(ranks)) << r.out;
    EXPECT_EQ(field(r.out, "ranks agree"), "1") << r.out;  // every rank's policy, byte for byte
    // the same Adam steps on weights of order 1: only the order of float additions differs (measured 3e-8)
    EXPECT_LT(std::stod(field(r.out, "largest difference")), 1e-6) << r.out;
    EXPECT_GT(std::stod(field(r.out, "largest weight")), 0.5) << r.out;
    // mean 3, variance 4 from sums about the running mean: equal to one update on all columns up to rounding
    EXPECT_LT(std::stod(field(r.out, "normaliser difference")), 1e-5) << r.out;
  }
}

TEST(MpiCli, TwoRanksTrainTheWalkInStepTheSameRunToRunAndAfterAResume) {
  const std::string dir = cli::tempDir("mpi", "walk");
  const std::string common = "train walk --envs 4 --threads 1 --eval-every 0 --run-dir ";
  const CliRun a = mpirun(2, common + dir + "/a --steps 40960");
  ASSERT_EQ(a.code, 0) << a.out;
  EXPECT_NE(a.out.find("4 envs in 2 ranks of 2"), std::string::npos) << a.out;
  EXPECT_NE(a.out.find("ranks in step: all 2 end with policy hash"), std::string::npos) << a.out;
  EXPECT_EQ(a.out.find("iter 1/2"), a.out.rfind("iter 1/2")) << "rank 1 printed too:\n" << a.out;
  const std::string log = engine::readFile(dir + "/a/log.csv");
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 3) << log;  // the header and 2 iterations, written once
  ASSERT_TRUE(std::filesystem::exists(dir + "/a/walk.onnx"));

  // the same run again, in two parts: run to run and across a resume, the same policy
  const CliRun c1 = mpirun(2, common + dir + "/c --steps 20480");
  ASSERT_EQ(c1.code, 0) << c1.out;
  const CliRun c2 = mpirun(2, common + dir + "/c --steps 40960 --resume");
  ASSERT_EQ(c2.code, 0) << c2.out;
  const std::string policy = engine::readFile(dir + "/a/walk.policy.bin", engine::kMaxModelFileBytes);
  EXPECT_TRUE(policy == engine::readFile(dir + "/c/walk.policy.bin", engine::kMaxModelFileBytes));
}

TEST(MpiCli, SigusrOneToMpirunStopsEveryRankWithACheckpoint) {
  // mpirun forwards SIGUSR1 to the ranks (Ctrl-C makes it kill them); sent once the run has begun, every rank stops at
  // the end of the iteration in progress, rank 0 writes the checkpoint, and the run exits 130 as after Ctrl-C
  const std::string dir = cli::tempDir("mpi", "usr1");
  const std::string out = dir + "/out.txt";
  const CliRun r = cli::shell(kMpirun + "-np 2 " + TREELEARN_BINARY +
                              " train walk --envs 4 --threads 1 --eval-every 0 --steps 409600 --run-dir " + dir +
                              " > " + out + " 2>&1 & pid=$!; for i in $(seq 600); do grep -q 'training walk' " + out +
                              " && break; sleep 0.1; done; sleep 2; kill -USR1 $pid; wait $pid; echo \"exit $?\" >> " +
                              out + "; cat " + out);
  EXPECT_NE(r.out.find("stopped at iteration 1 "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("exit 130"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir + "/checkpoint.bin"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/walk.onnx"));  // a stopped run exports nothing
}

TEST(MpiCli, OneRankIsTheRunWithoutMpirunBitForBit) {
  const std::string dir = cli::tempDir("mpi", "one");
  const std::string common = "train walk --envs 4 --threads 1 --eval-every 0 --steps 20480 --run-dir ";
  const CliRun one = mpirun(1, common + dir + "/mpi");
  ASSERT_EQ(one.code, 0) << one.out;
  const CliRun plain = cli::run(common + dir + "/plain");
  ASSERT_EQ(plain.code, 0) << plain.out;
  EXPECT_TRUE(engine::readFile(dir + "/mpi/walk.policy.bin", engine::kMaxModelFileBytes) ==
              engine::readFile(dir + "/plain/walk.policy.bin", engine::kMaxModelFileBytes));
}

TEST(MpiCli, TheMultiTaskNetworkTrainsOverTwoRanks) {
  const std::string dir = cli::tempDir("mpi", "multitask");
  const CliRun r =
      mpirun(2, "multitask --skills walk squat --envs-per-skill 2 --threads 1 --steps 4096 --run-dir " + dir);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("ranks in step: all 2"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir + "/multitask.policy.bin"));
  EXPECT_EQ(engine::readFile(dir + "/skills.txt"), "walk\nsquat\n");
}

TEST(MpiCli, ACardSharedByTheRanksIsTheRecordedCardToTheBit) {
  // the ranks step their episodes' physics, the policy acts on all episodes at once: the figures are one process's,
  // so the retention check against the shipped model's recorded card passes (3 ranks: uneven shares)
  for (const auto& [skill, ranks] : {std::pair{"pushup", 2}, std::pair{"one_leg", 3}}) {  // a ground card, a driven one
    const CliRun r = mpirun(ranks, std::string("eval ") + skill);
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("identical to the card recorded for this model"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("CARD PASSED"), r.out.rfind("CARD PASSED")) << "printed by one rank only:\n" << r.out;
  }
}

TEST(MpiCli, TheTrainingCardIsSharedByTheRanksAndTheBestIsKept) {
  const std::string dir = cli::tempDir("mpi", "eval");
  const CliRun r =
      mpirun(2, "train walk --envs 4 --threads 1 --steps 20480 --eval-every 1 --eval-episodes 3 --run-dir " + dir);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("  eval: "), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("  eval: "), r.out.rfind("  eval: ")) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir + "/best.bin"));
  EXPECT_NE(r.out.find("best-by-evaluation policy"), std::string::npos) << r.out;
}

TEST(MpiCli, EnvironmentsThatTheRanksCannotShareAndCommandsThatDoNotRunOnRanksAreRefused) {
  const CliRun uneven = mpirun(2, "train walk --envs 5 --steps 20480 --run-dir " + cli::tempDir("mpi", "uneven"));
  EXPECT_NE(uneven.code, 0) << uneven.out;
  EXPECT_NE(uneven.out.find("5 environments cannot be shared evenly by 2 ranks"), std::string::npos) << uneven.out;
  const CliRun play = mpirun(2, "play levels/flat --seconds 1");
  EXPECT_NE(play.code, 0) << play.out;
  EXPECT_NE(play.out.find("only train, multitask and eval SKILL (a card) run across ranks"), std::string::npos)
      << play.out;
  const CliRun rewards = mpirun(2, "eval walk --rewards 1");
  EXPECT_NE(rewards.code, 0) << rewards.out;
  EXPECT_NE(rewards.out.find("under mpirun eval runs a report card"), std::string::npos) << rewards.out;
}

}  // namespace
#endif

#ifndef TREELEARN_MPI_TESTS
#include <gtest/gtest.h>

#include <string>

#include "tests/cli_run.h"

namespace {

// a build without MPI (the sanitizer build) started by mpirun would train the whole run on every rank and write over
// the others' files: it refuses, told by the launcher's environment
TEST(MpiCli, ABuildWithoutMpiStartedByMpirunRefusesToRun) {
  const std::string dir = cli::tempDir("mpi", "nompi");
  const cli::CliRun r = cli::shell("OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=0 " + std::string(TREELEARN_BINARY) +
                                   " train walk --steps 20480 --run-dir " + dir + "/run");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("this treelearn was built without MPI"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir + "/run"));
}

}  // namespace
#endif
