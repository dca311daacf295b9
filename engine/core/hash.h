// hash.h — 64-bit FNV-1a, used for content hashes (levels, models) and simulation state hashes.
// Fast enough for a state hash every few ticks; not cryptographic.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace engine {

/// Incremental FNV-1a (64 bit). Feed bytes or trivially copyable values; value() is the hash so far.
class Hasher {
 public:
  void bytes(const void* data, size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) {
      h_ ^= p[i];
      h_ *= 1099511628211ull;
    }
  }
  template <typename T>
  void value(const T& v) {
    bytes(&v, sizeof(T));
  }
  uint64_t value() const { return h_; }

 private:
  uint64_t h_ = 14695981039346656037ull;
};

/// FNV-1a of a byte string.
inline uint64_t hashBytes(std::string_view s) {
  Hasher h;
  h.bytes(s.data(), s.size());
  return h.value();
}

/// 16 lowercase hex digits.
std::string toHex(uint64_t v);

/// Parses exactly 16 hex digits; returns false if s is not that.
bool parseHex(std::string_view s, uint64_t* out);

}  // namespace engine
