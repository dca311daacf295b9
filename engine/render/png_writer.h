// png_writer.h — fast PNG output for rendered frames (libpng, zlib level 1, SUB filter).
// The file is encoded in memory and written atomically, so a failed write leaves nothing behind.
#pragma once

#include <cstdint>
#include <string>

namespace engine {

/// Writes an RGBA8 image (width*height*4 bytes, rows top-down) as a PNG at path; keepAlpha = false stores
/// RGB (alpha dropped). Atomic (temp file + rename). Throws engine::Error naming the file on failure.
void writePng(const std::string& path, const uint8_t* rgba, int width, int height, bool keepAlpha = false);

}  // namespace engine
