// error.h — the one error type readers and loaders throw.
// A Error carries a complete message: "file:line: what is wrong" (or "file: byte N: ...").
// apps/ catches it, prints it and exits non-zero; nothing below apps/ prints or exits.
#pragma once

#include <stdexcept>
#include <string>

namespace engine {

/// An input problem the user can fix (bad file, bad argument). what() is the full, located message.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// Builds "file:line: message" (line <= 0 leaves the line out).
std::string located(const std::string& file, int line, const std::string& message);

}  // namespace engine
