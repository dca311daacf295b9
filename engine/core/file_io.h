// file_io.h — whole-file reads and atomic writes (temp file in the same folder, then rename),
// so an interrupted or failed write never leaves a half-written output behind.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace engine {

/// Reads a whole file as bytes. Throws engine::Error naming the file if it cannot be read.
std::string readFile(const std::string& path);

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
