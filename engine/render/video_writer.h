// video_writer.h — streams RGBA frames into an H.264 MP4 through an ffmpeg child process.
// Needs the ffmpeg binary on PATH (Debian package ffmpeg). The video is written to <path>.tmp.mp4 and
// renamed into place by finish(), so the final path never holds a half-written file.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <cstdio>
#include <string>

namespace engine {

/// An MP4 being encoded: construct, addFrame() per frame, then finish().
class VideoWriter {
 public:
  /// Starts ffmpeg for width x height (both even) RGBA frames at fps frames per second, writing mp4Path.
  /// Throws engine::Error if ffmpeg is not on PATH, the sizes are invalid or the output folder is missing.
  VideoWriter(const std::string& mp4Path, int width, int height, int fps);
  /// Without finish(): stops ffmpeg and removes the temporary file.
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  /// Sends one frame: width*height*4 bytes, RGBA, rows top-down. Throws engine::Error if ffmpeg failed.
  void addFrame(const uint8_t* rgba);
  /// Ends the stream, waits for ffmpeg and moves the video to its final path. Throws engine::Error on failure
  /// (the temporary file is removed).
  void finish();
  /// Frames sent so far.
  int frameCount() const { return frames_; }

 private:
  void stopChild(bool kill) noexcept;  // closes the input, (optionally kills,) reaps ffmpeg; sets exitStatus_
  std::string childErrors() const;     // ffmpeg's stderr, trimmed
  [[noreturn]] void fail(const std::string& what);  // cleans up and throws engine::Error

  std::string path_;
  std::string tempPath_;
  int width_;
  int height_;
  int frames_ = 0;
  pid_t pid_ = -1;               // ffmpeg, -1 when not running
  int input_ = -1;               // our end of ffmpeg's stdin (a socket, so writes can use MSG_NOSIGNAL)
  int exitStatus_ = 0;           // waitpid status after stopChild
  std::FILE* errors_ = nullptr;  // anonymous temp file holding ffmpeg's stderr
  bool closed_ = false;          // finish() done or failed
};

}  // namespace engine
