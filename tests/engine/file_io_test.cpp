// file_io_test.cpp — whole-file reads that refuse what never ends, atomic writes and the temps a killed writer
// leaves behind.
#include "engine/core/file_io.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "engine/core/error.h"

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

// the message readFile throws, "" if it reads
static std::string readError(const std::string& path, int64_t maxBytes = engine::kMaxTextFileBytes) {
  try {
    engine::readFile(path, maxBytes);
  } catch (const engine::Error& e) {
    return e.what();
  }
  return "";
}

// a FIFO without a writer blocked every reader forever; /dev/zero was read until memory ran out
TEST(FileIo, AFifoADeviceAndAFolderAreRefusedAtOnce) {
  const std::string dir = testing::TempDir() + "/treelearn_file_io_special";
  fs::remove_all(dir);
  fs::create_directories(dir);
  ASSERT_EQ(::mkfifo((dir + "/level.toml").c_str(), 0644), 0);
  EXPECT_EQ(readError(dir + "/level.toml"), dir + "/level.toml: is a FIFO, expected a regular file");
  EXPECT_EQ(readError("/dev/zero"), "/dev/zero: is a character device, expected a regular file");
  EXPECT_EQ(readError(dir), dir + ": is a directory, expected a regular file");
  // a symbolic link is followed to what it names
  fs::create_symlink("/dev/zero", dir + "/model.onnx");
  EXPECT_EQ(readError(dir + "/model.onnx"), dir + "/model.onnx: is a character device, expected a regular file");
  EXPECT_NE(readError(dir + "/missing.toml").find("missing.toml: cannot open: No such file"), std::string::npos);
}

TEST(FileIo, AFileLargerThanItsFormatsCapIsRefusedBeforeItIsRead) {
  const std::string dir = testing::TempDir() + "/treelearn_file_io_cap";
  fs::remove_all(dir);
  fs::create_directories(dir);
  engine::writeFileAtomic(dir + "/a.keys", std::string(2000, '#'));
  EXPECT_EQ(readError(dir + "/a.keys", 2000), "");
  EXPECT_EQ(readError(dir + "/a.keys", 1999),
            dir + "/a.keys: is 2000 bytes, larger than the 1999 bytes this kind of file may be");
  // a sparse 17 MiB file (no disk used) against the 16 MiB of text formats
  fs::resize_file(dir + "/a.keys", 17 << 20);
  EXPECT_EQ(readError(dir + "/a.keys"), dir + "/a.keys: is 17 MiB, larger than the 16 MiB this kind of file may be");
}
