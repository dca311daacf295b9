// cli_run.h — running the built treelearn program (or a shell command) from the source folder in the end-to-end
// tests: its exit code and its output, stdout and stderr together; and a fresh temp folder per test.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

namespace cli {

inline const std::string kSource = TREELEARN_SOURCE_DIR;

struct CliRun {
  int code = -1;
  std::string out;  ///< stdout and stderr together
};

/// Runs `cmd` with the shell in the source folder.
inline CliRun shell(const std::string& cmd) {
  CliRun r;
  FILE* p = popen(("cd " + kSource + " && " + cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// Runs build/treelearn with `args` in the source folder.
inline CliRun run(const std::string& args) { return shell(std::string(TREELEARN_BINARY) + " " + args); }

/// An empty folder treelearn_PREFIX_NAME under the test temp folder (removed first if it was there).
inline std::string tempDir(const std::string& prefix, const std::string& name) {
  const std::string d = testing::TempDir() + "/treelearn_" + prefix + "_" + name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace cli
