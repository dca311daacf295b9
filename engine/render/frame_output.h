// frame_output.h — where rendered frames go: numbered PNGs in a folder (--frames DIR) and/or an MP4
// piped through ffmpeg (--video FILE.mp4). Owns the Renderer; feed it snapshots, then finish().
#pragma once

#include <memory>
#include <string>

#include "engine/render/scene_snapshot.h"

namespace engine {

class Renderer;
class VideoWriter;

class FrameOutput {
 public:
  /// framesDir or videoPath may be empty (not wanted). Creates framesDir. Throws engine::Error.
  FrameOutput(const std::string& framesDir, const std::string& videoPath, int width, int height, int fps);
  ~FrameOutput();

  /// Renders one frame and writes it to every output.
  void add(const SceneSnapshot& snapshot);

  /// Completes the video (atomic rename into place). Throws engine::Error if ffmpeg failed.
  void finish();

  int frames() const { return frames_; }

 private:
  std::string framesDir_;
  std::unique_ptr<Renderer> renderer_;
  std::unique_ptr<VideoWriter> video_;
  int frames_ = 0;
};

}  // namespace engine
