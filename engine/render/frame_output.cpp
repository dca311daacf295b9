// frame_output.cpp — renders snapshots and fans the pixels out to PNG files and the video pipe.
#include "engine/render/frame_output.h"

#include <cstdio>

#include "engine/core/file_io.h"
#include "engine/render/png_writer.h"
#include "engine/render/renderer.h"
#include "engine/render/video_writer.h"

namespace engine {

FrameOutput::FrameOutput(const std::string& framesDir, const std::string& videoPath, int width, int height, int fps)
    : framesDir_(framesDir) {
  if (!framesDir.empty()) makeDirectories(framesDir);
  if (!videoPath.empty()) video_ = std::make_unique<VideoWriter>(videoPath, width, height, fps);
  renderer_ = std::make_unique<Renderer>(width, height);
}

FrameOutput::~FrameOutput() = default;

void FrameOutput::add(const SceneSnapshot& snapshot) {
  renderer_->render(snapshot);
  if (!framesDir_.empty()) {
    char name[32];
    std::snprintf(name, sizeof name, "/frame_%06d.png", frames_);
    writePng(framesDir_ + name, renderer_->rgba(), renderer_->width(), renderer_->height());
  }
  if (video_) video_->addFrame(renderer_->rgba());
  ++frames_;
}

void FrameOutput::finish() {
  if (video_) video_->finish();
}

}  // namespace engine
