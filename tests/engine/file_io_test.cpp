// file_io_test.cpp — atomic writes and the temps a killed writer leaves behind.
#include "engine/core/file_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace fs = std::filesystem;

TEST(FileIo, AnAtomicWriteLeavesTheFileAndNoTemp) {
  const std::string dir = testing::TempDir() + "/treelearn_file_io_atomic";
  fs::remove_all(dir);
  fs::create_directories(dir);
  engine::writeFileAtomic(dir + "/a.bin", "first");
  engine::writeFileAtomic(dir + "/a.bin", "second");
  EXPECT_EQ(engine::readFile(dir + "/a.bin"), "second");
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1);
}

// a checkpoint write killed before its rename leaves NAME.tmp.PID: the next run clears such temps, and only them
TEST(FileIo, StaleTempsOfKilledWritersAreRemovedAndNothingElse) {
  const std::string dir = testing::TempDir() + "/treelearn_file_io_stale";
  fs::remove_all(dir);
  fs::create_directories(dir);
  engine::writeFileAtomic(dir + "/checkpoint.bin.tmp.99999999", "half a checkpoint");  // a dead writer's
  engine::writeFileAtomic(dir + "/log.csv", "rows");
  engine::writeFileAtomic(dir + "/notes.tmp.txt", "not a temp of ours");
  engine::writeFileAtomic(dir + "/own.bin.tmp." + std::to_string(::getpid()), "this process's");
  EXPECT_EQ(engine::removeStaleTemps(dir), 1);
  EXPECT_FALSE(fs::exists(dir + "/checkpoint.bin.tmp.99999999"));
  EXPECT_TRUE(fs::exists(dir + "/log.csv"));
  EXPECT_TRUE(fs::exists(dir + "/notes.tmp.txt"));
  EXPECT_TRUE(fs::exists(dir + "/own.bin.tmp." + std::to_string(::getpid())));
  EXPECT_EQ(engine::removeStaleTemps(dir + "/missing"), 0);  // a folder that is not there: nothing to do
}
