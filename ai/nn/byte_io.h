// byte_io.h — little binary writer/reader for checkpoints: fixed-width little-endian scalars, strings and
// float/double tensors with their shapes. The reader throws engine::Error "what: byte N: ..." on truncation
// or a shape mismatch. Assumes a little-endian host (x86-64, AArch64), as everything else here does.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>

#include "ai/nn/mlp.h"

namespace ai {

/// Appends values to a byte string.
class ByteWriter {
 public:
  /// Raw bytes, no length prefix.
  void bytes(const void* data, size_t n) { out_.append(static_cast<const char*>(data), n); }
  /// Fixed-width little-endian scalars: 1, 4, 8, 8, 4 and 8 bytes.
  void u8(uint8_t v) { bytes(&v, 1); }
  void u32(uint32_t v) { bytes(&v, 4); }
  void u64(uint64_t v) { bytes(&v, 8); }
  void i64(int64_t v) { bytes(&v, 8); }
  void f32(float v) { bytes(&v, 4); }
  void f64(double v) { bytes(&v, 8); }
  /// Length-prefixed (u64) string.
  void str(std::string_view s);
  /// rows, cols (u64 each), then the column-major data.
  void matrix(const Eigen::MatrixXf& m);
  /// size (u64), then the data.
  void vector(const Eigen::VectorXf& v);
  void vector(const Eigen::VectorXd& v);
  /// Activation, layer count, then each W and b.
  void mlp(const MlpWeights& w);
  /// The bytes written so far.
  const std::string& data() const { return out_; }
  /// Moves the bytes out (the writer is empty afterwards).
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

/// Reads values back in the order they were written. what names the source in error messages.
class ByteReader {
 public:
  /// data must outlive the reader.
  ByteReader(std::string_view data, std::string what) : data_(data), what_(std::move(what)) {}
  /// Copies the next n bytes.
  void bytes(void* out, size_t n);
  /// The counterparts of ByteWriter's methods, in the same formats.
  uint8_t u8();
  uint32_t u32();
  uint64_t u64();
  int64_t i64();
  float f32();
  double f64();
  std::string str();
  Eigen::MatrixXf matrix();
  Eigen::VectorXf vectorF();
  Eigen::VectorXd vectorD();
  MlpWeights mlp();
  /// Bytes consumed so far.
  size_t offset() const { return pos_; }
  /// True when every byte was consumed.
  bool atEnd() const { return pos_ == data_.size(); }
  /// Throws engine::Error "what: byte <offset>: message".
  [[noreturn]] void fail(const std::string& message) const;

 private:
  uint64_t count(uint64_t elementSize);  // reads a u64 element count and checks it fits in the rest
  std::string_view data_;
  std::string what_;
  size_t pos_ = 0;
};

}  // namespace ai
