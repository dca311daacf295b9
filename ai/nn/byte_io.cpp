// byte_io.cpp — binary writer/reader for checkpoints and policy files.
#include "ai/nn/byte_io.h"

#include <cstring>

#include "engine/core/error.h"

namespace ai {

void ByteWriter::str(std::string_view s) {
  u64(s.size());
  bytes(s.data(), s.size());
}

void ByteWriter::matrix(const Eigen::MatrixXf& m) {
  u64(uint64_t(m.rows()));
  u64(uint64_t(m.cols()));
  bytes(m.data(), sizeof(float) * size_t(m.size()));
}

void ByteWriter::vector(const Eigen::VectorXf& v) {
  u64(uint64_t(v.size()));
  bytes(v.data(), sizeof(float) * size_t(v.size()));
}

void ByteWriter::vector(const Eigen::VectorXd& v) {
  u64(uint64_t(v.size()));
  bytes(v.data(), sizeof(double) * size_t(v.size()));
}

void ByteWriter::mlp(const MlpWeights& w) {
  u8(uint8_t(w.activation));
  u32(uint32_t(w.layers()));
  for (int k = 0; k < w.layers(); ++k) {
    matrix(w.W[size_t(k)]);
    vector(w.b[size_t(k)]);
  }
}

void ByteReader::fail(const std::string& message) const {
  throw engine::Error(what_ + ": byte " + std::to_string(pos_) + ": " + message);
}

void ByteReader::bytes(void* out, size_t n) {
  if (n > data_.size() - pos_) fail("truncated (needs " + std::to_string(n) + " more bytes)");
  if (n > 0) std::memcpy(out, data_.data() + pos_, n);
  pos_ += n;
}

uint8_t ByteReader::u8() {
  uint8_t v;
  bytes(&v, 1);
  return v;
}
uint32_t ByteReader::u32() {
  uint32_t v;
  bytes(&v, 4);
  return v;
}
uint64_t ByteReader::u64() {
  uint64_t v;
  bytes(&v, 8);
  return v;
}
int64_t ByteReader::i64() {
  int64_t v;
  bytes(&v, 8);
  return v;
}
float ByteReader::f32() {
  float v;
  bytes(&v, 4);
  return v;
}
double ByteReader::f64() {
  double v;
  bytes(&v, 8);
  return v;
}

uint64_t ByteReader::count(uint64_t elementSize) {
  const uint64_t n = u64();
  if (elementSize > 0 && n > (data_.size() - pos_) / elementSize)
    fail("element count " + std::to_string(n) + " exceeds the data");
  return n;
}

std::string ByteReader::str() {
  const uint64_t n = count(1);
  std::string s(size_t(n), '\0');
  bytes(s.data(), size_t(n));
  return s;
}

Eigen::MatrixXf ByteReader::matrix() {
  const uint64_t rows = u64();
  const uint64_t cols = count(0);
  if (rows > (1u << 30) || cols > (1u << 30) || (rows * cols) > (data_.size() - pos_) / sizeof(float))
    fail("matrix " + std::to_string(rows) + " x " + std::to_string(cols) + " exceeds the data");
  Eigen::MatrixXf m(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  bytes(m.data(), sizeof(float) * size_t(m.size()));
  return m;
}

Eigen::VectorXf ByteReader::vectorF() {
  Eigen::VectorXf v(static_cast<Eigen::Index>(count(sizeof(float))));
  bytes(v.data(), sizeof(float) * size_t(v.size()));
  return v;
}

Eigen::VectorXd ByteReader::vectorD() {
  Eigen::VectorXd v(static_cast<Eigen::Index>(count(sizeof(double))));
  bytes(v.data(), sizeof(double) * size_t(v.size()));
  return v;
}

MlpWeights ByteReader::mlp() {
  MlpWeights w;
  const uint8_t act = u8();
  if (act > uint8_t(Activation::Tanh)) fail("unknown activation " + std::to_string(act));
  w.activation = Activation(act);
  const uint32_t layers = u32();
  if (layers > 64) fail("implausible layer count " + std::to_string(layers));
  for (uint32_t k = 0; k < layers; ++k) {
    w.W.push_back(matrix());
    w.b.push_back(vectorF());
    if (w.b.back().size() != w.W.back().rows()) fail("layer " + std::to_string(k) + ": bias size does not match W");
    if (k > 0 && w.W[k].cols() != w.W[k - 1].rows()) fail("layer " + std::to_string(k) + ": input size does not match");
  }
  return w;
}

}  // namespace ai
