// png_writer.cpp — libpng encoding into memory (setjmp error handling kept inside one C-style
// function), then engine::writeFileAtomic.
#include "engine/render/png_writer.h"

#include <png.h>

#include <csetjmp>
#include <cstring>
#include <string>
#include <vector>

#include "engine/core/error.h"
#include "engine/core/file_io.h"

namespace engine {

namespace {

// what the libpng callbacks write to; lives outside the setjmp frame
struct PngSink {
  std::string bytes;
  char message[256] = {0};
};

void appendBytes(png_structp png, png_bytep data, png_size_t length) {
  auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
  try {
    sink->bytes.append(reinterpret_cast<const char*>(data), length);
  } catch (...) {
    png_error(png, "out of memory");
  }
}

void flushNothing(png_structp) {}

void onPngError(png_structp png, png_const_charp message) {
  auto* sink = static_cast<PngSink*>(png_get_error_ptr(png));
  std::strncpy(sink->message, message, sizeof(sink->message) - 1);
  png_longjmp(png, 1);
}

void onPngWarning(png_structp, png_const_charp) {}

// encodes into sink->bytes; returns false (with sink->message) on a libpng error.
// rows must stay valid; no C++ objects with destructors live in this frame across setjmp
bool encodePng(PngSink* sink, png_bytep* rows, int width, int height, bool keepAlpha) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, sink, onPngError, onPngWarning);
  if (!png) {
    std::strcpy(sink->message, "cannot create the libpng writer");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    std::strcpy(sink->message, "cannot create the libpng info struct");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, sink, appendBytes, flushNothing);
  // speed over size: zlib level 1 and the SUB filter are ~3x faster than the defaults
  png_set_compression_level(png, 1);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               keepAlpha ? PNG_COLOR_TYPE_RGB_ALPHA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (!keepAlpha) png_set_filler(png, 0, PNG_FILLER_AFTER);  // input rows are RGBA: strip the 4th byte
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

void writePng(const std::string& path, const uint8_t* rgba, int width, int height, bool keepAlpha) {
  if (!rgba || width <= 0 || height <= 0)
    throw Error(path + ": cannot write PNG: invalid image " + std::to_string(width) + "x" + std::to_string(height));

  std::vector<png_bytep> rows(static_cast<size_t>(height));
  const size_t rowBytes = static_cast<size_t>(width) * 4;
  for (int y = 0; y < height; ++y) rows[y] = const_cast<png_bytep>(rgba + static_cast<size_t>(y) * rowBytes);

  PngSink sink;
  sink.bytes.reserve(rowBytes * static_cast<size_t>(height) / 4);
  if (!encodePng(&sink, rows.data(), width, height, keepAlpha))
    throw Error(path + ": cannot encode PNG: " + sink.message);
  writeFileAtomic(path, sink.bytes);
}

}  // namespace engine
