// file_io.h — whole-file reads and atomic writes (temp file in the same folder, then rename),
// so an interrupted or failed write never leaves a half-written output behind.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace engine {

/// Size caps by format: a reader refuses a larger file before reading it (a mistyped path to a disk image, or a
/// file that grows without end, is found out at once instead of when memory runs out).
constexpr int64_t kMaxTextFileBytes = int64_t(16) << 20;   ///< levels, trees, robot files, key scripts, replays
constexpr int64_t kMaxDataFileBytes = int64_t(256) << 20;  ///< recorded entry states, training logs
constexpr int64_t kMaxModelFileBytes = int64_t(1) << 30;   ///< policies, checkpoints, ONNX models

/// Reads a whole file as bytes. Throws engine::Error naming the file if it cannot be read, is not a regular file
/// (a folder, a FIFO, a device such as /dev/zero: none of them ends like a file) or is larger than maxBytes.
std::string readFile(const std::string& path, int64_t maxBytes = kMaxTextFileBytes);

/// Writes bytes to path atomically: writes path.tmp.<pid>, fsyncs, renames. Throws engine::Error on failure
/// (the temp file is removed and any existing file at path is left untouched).
void writeFileAtomic(const std::string& path, std::string_view bytes);

/// Removes the temps (NAME.tmp.PID) that writeFileAtomic left in `dir` when a process was killed while writing;
/// returns how many. This process's own are kept.
int removeStaleTemps(const std::string& dir);

/// A project file by its path relative to the source tree: as given if it exists from the working directory,
/// else under the source tree this binary was built from (so build/treelearn works from any folder).
std::string projectFile(const std::string& relative);

/// Creates a directory and its parents if missing. Throws engine::Error on failure.
void makeDirectories(const std::string& path);

}  // namespace engine
