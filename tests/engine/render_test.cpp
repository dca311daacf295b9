// render_test.cpp — camera orientation, rendered pixels at projected positions, HUD, PNG and MP4 output.
// Renders small off-screen frames with OSMesa; the video test is skipped when ffmpeg is not installed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "engine/core/error.h"
#include "engine/render/camera.h"
#include "engine/render/png_writer.h"
#include "engine/render/renderer.h"
#include "engine/render/video_writer.h"

namespace engine {
namespace {

namespace fs = std::filesystem;

// a fresh empty folder under the system temp dir, removed at scope exit
struct TempDir {
  fs::path path;
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "treelearn_render_XXXXXX").string();
    path = ::mkdtemp(pattern.data());
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& entry : fs::directory_iterator(path)) out.push_back(entry.path().filename().string());
    return out;
  }
};

std::string readAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// ground plus one red ball at the follow point
SceneSnapshot redBallScene(CameraMode mode) {
  SceneSnapshot scene;
  DrawShape ground;
  ground.kind = ShapeKind::Plane;
  scene.shapes.push_back(ground);
  DrawShape ball;
  ball.kind = ShapeKind::Sphere;
  ball.position = Eigen::Vector3d(2.0, 0.0, 0.8);
  ball.radius = 0.15;
  ball.rgba = 0xd04020ff;
  scene.shapes.push_back(ball);
  scene.follow = ball.position;
  scene.followYaw = 0.0;
  scene.camera = mode;
  return scene;
}

struct Pixel {
  int r, g, b;
};

Pixel pixelAt(const Renderer& renderer, int x, int y) {
  const uint8_t* p = renderer.rgba() + (static_cast<size_t>(y) * renderer.width() + x) * 4;
  return {p[0], p[1], p[2]};
}

bool isRed(const Pixel& p) { return p.r > p.g + 60 && p.r > p.b + 60; }

void expectBallAtProjectedPixel(CameraMode mode) {
  Renderer renderer(640, 360);
  const SceneSnapshot scene = redBallScene(mode);
  renderer.render(scene);

  double px = 0, py = 0;
  ASSERT_TRUE(projectToPixel(renderer.lastCamera(), scene.follow, &px, &py));
  const int x = static_cast<int>(px);
  const int y = static_cast<int>(py);
  ASSERT_GE(x, 160);  // room for the "150 px to the left" probe
  const int offsets[][2] = {{0, 0}, {5, 0}, {-5, 0}, {0, 5}, {0, -5}, {3, 3}, {-3, -3}};
  for (const auto& o : offsets) {
    const Pixel p = pixelAt(renderer, x + o[0], y + o[1]);
    EXPECT_TRUE(isRed(p)) << "at (" << x + o[0] << ", " << y + o[1] << ") rgb " << p.r << " " << p.g << " " << p.b;
  }
  const Pixel left = pixelAt(renderer, x - 150, y);
  EXPECT_FALSE(isRed(left)) << "rgb " << left.r << " " << left.g << " " << left.b;
}

TEST(Camera, SideViewShowsForwardToTheRightAndUpAsUp) {
  SceneSnapshot scene;
  scene.follow = Eigen::Vector3d(5.0, 1.0, 0.8);
  scene.camera = CameraMode::Side;
  const Camera camera = followCamera(scene, 640, 360);
  double cx, cy, fx, fy, ux, uy;
  ASSERT_TRUE(projectToPixel(camera, scene.follow, &cx, &cy));
  ASSERT_TRUE(projectToPixel(camera, scene.follow + Eigen::Vector3d(0.5, 0, 0), &fx, &fy));
  ASSERT_TRUE(projectToPixel(camera, scene.follow + Eigen::Vector3d(0, 0, 0.5), &ux, &uy));
  EXPECT_GT(fx, cx + 20);  // +X forward goes right
  EXPECT_NEAR(fy, cy, 1e-6);
  EXPECT_LT(uy, cy - 20);  // +Z goes up (smaller row)
  // the camera looks 0.2 m below the follow point, so the follow point sits just above the centre
  EXPECT_NEAR(cx, 320.0, 1e-6);
  EXPECT_LT(cy, 180.0);
}

TEST(Camera, ChaseViewLooksAlongTheHeading) {
  SceneSnapshot scene;
  scene.follow = Eigen::Vector3d(1.0, 2.0, 0.8);
  scene.followYaw = 0.5 * 3.14159265358979;  // heading +Y
  scene.camera = CameraMode::Chase;
  const Camera camera = followCamera(scene, 640, 360);
  EXPECT_NEAR(camera.eye.x(), 1.0, 1e-9);
  EXPECT_NEAR(camera.eye.y(), 2.0 - 3.0, 1e-9);
  EXPECT_NEAR(camera.eye.z(), 0.8 + 1.2, 1e-9);
  double cx, cy, lx, ly, bx, by;
  ASSERT_TRUE(projectToPixel(camera, scene.follow, &cx, &cy));
  EXPECT_NEAR(cx, 320.0, 1e-6);
  EXPECT_NEAR(cy, 180.0, 1e-6);
  // heading +Y: the robot's left (-X) shows on the left of the image
  ASSERT_TRUE(projectToPixel(camera, scene.follow + Eigen::Vector3d(-0.5, 0, 0), &lx, &ly));
  EXPECT_LT(lx, cx - 20);
  // a point behind the camera does not project
  EXPECT_FALSE(projectToPixel(camera, camera.eye - Eigen::Vector3d(0, 1, 0), &bx, &by));
}

TEST(Renderer, RobotColouredPixelsAppearAtProjectedPosition) {
  {
    SCOPED_TRACE("Side");
    expectBallAtProjectedPixel(CameraMode::Side);
  }
  {
    SCOPED_TRACE("Chase");
    expectBallAtProjectedPixel(CameraMode::Chase);
  }
}

TEST(Renderer, ImageIsTopDownWithSkyAboveGround) {
  Renderer renderer(320, 180);
  renderer.render(redBallScene(CameraMode::Side));
  const Pixel top = pixelAt(renderer, 160, 2);
  const Pixel bottom = pixelAt(renderer, 160, 177);
  EXPECT_GT(top.b, top.r + 40);                  // sky blue
  EXPECT_LT(std::abs(bottom.r - bottom.b), 20);  // grey ground
}

int countWhitePixels(const Renderer& renderer, int width, int height) {
  int count = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Pixel p = pixelAt(renderer, x, y);
      if (p.r > 230 && p.g > 230 && p.b > 230) ++count;
    }
  return count;
}

TEST(Renderer, HudTextIsDrawn) {
  Renderer renderer(640, 360);
  SceneSnapshot scene = redBallScene(CameraMode::Side);
  scene.hud = "TIME 1.00";
  renderer.render(scene);
  EXPECT_GT(countWhitePixels(renderer, 200, 30), 50);

  scene.hud.clear();
  renderer.render(scene);
  EXPECT_EQ(countWhitePixels(renderer, 200, 30), 0);
}

TEST(Renderer, TwoRenderersKeepSeparateImages) {
  Renderer a(64, 48);
  Renderer b(32, 24);
  SceneSnapshot scene = redBallScene(CameraMode::Side);
  a.render(scene);
  b.render(scene);
  a.render(scene);
  EXPECT_EQ(a.width(), 64);
  EXPECT_EQ(b.height(), 24);
  EXPECT_GT(pixelAt(a, 32, 2).b, pixelAt(a, 32, 2).r);
}

TEST(PngWriter, WritesValidPngAtomically) {
  TempDir dir;
  const int width = 64, height = 32;
  std::vector<uint8_t> image(width * height * 4);
  for (size_t i = 0; i < image.size(); ++i) image[i] = static_cast<uint8_t>(i * 7);

  const fs::path file = dir.path / "frame.png";
  writePng(file.string(), image.data(), width, height);
  const std::string bytes = readAll(file);
  ASSERT_GT(bytes.size(), 33u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  // IHDR: big-endian width and height at bytes 16..23, colour type 2 (RGB) at byte 25
  EXPECT_EQ(bytes.substr(12, 4), "IHDR");
  EXPECT_EQ(static_cast<uint8_t>(bytes[19]), width);
  EXPECT_EQ(static_cast<uint8_t>(bytes[23]), height);
  EXPECT_EQ(bytes[25], 2);
  EXPECT_EQ(dir.names(), std::vector<std::string>{"frame.png"});

  writePng((dir.path / "alpha.png").string(), image.data(), width, height, /*keepAlpha=*/true);
  EXPECT_EQ(readAll(dir.path / "alpha.png")[25], 6);  // RGBA

  const fs::path missing = dir.path / "missing" / "frame.png";
  EXPECT_THROW(writePng(missing.string(), image.data(), width, height), Error);
  EXPECT_FALSE(fs::exists(dir.path / "missing"));
  EXPECT_EQ(dir.names().size(), 2u);
}

TEST(VideoWriter, WritesMp4) {
  if (std::system("command -v ffmpeg > /dev/null 2>&1") != 0) GTEST_SKIP() << "ffmpeg is not installed";
  TempDir dir;
  const int width = 64, height = 48;
  std::vector<uint8_t> frame(width * height * 4, 255);
  const fs::path file = dir.path / "clip.mp4";
  {
    VideoWriter video(file.string(), width, height, 30);
    for (int i = 0; i < 10; ++i) {
      for (size_t p = 0; p < frame.size(); p += 4) frame[p] = static_cast<uint8_t>(i * 25);
      video.addFrame(frame.data());
    }
    EXPECT_FALSE(fs::exists(file));  // only the temp file exists until finish()
    video.finish();
    EXPECT_EQ(video.frameCount(), 10);
  }
  const std::string bytes = readAll(file);
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(4, 4), "ftyp");
  EXPECT_EQ(dir.names(), std::vector<std::string>{"clip.mp4"});

  // abandoned without finish(): nothing is left behind
  {
    VideoWriter video((dir.path / "abandoned.mp4").string(), width, height, 30);
    video.addFrame(frame.data());
  }
  EXPECT_EQ(dir.names(), std::vector<std::string>{"clip.mp4"});

  EXPECT_THROW(VideoWriter((dir.path / "missing" / "clip.mp4").string(), width, height, 30), Error);
  EXPECT_THROW(VideoWriter((dir.path / "odd.mp4").string(), 63, 48, 30), Error);
}

}  // namespace
}  // namespace engine
