// renderer.h — off-screen software renderer (OSMesa, fixed-function GL) for SceneSnapshot frames.
// Depends on OSMesa/GL only in renderer.cpp. One Renderer owns one GL context; use it from one thread
// at a time (render() makes its context current on the calling thread).
// Limitations: no shadows, no anti-aliasing; the ground Plane is drawn as a finite checkered square.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "engine/render/camera.h"
#include "engine/render/scene_snapshot.h"

namespace engine {

/// Draws SceneSnapshots into an RGBA8 image held in memory.
class Renderer {
 public:
  /// Creates an OSMesa context (RGBA, 24-bit depth) of width x height pixels. Throws engine::Error on failure.
  Renderer(int width, int height);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Draws one frame (shapes, ground, HUD) with the snapshot's follow camera; the result is in rgba().
  void render(const SceneSnapshot& snapshot);

  /// The last frame: width*height*4 bytes, RGBA, rows top-down. Valid until the next render() or destruction.
  const uint8_t* rgba() const { return image_.data(); }
  /// Image width [px].
  int width() const { return width_; }
  /// Image height [px].
  int height() const { return height_; }
  /// The camera used by the last render() (for projectToPixel).
  const Camera& lastCamera() const { return camera_; }

 private:
  struct Gl;  // GL context, buffers and meshes; defined in renderer.cpp

  int width_;
  int height_;
  Camera camera_;
  std::vector<uint8_t> image_;  // top-down copy of the OSMesa buffer
  std::unique_ptr<Gl> gl_;
};

}  // namespace engine
