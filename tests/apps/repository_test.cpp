// repository_test.cpp — what the repository holds: the product, not a lab notebook. Reads the tracked files of
// the checkout (`git ls-files` in TREELEARN_SOURCE_DIR); skipped when the source is not a git checkout.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

const std::string kSource = TREELEARN_SOURCE_DIR;
constexpr long long kLargeFileBytes = 5LL * 1024 * 1024;  // 5 MB

// stdout of a shell command; ok false when it could not run or exited non-zero
std::string capture(const std::string& cmd, bool* ok) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) {
    *ok = false;
    return out;
  }
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
  *ok = pclose(p) == 0;
  return out;
}

// the tracked files, repository-relative; empty when TREELEARN_SOURCE_DIR is not a git checkout
std::vector<std::string> trackedFiles() {
  bool ok = false;
  const std::string inside = capture("git -C '" + kSource + "' rev-parse --is-inside-work-tree 2>/dev/null", &ok);
  if (!ok || inside.rfind("true", 0) != 0) return {};
  const std::string list = capture("git -C '" + kSource + "' ls-files -z 2>/dev/null", &ok);
  std::vector<std::string> files;
  if (!ok) return files;
  size_t start = 0;
  for (size_t i = 0; i < list.size(); ++i)
    if (list[i] == '\0') {
      if (i > start) files.push_back(list.substr(start, i - start));
      start = i + 1;
    }
  return files;
}

// size in bytes of a tracked file in the work tree (-1: missing, e.g. deleted but not yet committed)
long long fileSize(const std::string& path) {
  struct stat st;
  if (stat((kSource + "/" + path).c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return -1;
  return static_cast<long long>(st.st_size);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

// Development narrative ("in session N we tried ...", "issue N asks ...") belongs in the history and in dated
// experiment entries (docs/experiments.md, docs/skills/), not in the product's files.
TEST(Repository, NoDevelopmentSessionNarrativeInTrackedFiles) {
  const std::vector<std::string> files = trackedFiles();
  if (files.empty()) GTEST_SKIP() << kSource << " is not a git checkout";
  const std::regex narrative("session [0-9]|issue [0-9]", std::regex::icase);
  std::ostringstream found;
  int matches = 0;
  for (const std::string& path : files) {
    const long long size = fileSize(path);
    if (size < 0 || size > kLargeFileBytes) continue;
    std::ifstream in(kSource + "/" + path, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.find('\0') != std::string::npos) continue;  // binary (models, policies, images)
    const std::string folded = lower(text);
    if (folded.find("session ") == std::string::npos && folded.find("issue ") == std::string::npos) continue;
    std::istringstream lines(text);
    std::string line;
    for (int number = 1; std::getline(lines, line); ++number) {
      std::smatch m;
      if (!std::regex_search(line, m, narrative)) continue;
      ++matches;
      found << "  " << path << ":" << number << ": '" << m.str() << "'\n";
    }
  }
  EXPECT_EQ(matches, 0) << "development narrative in tracked files (say it with a date and commit, or drop it):\n"
                        << found.str();
}

// The repository holds what play needs; large files are allowed only where assets/large_files.txt lists them.
TEST(Repository, NoLargeFilesOutsideTheListedOnes) {
  const std::vector<std::string> files = trackedFiles();
  if (files.empty()) GTEST_SKIP() << kSource << " is not a git checkout";
  std::ifstream list(kSource + "/assets/large_files.txt");
  ASSERT_TRUE(list.good()) << "assets/large_files.txt is missing";
  std::set<std::string> allowed;
  std::string line;
  while (std::getline(list, line)) {
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    allowed.insert(line);
  }
  const std::set<std::string> tracked(files.begin(), files.end());
  for (const std::string& path : allowed)
    EXPECT_TRUE(tracked.count(path)) << "assets/large_files.txt lists " << path << ", which is not tracked";
  for (const std::string& path : files) {
    const long long size = fileSize(path);
    if (size > kLargeFileBytes && !allowed.count(path))
      ADD_FAILURE() << path << " is " << size << " bytes (" << size / (1024 * 1024)
                    << " MB), over 5 MB and not listed in assets/large_files.txt";
  }
}

// every tracked C++ file is as .clang-format writes it (Google base, 120 columns): `clang-format -i FILE` fixes one
TEST(Repository, CodeFollowsTheClangFormatStyle) {
  const std::vector<std::string> files = trackedFiles();
  if (files.empty()) GTEST_SKIP() << kSource << " is not a git checkout";
  bool ok = false;
  capture("clang-format --version >/dev/null 2>&1", &ok);
  if (!ok) GTEST_SKIP() << "clang-format is not installed (scripts/setup.sh installs it)";
  std::string list;
  for (const std::string& f : files)
    if (f.size() > 4 && (f.compare(f.size() - 4, 4, ".cpp") == 0 || f.compare(f.size() - 2, 2, ".h") == 0))
      list += " '" + f + "'";
  const std::string out =
      capture("cd '" + kSource + "' && clang-format --dry-run" + list + " 2>&1 | grep 'warning:' | head -20", &ok);
  EXPECT_EQ(out, "") << "not formatted (run clang-format -i on these files):\n" << out;
}
