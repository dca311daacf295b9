// video_writer.cpp — ffmpeg child via posix_spawn; frames go over a Unix socket written with
// MSG_NOSIGNAL, so a dead ffmpeg gives EPIPE (reported as engine::Error) instead of SIGPIPE.
#include "engine/render/video_writer.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include "engine/core/error.h"

extern char** environ;

namespace engine {

namespace {

// the full path of an executable found on PATH, or "" if there is none
std::string findOnPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
  size_t start = 0;
  while (start <= dirs.size()) {
    size_t end = dirs.find(':', start);
    if (end == std::string::npos) end = dirs.size();
    std::string dir = dirs.substr(start, end - start);
    if (dir.empty()) dir = ".";
    const std::string candidate = dir + "/" + name;
    struct stat st {};
    if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(candidate.c_str(), X_OK) == 0)
      return candidate;
    start = end + 1;
  }
  return "";
}

}  // namespace

VideoWriter::VideoWriter(const std::string& mp4Path, int width, int height, int fps)
    : path_(mp4Path), tempPath_(mp4Path + ".tmp.mp4"), width_(width), height_(height) {
  const std::string ffmpeg = findOnPath("ffmpeg");
  if (ffmpeg.empty()) throw Error("ffmpeg not found: install it with scripts/setup.sh (Debian package ffmpeg)");
  if (width <= 0 || height <= 0 || width % 2 != 0 || height % 2 != 0)
    throw Error(mp4Path + ": video size must be positive and even, got " + std::to_string(width) + "x" +
                std::to_string(height));
  if (fps <= 0) throw Error(mp4Path + ": video fps must be positive, got " + std::to_string(fps));

  // fail early and clearly if the output folder is missing or read-only
  std::filesystem::path folder = std::filesystem::path(mp4Path).parent_path();
  if (folder.empty()) folder = ".";
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec))
    throw Error(mp4Path + ": cannot write video: folder " + folder.string() + " does not exist");
  if (::access(folder.c_str(), W_OK) != 0)
    throw Error(mp4Path + ": cannot write video: folder " + folder.string() + " is not writable");

  errors_ = std::tmpfile();
  if (!errors_) throw Error(mp4Path + ": cannot create a temporary file for ffmpeg messages");
  int sockets[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sockets) != 0) {
    std::fclose(errors_);
    throw Error(mp4Path + ": cannot create a socket to ffmpeg: " + std::strerror(errno));
  }

  const std::vector<std::string> args = {ffmpeg,      "-y",
                                         "-loglevel", "error",
                                         "-f",        "rawvideo",
                                         "-pix_fmt",  "rgba",
                                         "-s",        std::to_string(width) + "x" + std::to_string(height),
                                         "-r",        std::to_string(fps),
                                         "-i",        "-",
                                         "-c:v",      "libx264",
                                         "-pix_fmt",  "yuv420p",
                                         "-preset",   "veryfast",
                                         "-crf",      "23",
                                         "-movflags", "+faststart",
                                         tempPath_};
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);

  // child: stdin = the socket, stdout = /dev/null, stderr = the message file
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, sockets[1], STDIN_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, fileno(errors_), STDERR_FILENO);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, ffmpeg.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(sockets[1]);
  if (rc != 0) {
    ::close(sockets[0]);
    std::fclose(errors_);
    throw Error(mp4Path + ": cannot start " + ffmpeg + ": " + std::strerror(rc));
  }
  pid_ = pid;
  input_ = sockets[0];
}

VideoWriter::~VideoWriter() {
  if (pid_ > 0) {
    stopChild(true);
    ::unlink(tempPath_.c_str());
  }
  if (errors_) std::fclose(errors_);
}

void VideoWriter::addFrame(const uint8_t* rgba) {
  if (closed_) throw Error(path_ + ": addFrame after the video was finished or failed");
  const size_t total = static_cast<size_t>(width_) * height_ * 4;
  size_t done = 0;
  while (done < total) {
    const ssize_t n = ::send(input_, rgba + done, total - done, MSG_NOSIGNAL);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EPIPE || errno == ECONNRESET) fail("ffmpeg stopped early");
      fail(std::string("cannot send a frame to ffmpeg: ") + std::strerror(errno));
    }
    done += static_cast<size_t>(n);
  }
  ++frames_;
}

void VideoWriter::finish() {
  if (closed_) throw Error(path_ + ": finish called twice or after a failure");
  stopChild(false);
  if (!WIFEXITED(exitStatus_) || WEXITSTATUS(exitStatus_) != 0) fail("ffmpeg failed");
  if (std::rename(tempPath_.c_str(), path_.c_str()) != 0)
    fail(std::string("cannot rename the video into place: ") + std::strerror(errno));
  closed_ = true;
}

void VideoWriter::stopChild(bool kill) noexcept {
  if (input_ >= 0) {
    ::close(input_);  // EOF: ffmpeg flushes and writes the file
    input_ = -1;
  }
  if (pid_ <= 0) return;
  if (kill) ::kill(pid_, SIGKILL);
  while (::waitpid(pid_, &exitStatus_, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1;
}

std::string VideoWriter::childErrors() const {
  if (!errors_) return "";
  std::string text(4096, '\0');
  std::fflush(errors_);
  std::rewind(errors_);
  text.resize(std::fread(text.data(), 1, text.size(), errors_));
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text;
}

void VideoWriter::fail(const std::string& what) {
  closed_ = true;
  stopChild(true);
  ::unlink(tempPath_.c_str());
  std::string message = path_ + ": " + what;
  if (WIFEXITED(exitStatus_) && WEXITSTATUS(exitStatus_) != 0)
    message += " (exit code " + std::to_string(WEXITSTATUS(exitStatus_)) + ")";
  else if (WIFSIGNALED(exitStatus_) && WTERMSIG(exitStatus_) != SIGKILL)
    message += " (killed by signal " + std::to_string(WTERMSIG(exitStatus_)) + ")";
  const std::string details = childErrors();
  if (!details.empty()) message += ": " + details;
  throw Error(message);
}

}  // namespace engine
