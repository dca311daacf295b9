// fuzz_test.cpp — deterministic mutation fuzzing of every file reader (layout and use: tests/fuzz/README.md).
// Each reader gets its committed seed files (tests/fuzz/corpus/READER/) and a fixed-seed stream of mutations of
// them; every input must either load or be refused with engine::Error whose message names the file it was read
// as. Any other exception, an empty or unnamed message, a crash, a hang (10 s) or an allocation of gigabytes is a
// finding. Inputs that once failed live in tests/fuzz/regressions/READER/ and are read again by each reader's
// regression test.
#include <cxxabi.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <typeinfo>
#include <vector>

#include "ai/nn/adam.h"
#include "ai/onnx/policy_onnx.h"
#include "ai/ppo/checkpoint.h"
#include "ai/ppo/ppo_config.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"
#include "engine/input/key_script.h"
#include "engine/replay/replay.h"
#include "levels/level.h"
#include "robot/entry_state.h"
#include "robot/robot_model.h"
#include "robot/skill_tree.h"
#include "tests/fixtures.h"

// AddressSanitizer reserves terabytes of address space up front, so the address-space budget below is left out
// in a sanitizer build (ASan reports oversized allocations itself)
#if defined(__SANITIZE_ADDRESS__)
#define TREELEARN_FUZZ_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TREELEARN_FUZZ_ASAN 1
#endif
#endif

namespace {

namespace fs = std::filesystem;

const std::string kFuzzDir = fixtures::kSource + "/tests/fuzz";

/// A reader that takes longer than this on one input hangs: the watchdog ends the process.
constexpr auto kHangLimit = std::chrono::seconds(10);
/// Address space a reader may add while the fuzz loop runs: no reader here needs more than a few megabytes for
/// inputs of at most a few hundred kilobytes, so gigabytes mean a size field was believed.
constexpr uint64_t kAddressBudget = uint64_t(2) << 30;

// ---- findings not fixed yet ----------------------------------------------------------------------------------------

/// A finding whose reader is not fixed yet. Its regression input (regressions/FOLDER/FILE) is skipped by the
/// reader's regression test, and a misbehaviour containing `signature` in the mutation test is counted and printed
/// instead of failing it (the fixed seed finds it again on every run). Delete the entry once the reader is fixed.
struct KnownFinding {
  const char* folder;
  const char* file;
  const char* signature;
};

// inputs that still misbehave, skipped by name until their reader is fixed (empty: every finding so far is fixed
// and its input kept under regressions/)
const std::vector<KnownFinding> kKnownFindings = {};

const KnownFinding* knownFindingFile(const std::string& folder, const std::string& file) {
  for (const KnownFinding& k : kKnownFindings)
    if (folder == k.folder && file == k.file) return &k;
  return nullptr;
}

const KnownFinding* knownFindingMisbehaviour(const std::string& folder, const std::string& misbehaviour) {
  for (const KnownFinding& k : kKnownFindings)
    if (folder == k.folder && misbehaviour.find(k.signature) != std::string::npos) return &k;
  return nullptr;
}

// ---- the readers ---------------------------------------------------------------------------------------------------

/// One reader under test.
struct Reader {
  std::string folder;  ///< corpus/FOLDER and regressions/FOLDER
  uint64_t seed = 0;   ///< of the mutation stream
  int iterations = 0;  ///< mutated inputs per run (times TREELEARN_FUZZ_ITERATIONS), sized for 1-3 s in Release
  bool text = true;    ///< text-aware mutations (numbers, lines) rather than binary ones (size fields, floats)
  std::string named;   ///< what a refusal's message must contain: the file name or path the bytes are read as
  /// reads bytes as the reader's file; throws whatever the reader throws
  std::function<void(const std::string& bytes)> load;
  /// recomputes a container's length and checksum after mutation, so that most mutations reach the payload
  /// behind it instead of all stopping at the checksum (nullptr: no checksum)
  std::function<void(std::string* bytes)> reseal;
};

Reader reader(const std::string& folder, uint64_t seed, int iterations, bool text, const std::string& named) {
  Reader r;
  r.folder = folder;
  r.seed = seed;
  r.iterations = iterations;
  r.text = text;
  r.named = named;
  return r;
}

void writeBytes(const std::string& path, const std::string& bytes) {
  // not engine::writeFileAtomic: its fsync per input would make the loop disk-bound; and unlinked first, because
  // ext4 flushes a file that is truncated and rewritten (auto_da_alloc): 2.7 ms an input instead of 0.01 ms
  ::unlink(path.c_str());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error("fuzz harness: cannot write " + path);
}

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// a fresh folder under the test temp dir for the readers that only read paths; removed at scope exit
struct TempFolder {
  std::string path;
  explicit TempFolder(const std::string& name) {
    path = testing::TempDir() + "treelearn-fuzz-" + name + "-" + std::to_string(::getpid());
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempFolder() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// the ai container (checkpoint.h): magic, u32 version, u64 payload length, u64 FNV-1a of the payload, payload
void resealContainer(std::string* bytes) {
  constexpr size_t kHeader = 8 + 4 + 8 + 8;
  if (bytes->size() < kHeader) return;
  const uint64_t length = bytes->size() - kHeader;
  const uint64_t checksum = engine::hashBytes(std::string_view(*bytes).substr(kHeader));
  std::memcpy(bytes->data() + 12, &length, 8);
  std::memcpy(bytes->data() + 20, &checksum, 8);
}

// a replay's last line is "end <FNV-1a of every byte before it>"
void resealReplay(std::string* bytes) {
  const size_t end = bytes->rfind("\nend ");
  if (end == std::string::npos || end + 5 + 16 > bytes->size()) return;
  const std::string hex = engine::toHex(engine::hashBytes(std::string_view(*bytes).substr(0, end + 1)));
  bytes->replace(end + 5, 16, hex);
}

Reader levelReader() {
  Reader r = reader("level", 0x6c6576656c, 15000, true, "fuzzed-level.toml");
  r.load = [](const std::string& b) { levels::parseLevel(b, "fuzzed-level.toml"); };
  return r;
}

Reader keyScriptReader() {
  Reader r = reader("key_script", 0x6b657973, 15000, true, "fuzzed.keys");
  r.load = [](const std::string& b) { engine::parseKeyScriptWithSeed(b, "fuzzed.keys"); };
  return r;
}

Reader replayReader() {
  Reader r = reader("replay", 0x7265706c6179, 50000, true, "fuzzed.replay");
  r.load = [](const std::string& b) { engine::parseReplay(b, "fuzzed.replay"); };
  r.reseal = resealReplay;
  return r;
}

Reader skillTreeReader(const std::string& dir) {
  const std::string path = dir + "/fuzzed-tree.toml";
  Reader r = reader("skill_tree", 0x74726565, 2000, true, path);
  r.load = [path](const std::string& b) {
    writeBytes(path, b);
    robot::loadSkillTree(path, fixtures::robotModel());
  };
  return r;
}

Reader ppoConfigReader() {
  Reader r = reader("ppo_config", 0x70706f, 24000, true, "fuzzed-ppo.toml");
  r.load = [](const std::string& b) {
    // the shared table, then a skill's overrides on top of it, as training reads the tree
    const ai::PpoConfig shared = ai::parsePpoConfig(b, "fuzzed-ppo.toml", "ppo");
    ai::parsePpoConfig(b, "fuzzed-ppo.toml", "skill.run.ppo", shared);
  };
  return r;
}

// the robot config names its URDF relative to itself: an unmutated copy of the URDF seed sits beside it. Errors
// about the URDF name the URDF, so a refusal must name a file in this folder.
Reader robotModelReader(const std::string& dir) {
  fs::copy_file(kFuzzDir + "/corpus/urdf/g1_23dof.urdf", dir + "/g1_23dof.urdf", fs::copy_options::overwrite_existing);
  const std::string path = dir + "/fuzzed-robot.toml";
  Reader r = reader("robot_model", 0x726f626f74, 3500, true, dir + "/");
  r.load = [path](const std::string& b) {
    writeBytes(path, b);
    robot::loadRobotModel(path);
  };
  return r;
}

Reader urdfReader() {
  Reader r = reader("urdf", 0x75726466, 2500, true, "fuzzed.urdf");
  r.load = [](const std::string& b) {
    robot::RobotModel model;
    robot::parseG1Urdf(b, "fuzzed.urdf", &model);
  };
  return r;
}

Reader onnxReader(const std::string& dir) {
  const std::string path = dir + "/fuzzed.onnx";
  Reader r = reader("onnx", 0x6f6e6e78, 50000, false, path);
  r.load = [path](const std::string& b) {
    writeBytes(path, b);
    ai::loadPolicyOnnx(path);
  };
  return r;
}

Reader policyReader(const std::string& dir) {
  const std::string path = dir + "/fuzzed.policy.bin";
  Reader r = reader("policy", 0x706f6c696379, 60000, false, path);
  r.load = [path](const std::string& b) {
    writeBytes(path, b);
    ai::PolicyInfo info;
    ai::loadPolicyState(path, &info);
  };
  r.reseal = resealContainer;
  return r;
}

Reader checkpointReader(const std::string& dir) {
  const std::string path = dir + "/fuzzed-checkpoint.bin";
  Reader r = reader("checkpoint", 0x636b7074, 35000, false, path);
  r.load = [path](const std::string& b) {
    writeBytes(path, b);
    ai::loadCheckpoint(path);
  };
  r.reseal = resealContainer;
  return r;
}

Reader entriesReader() {
  Reader r = reader("entries", 0x656e7472, 16000, true, "fuzzed.entries");
  r.load = [](const std::string& b) { robot::parseEntries(b, "fuzzed.entries"); };
  return r;
}

// ---- the generated binary seeds ------------------------------------------------------------------------------------

// The binary seeds are written by the code below rather than copied from assets/ (a shipped policy is 2.4 MB): run
// the reader's test once with TREELEARN_FUZZ_WRITE_SEEDS=1 to write them again after a format change.
bool writeSeedsRequested() {
  const char* v = std::getenv("TREELEARN_FUZZ_WRITE_SEEDS");
  return v && std::string(v) == "1";
}

// checkpoint_test.cpp's small policy: 3 observations, 2 actions, a one-layer actor and a two-layer critic
ai::PolicyState smallPolicy() {
  ai::PpoConfig c;
  c.actorHidden = {8};
  c.criticHidden = {6, 5};
  ai::PolicyState p = ai::makePolicyState(c, 3, 2, 99);
  Eigen::MatrixXf batch(3, 4);
  batch << 0.1f, -0.2f, 0.3f, 0.4f, 1.0f, 0.5f, -1.5f, 2.0f, -0.3f, 0.0f, 0.7f, 0.2f;
  p.normalizer.update(batch);
  return p;
}

void writePolicySeeds(const std::string& dir) {
  ai::savePolicyState(dir + "/small.policy.bin", smallPolicy(), ai::PolicyInfo{0x1234, 7, 700, 1.5});
}

void writeCheckpointSeeds(const std::string& dir) {
  ai::TrainerCheckpoint c;
  c.configHash = 0x1234;
  c.seed = 5;
  c.totalSteps = 1000;
  c.iteration = 3;
  c.envSteps = 300;
  c.bestScore = 0.5;
  c.policy = smallPolicy();
  // one Adam step over the actor, so that the moments are in the file
  ai::MlpWeights gradient = c.policy.actor;
  std::vector<ai::TensorRef> params, grads;
  ai::appendTensors(&c.policy.actor, &params);
  ai::appendTensors(&gradient, &grads);
  c.optimizer.step(params, grads, 1e-3f);
  std::ostringstream rng;
  rng << std::mt19937_64(5);
  c.rngState = rng.str();
  c.envState = "fuzz seed";
  c.adaptiveLearningRate = 1e-4;
  ai::saveCheckpoint(dir + "/small.checkpoint.bin", c);
}

void writeOnnxSeeds(const std::string& dir) {
  auto policy = [](const std::vector<int>& sizes, ai::Activation activation) {
    ai::PolicyExport p;
    p.actor = ai::makeMlp(sizes, activation, 5, 0.5f);
    const auto n = Eigen::Index(sizes.front());
    p.obsMean = Eigen::VectorXf::LinSpaced(n, -1.0f, 1.0f);
    p.obsStd = Eigen::VectorXf::LinSpaced(n, 0.5f, 2.0f);
    p.metadata = {{"skill", "fuzz"}, {"env_steps", "1000"}};
    return p;
  };
  ai::savePolicyOnnx(dir + "/elu-6-8-3.onnx", policy({6, 8, 3}, ai::Activation::Elu));
  ai::savePolicyOnnx(dir + "/tanh-5-4-4-2.onnx", policy({5, 4, 4, 2}, ai::Activation::Tanh));
}

void writePpoConfigSeeds(const std::string& dir) {
  engine::writeFileAtomic(dir + "/defaults.toml",
                          "# every key at its default (ai::toToml(ai::PpoConfig{}))\n" + ai::toToml(ai::PpoConfig{}));
}

// ---- the mutations -------------------------------------------------------------------------------------------------

struct Seed {
  std::string name, bytes;
};

// the regular files of a folder, sorted by name (directory order is not portable); dot files (.gitkeep) left out
std::vector<Seed> readFolder(const std::string& dir) {
  std::vector<Seed> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (!e.is_regular_file() || name.empty() || name[0] == '.') continue;
    out.push_back({name, readBytes(e.path().string())});
  }
  std::sort(out.begin(), out.end(), [](const Seed& a, const Seed& b) { return a.name < b.name; });
  return out;
}

// Mutated copies of the seeds, reproducible from the seed alone: every choice is rng() % n (the standard
// distributions differ between standard libraries, mt19937_64 itself does not).
class Mutator {
 public:
  Mutator(uint64_t seed, const std::vector<Seed>& seeds, bool text) : rng_(seed), seeds_(seeds), text_(text) {}

  // a seed with 1-3 mutations stacked, resealed 3 times in 4 if reseal is set; *how names the seed and mutations
  std::string next(const std::function<void(std::string*)>& reseal, std::string* how) {
    const Seed& seed = seeds_[below(seeds_.size())];
    std::string s = seed.bytes;
    *how = seed.name + ":";
    for (uint64_t k = 1 + below(3); k > 0; --k) *how += " " + mutate(&s);
    if (reseal && below(4) != 0) {
      reseal(&s);
      *how += " resealed";
    }
    return s;
  }

 private:
  uint64_t below(uint64_t n) { return n == 0 ? 0 : rng_() % n; }
  size_t position(const std::string& s) { return size_t(below(s.size() + 1)); }  // 0..size: an insertion point

  std::string mutate(std::string* s) {
    // the generic byte mutations, then the format-aware ones weighted up (they get past the tokeniser more often)
    static const char* const kText[] = {"flip",       "byte",      "insert",        "erase",  "duplicate",
                                        "truncate",   "splice",    "number",        "number", "number",
                                        "line-twice", "line-gone", "lines-swapped", "rename", "rename"};
    static const char* const kBinary[] = {"flip",   "byte", "insert", "erase", "duplicate", "truncate",
                                          "splice", "word", "word",   "word",  "float"};
    const std::string op = text_ ? kText[below(std::size(kText))] : kBinary[below(std::size(kBinary))];
    const size_t at = position(*s);
    if (op == "flip") {
      if (s->empty()) return op + "(empty)";
      const size_t i = size_t(below(s->size()));
      (*s)[i] = char((*s)[i] ^ (1 << below(8)));
      return op + "@" + std::to_string(i);
    }
    if (op == "byte") {
      static const unsigned char kBytes[] = {0,   0xff, 0x7f, 0x80, '\n', '\r', '"', '\'', '[', ']', '{',
                                             '}', '=',  ' ',  '#',  '\\', '.',  '-', '0',  '9', 'e', ','};
      if (s->empty()) return op + "(empty)";
      const size_t i = size_t(below(s->size()));
      (*s)[i] = below(4) == 0 ? char(below(256)) : char(kBytes[below(std::size(kBytes))]);
      return op + "@" + std::to_string(i);
    }
    if (op == "insert") {
      static const char* const kTokens[] = {
          "\n[",  "\n[[x]]\n", "\"\"\"", "\\u0000", "#",   "=",        "]]",   "\xc3\x28", "\xef\xbb\xbf", "\t",
          "\r\n", "{",         "}",      " = 1\n",  "<a>", "</robot>", "<!--", "&amp;",    "&#0;",         "\x00\x00"};
      // nesting 3000 deep: a recursive parser without a depth limit overflows its stack
      static const char* const kNested[] = {"[", "{a=", "a=[", "<a>"};
      std::string bytes;
      const uint64_t kind = below(8);
      if (kind < 4) {
        for (uint64_t n = 1 + below(8); n > 0; --n) bytes += char(below(256));
      } else if (kind == 4) {
        for (const char* t = kNested[below(std::size(kNested))]; bytes.size() < 3000 * std::strlen(t);) bytes += t;
      } else {
        const char* t = kTokens[below(std::size(kTokens))];
        bytes = std::string(t, t[0] == '\x00' ? 2 : std::strlen(t));
      }
      s->insert(at, bytes);
      return op + "@" + std::to_string(at);
    }
    if (op == "erase") {
      const size_t n = size_t(1 + below(16));
      s->erase(at, n);
      return op + "@" + std::to_string(at);
    }
    if (op == "duplicate") {
      if (s->empty()) return op + "(empty)";
      const size_t from = size_t(below(s->size()));
      const std::string chunk = s->substr(from, size_t(1 + below(64)));
      s->insert(position(*s), chunk);
      return op + "@" + std::to_string(from);
    }
    if (op == "truncate") {
      s->resize(at);
      return op + "@" + std::to_string(at);
    }
    if (op == "splice") {
      const Seed& other = seeds_[below(seeds_.size())];
      const size_t from = size_t(below(other.bytes.size() + 1));
      *s = s->substr(0, at) + other.bytes.substr(from);
      return op + "@" + std::to_string(at) + "+" + other.name + "@" + std::to_string(from);
    }
    if (op == "number") return replaceNumber(s);
    if (op == "line-twice" || op == "line-gone" || op == "lines-swapped") return editLines(op, s);
    if (op == "rename") return renameWord(s);
    if (op == "word") return overwriteWord(s);
    return overwriteFloat(s);
  }

  // a number token replaced by an extreme or odd one
  std::string replaceNumber(std::string* s) {
    static const char* const kNumbers[] = {"1e308",
                                           "-1e308",
                                           "1e309",
                                           "nan",
                                           "inf",
                                           "-inf",
                                           "-1",
                                           "0",
                                           "-0",
                                           "0.5",
                                           "1e-320",
                                           "2147483647",
                                           "2147483648",
                                           "-2147483649",
                                           "4294967296",
                                           "9223372036854775807",
                                           "9223372036854775808",
                                           "18446744073709551616",
                                           "0x7fffffff",
                                           "1_000"};
    std::vector<std::pair<size_t, size_t>> numbers;  // start, length
    const auto isDigit = [](char c) { return c >= '0' && c <= '9'; };
    for (size_t i = 0; i < s->size();) {
      const bool starts =
          isDigit((*s)[i]) || (((*s)[i] == '-' || (*s)[i] == '.') && i + 1 < s->size() && isDigit((*s)[i + 1]));
      const bool inWord = i > 0 && (std::isalnum(static_cast<unsigned char>((*s)[i - 1])) || (*s)[i - 1] == '_');
      if (!starts || inWord) {
        ++i;
        continue;
      }
      size_t j = i + 1;
      while (j < s->size() && (isDigit((*s)[j]) || std::strchr(".eE+-_", (*s)[j]))) ++j;
      numbers.emplace_back(i, j - i);
      i = j;
    }
    if (numbers.empty()) return "number(none)";
    const auto [at, length] = numbers[below(numbers.size())];
    std::string replacement;
    switch (below(std::size(kNumbers) + 2)) {
      case std::size(kNumbers):
        replacement = std::string(100000, '9');  // a huge number
        break;
      case std::size(kNumbers) + 1:
        replacement = "\"" + std::string(100000, 'x') + "\"";  // a huge string
        break;
      default:
        replacement = kNumbers[below(std::size(kNumbers))];
    }
    s->replace(at, length, replacement);
    return "number@" + std::to_string(at) + "=" + replacement.substr(0, 24);
  }

  std::string editLines(const std::string& op, std::string* s) {
    std::vector<size_t> starts = {0};
    for (size_t i = 0; i < s->size(); ++i)
      if ((*s)[i] == '\n' && i + 1 < s->size()) starts.push_back(i + 1);
    auto lineAt = [&](size_t k) {
      const size_t end = k + 1 < starts.size() ? starts[k + 1] : s->size();
      return std::make_pair(starts[k], end - starts[k]);
    };
    const size_t k = size_t(below(starts.size()));
    const auto [at, length] = lineAt(k);
    std::string line = s->substr(at, length);
    if (!line.empty() && line.back() != '\n') line += '\n';
    if (op == "line-twice") {
      s->insert(at, line);
    } else if (op == "line-gone") {
      s->erase(at, length);
    } else {
      if (k + 1 >= starts.size()) return op + "(last)";
      const auto [nextAt, nextLength] = lineAt(k + 1);
      std::string next = s->substr(nextAt, nextLength);
      if (!next.empty() && next.back() != '\n') next += '\n';
      s->replace(at, length + nextLength, next + line);
    }
    return op + "@line" + std::to_string(k + 1);
  }

  // every occurrence of one word (a name, a key) changed alike: references to it stay consistent, so the input gets
  // past "unknown name" checks to the code that looks the name up (two parsers may read the change differently)
  std::string renameWord(std::string* s) {
    static const char* const kInfixes[] = {"\r",    "\n",   " ",        "\t", "&#233;", "&#13;",
                                           "&amp;", "\xe9", "\xc3\xa9", ".",  "\"",     "#"};
    const auto isWord = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
    size_t at = position(*s);
    while (at < s->size() && (!isWord((*s)[at]) || (at > 0 && isWord((*s)[at - 1])))) ++at;
    size_t end = at;
    while (end < s->size() && isWord((*s)[end])) ++end;
    if (end - at < 3) return "rename(none)";
    const std::string word = s->substr(at, end - at);
    const size_t cut = size_t(1 + below(word.size() - 1));
    const std::string renamed = word.substr(0, cut) + kInfixes[below(std::size(kInfixes))] + word.substr(cut);
    std::string out;
    size_t from = 0;
    for (size_t i = s->find(word); i != std::string::npos; i = s->find(word, i + word.size())) {
      const bool whole =
          (i == 0 || !isWord((*s)[i - 1])) && (i + word.size() == s->size() || !isWord((*s)[i + word.size()]));
      if (!whole) continue;
      out += s->substr(from, i - from) + renamed;
      from = i + word.size();
    }
    *s = out + s->substr(from);
    return "rename(" + word.substr(0, 24) + ")";
  }

  // a 4- or 8-byte little-endian field overwritten with a boundary value: counts, sizes, versions, lengths
  std::string overwriteWord(std::string* s) {
    static const uint64_t kWords[] = {0,          1,
                                      2,          3,
                                      23,         64,
                                      65,         4096,
                                      4097,       0x7fffffff,
                                      0x80000000, 0xffffffff,
                                      1ull << 30, (1ull << 30) + 1,
                                      1ull << 32, 1ull << 62,
                                      1ull << 63, ~0ull,
                                      ~0ull - 7,  0x0101010101010101ull};
    const size_t width = below(2) == 0 ? 4 : 8;
    if (s->size() < width) return "word(short)";
    // aligned to the field width 3 times in 4: the containers' fields sit at multiples of 4 from the payload start
    size_t at = size_t(below(s->size() - width + 1));
    if (below(4) != 0) at -= at % 4;
    const uint64_t v = kWords[below(std::size(kWords))];
    std::memcpy(s->data() + at, &v, width);
    return "word" + std::to_string(width * 8) + "@" + std::to_string(at) + "=" + std::to_string(v);
  }

  // a float or double overwritten with a value no training produces
  std::string overwriteFloat(std::string* s) {
    static const double kValues[] = {std::nan(""), INFINITY, -INFINITY, -1.0, 0.0, 1e38, 1e300, -1e-45, 5e-324};
    const double v = kValues[below(std::size(kValues))];
    const bool single = below(2) == 0;
    const size_t width = single ? 4 : 8;
    if (s->size() < width) return "float(short)";
    size_t at = size_t(below(s->size() - width + 1));
    at -= at % 4;
    if (single) {
      const float f = float(v);
      std::memcpy(s->data() + at, &f, 4);
    } else {
      std::memcpy(s->data() + at, &v, 8);
    }
    return std::string(single ? "f32" : "f64") + "@" + std::to_string(at) + "=" + std::to_string(v);
  }

  std::mt19937_64 rng_;
  const std::vector<Seed>& seeds_;
  bool text_;
};

// ---- crash, hang and memory guards ---------------------------------------------------------------------------------

// The input being read. A crash or a hang ends the process before the test can report it, so the signal handler
// and the watchdog write this input out first (tests/fuzz/README.md: turning it into a regression file).
std::atomic<const char*> gInputData{nullptr};
std::atomic<size_t> gInputSize{0};
std::atomic<int64_t> gInputStartNs{0};  // steady clock when the read began; 0 while no input is being read
char gDumpPath[1024] = {};

int64_t nowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void writeError(const char* text) { [[maybe_unused]] const ssize_t n = ::write(2, text, std::strlen(text)); }

// only async-signal-safe calls: it also runs in the signal handler
void dumpInput(const char* what) {
  const char* data = gInputData.load();
  if (!data) return;
  const int fd = ::open(gDumpPath, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd >= 0) {
    [[maybe_unused]] const ssize_t n = ::write(fd, data, gInputSize.load());
    ::close(fd);
  }
  writeError("\n[ fuzz     ] the reader ");
  writeError(what);
  writeError(" on an input, written to ");
  writeError(gDumpPath);
  writeError(" (tests/fuzz/README.md: adding a regression input)\n");
}

extern "C" void onFatalSignal(int signal) {
  dumpInput("crashed");
  ::signal(signal, SIG_DFL);
  ::raise(signal);
}

// While it lives: fatal signals dump the input, a watchdog ends a read that takes longer than kHangLimit, and the
// address space may grow by kAddressBudget only (Linux overcommits: an allocation of gigabytes that is never
// touched would succeed unnoticed; under the limit it throws std::bad_alloc, a finding).
class Guard {
 public:
  explicit Guard(const std::string& folder) {
    const std::string path = testing::TempDir() + "treelearn-fuzz-" + folder + "-last-input";
    std::snprintf(gDumpPath, sizeof gDumpPath, "%s", path.c_str());
    for (int s : kSignals) {
      struct sigaction a = {};
      a.sa_handler = onFatalSignal;
      sigemptyset(&a.sa_mask);
      ::sigaction(s, &a, &previous_[index(s)]);
    }
    watchdog_ = std::thread([this] { watch(); });
#ifndef TREELEARN_FUZZ_ASAN
    limited_ = ::getrlimit(RLIMIT_AS, &limit_) == 0 && limitAddressSpace();
#endif
  }
  ~Guard() {
    if (limited_) ::setrlimit(RLIMIT_AS, &limit_);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    watchdog_.join();
    for (int s : kSignals) ::sigaction(s, &previous_[index(s)], nullptr);
  }
  Guard(const Guard&) = delete;
  Guard& operator=(const Guard&) = delete;

 private:
  static constexpr int kSignals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};
  static size_t index(int s) { return size_t(std::find(std::begin(kSignals), std::end(kSignals), s) - kSignals); }

  bool limitAddressSpace() {
    std::ifstream status("/proc/self/status");
    uint64_t vmKb = 0;
    for (std::string line; std::getline(status, line);)
      if (line.rfind("VmSize:", 0) == 0) vmKb = std::strtoull(line.c_str() + 7, nullptr, 10);
    if (vmKb == 0) return false;
    struct rlimit budget = limit_;
    budget.rlim_cur = rlim_t(vmKb * 1024 + kAddressBudget);
    if (limit_.rlim_max != RLIM_INFINITY) budget.rlim_cur = std::min(budget.rlim_cur, limit_.rlim_max);
    return ::setrlimit(RLIMIT_AS, &budget) == 0;
  }

  void watch() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!wake_.wait_for(lock, std::chrono::milliseconds(100), [this] { return stop_; })) {
      const int64_t started = gInputStartNs.load();
      if (started != 0 && nowNs() - started > std::chrono::nanoseconds(kHangLimit).count()) {
        dumpInput("hung (more than 10 s)");
        ::signal(SIGABRT, SIG_DFL);
        std::abort();
      }
    }
  }

  struct sigaction previous_[std::size(kSignals)] = {};
  struct rlimit limit_ = {};
  bool limited_ = false;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread watchdog_;
};

// ---- running the inputs --------------------------------------------------------------------------------------------

/// Reads one input; returns "" when it loaded (*loaded) or was refused properly, else what went wrong.
std::string misbehaviour(const Reader& r, const std::string& bytes, bool* loaded) {
  *loaded = false;
  gInputData = bytes.data();
  gInputSize = bytes.size();
  gInputStartNs = nowNs();
  std::string what;
  try {
    r.load(bytes);
    *loaded = true;
  } catch (const engine::Error& e) {
    const std::string message = e.what();
    if (message.empty())
      what = "engine::Error with an empty message";
    else if (message.find(r.named) == std::string::npos)
      what = "engine::Error that does not name '" + r.named + "': " + message;
  } catch (const std::exception& e) {
    int status = 0;
    char* type = abi::__cxa_demangle(typeid(e).name(), nullptr, nullptr, &status);
    what = std::string("not engine::Error but ") + (status == 0 ? type : typeid(e).name()) + ": " + e.what();
    std::free(type);
  } catch (...) {
    what = "an exception that is not a std::exception";
  }
  gInputStartNs = 0;
  gInputData = nullptr;
  return what;
}

int iterationFactor() {
  const char* v = std::getenv("TREELEARN_FUZZ_ITERATIONS");
  const long n = v ? std::strtol(v, nullptr, 10) : 1;
  return n >= 1 && n <= 1000000 ? int(n) : 1;
}

uint64_t seedOffset() {
  const char* v = std::getenv("TREELEARN_FUZZ_SEED");
  return v ? std::strtoull(v, nullptr, 10) : 0;
}

// Every seed loads (a mutation of an input refused outright tests little), then the mutated inputs.
void fuzz(const Reader& r) {
  const std::vector<Seed> seeds = readFolder(kFuzzDir + "/corpus/" + r.folder);
  ASSERT_FALSE(seeds.empty()) << "no seed files in tests/fuzz/corpus/" << r.folder;
  Guard guard(r.folder);
  for (const Seed& s : seeds) {
    bool loaded = false;
    const std::string what = misbehaviour(r, s.bytes, &loaded);
    EXPECT_TRUE(loaded) << "seed " << s.name << " does not load" << (what.empty() ? "" : ": " + what);
  }

  Mutator mutator(r.seed ^ seedOffset(), seeds, r.text);
  const int n = r.iterations * iterationFactor();
  int loaded = 0, refused = 0, known = 0, failures = 0;
  int64_t slowestNs = 0;
  std::string slowest;
  const int64_t start = nowNs();
  for (int i = 0; i < n; ++i) {
    std::string how;
    const std::string input = mutator.next(r.reseal, &how);
    bool ok = false;
    const int64_t t0 = nowNs();
    const std::string what = misbehaviour(r, input, &ok);
    if (nowNs() - t0 > slowestNs) {
      slowestNs = nowNs() - t0;
      slowest = how;
    }
    if (what.empty()) {
      ++(ok ? loaded : refused);
      continue;
    }
    if (const KnownFinding* k = knownFindingMisbehaviour(r.folder, what)) {
      if (known++ == 0)
        std::printf("[ fuzz     ] %s: known finding (regressions/%s/%s) at input %d (%s)\n", r.folder.c_str(),
                    k->folder, k->file, i, how.c_str());
      continue;
    }
    if (failures++ < 5) {
      const std::string path = testing::TempDir() + "treelearn-fuzz-" + r.folder + "-input-" + std::to_string(i);
      writeBytes(path, input);
      ADD_FAILURE() << r.folder << " input " << i << " (" << how << "): " << what << "\n  input written to " << path
                    << " (tests/fuzz/README.md: adding a regression input)";
    }
  }
  const double seconds = double(nowNs() - start) * 1e-9;
  std::printf(
      "[ fuzz     ] %s: %d mutated inputs (%d loaded, %d refused, %d known findings, %d failures) in %.2f s; "
      "slowest %.1f ms (%s)\n",
      r.folder.c_str(), n, loaded, refused, known, failures, seconds, double(slowestNs) * 1e-6,
      slowest.substr(0, 100).c_str());
  EXPECT_EQ(failures, 0) << "of " << n << " mutated inputs";
}

// Every file in regressions/FOLDER is read again; known findings are skipped until their reader is fixed.
void replayRegressions(const Reader& r) {
  const std::vector<Seed> files = readFolder(kFuzzDir + "/regressions/" + r.folder);
  Guard guard(r.folder);
  std::vector<std::string> skipped;
  for (const Seed& f : files) {
    if (knownFindingFile(r.folder, f.name)) {
      skipped.push_back(f.name);
      continue;
    }
    bool loaded = false;
    EXPECT_EQ(misbehaviour(r, f.bytes, &loaded), "") << "regressions/" << r.folder << "/" << f.name;
  }
  if (!skipped.empty()) {
    std::string list;
    for (const std::string& s : skipped) list += " " + s;
    GTEST_SKIP() << "known findings skipped until the reader is fixed (kKnownFindings):" << list;
  }
}

// ---- the tests: two per reader -------------------------------------------------------------------------------------

TEST(FuzzLevel, MutatedLevelsLoadOrAreRefusedWithTheirFileNamed) { fuzz(levelReader()); }
TEST(FuzzLevel, RegressionInputsLoadOrAreRefusedWithTheirFileNamed) { replayRegressions(levelReader()); }

TEST(FuzzKeyScript, MutatedKeyScriptsLoadOrAreRefusedWithTheirFileNamed) { fuzz(keyScriptReader()); }
TEST(FuzzKeyScript, RegressionInputsLoadOrAreRefusedWithTheirFileNamed) { replayRegressions(keyScriptReader()); }

TEST(FuzzReplay, MutatedReplaysLoadOrAreRefusedWithTheirFileNamed) { fuzz(replayReader()); }
TEST(FuzzReplay, RegressionInputsLoadOrAreRefusedWithTheirFileNamed) { replayRegressions(replayReader()); }

TEST(FuzzSkillTree, MutatedSkillTreesLoadOrAreRefusedWithTheirFileNamed) {
  const TempFolder dir("skill_tree");
  fuzz(skillTreeReader(dir.path));
}
TEST(FuzzSkillTree, RegressionInputsLoadOrAreRefusedWithTheirFileNamed) {
  const TempFolder dir("skill_tree");
  replayRegressions(skillTreeReader(dir.path));
}

TEST(FuzzPpoConfig, MutatedPpoConfigsLoadOrAreRefusedWithTheirFileNamed) {
  if (writeSeedsRequested()) writePpoConfigSeeds(kFuzzDir + "/corpus/ppo_config");
  fuzz(ppoConfigReader());
}
TEST(FuzzPpoConfig, RegressionInputsLoadOrAreRefusedWithTheirFileNamed) { replayRegressions(ppoConfigReader()); }

TEST(FuzzRobotModel, MutatedRobotConfigsLoadOrAreRefusedWithTheirFileNamed) {
  const TempFolder dir("robot_model");
  fuzz(robotModelReader(dir.path));
}
TEST(FuzzRobotModel, RegressionInputsLoadOrAreRefusedWithTheirFileNamed) {
  const TempFolder dir("robot_model");
  replayRegressions(robotModelReader(dir.path));
}

TEST(FuzzUrdf, MutatedUrdfsLoadOrAreRefusedWithTheirFileNamed) { fuzz(urdfReader()); }
TEST(FuzzUrdf, RegressionInputsLoadOrAreRefusedWithTheirFileNamed) { replayRegressions(urdfReader()); }

TEST(FuzzOnnx, MutatedOnnxPoliciesLoadOrAreRefusedWithTheirFileNamed) {
  if (writeSeedsRequested()) writeOnnxSeeds(kFuzzDir + "/corpus/onnx");
  const TempFolder dir("onnx");
  fuzz(onnxReader(dir.path));
}
TEST(FuzzOnnx, RegressionInputsLoadOrAreRefusedWithTheirFileNamed) {
  const TempFolder dir("onnx");
  replayRegressions(onnxReader(dir.path));
}

TEST(FuzzPolicyFile, MutatedPolicyFilesLoadOrAreRefusedWithTheirFileNamed) {
  if (writeSeedsRequested()) writePolicySeeds(kFuzzDir + "/corpus/policy");
  const TempFolder dir("policy");
  fuzz(policyReader(dir.path));
}
TEST(FuzzPolicyFile, RegressionInputsLoadOrAreRefusedWithTheirFileNamed) {
  const TempFolder dir("policy");
  replayRegressions(policyReader(dir.path));
}

TEST(FuzzCheckpoint, MutatedCheckpointsLoadOrAreRefusedWithTheirFileNamed) {
  if (writeSeedsRequested()) writeCheckpointSeeds(kFuzzDir + "/corpus/checkpoint");
  const TempFolder dir("checkpoint");
  fuzz(checkpointReader(dir.path));
}
TEST(FuzzCheckpoint, RegressionInputsLoadOrAreRefusedWithTheirFileNamed) {
  const TempFolder dir("checkpoint");
  replayRegressions(checkpointReader(dir.path));
}

TEST(FuzzEntries, MutatedEntryFilesLoadOrAreRefusedWithTheirFileNamed) { fuzz(entriesReader()); }
TEST(FuzzEntries, RegressionInputsLoadOrAreRefusedWithTheirFileNamed) { replayRegressions(entriesReader()); }

}  // namespace
