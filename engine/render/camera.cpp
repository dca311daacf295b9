// camera.cpp — follow cameras, look-at and perspective matrices, world -> pixel projection.
#include "engine/render/camera.h"

#include <cmath>

namespace engine {

namespace {
constexpr double kPi = 3.14159265358979323846;
// near/far planes used by projectToPixel; only the x/y result matters, so any valid pair works
constexpr double kProjectNear = 0.05;
constexpr double kProjectFar = 1000.0;
}  // namespace

Camera followCamera(const SceneSnapshot& snapshot, int width, int height) {
  Camera camera;
  camera.width = width;
  camera.height = height;
  camera.up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d& follow = snapshot.follow;
  if (snapshot.camera == CameraMode::Side) {
    // looking along +Y: right = forward x up = +X, so the robot walks left to right
    camera.eye = follow + Eigen::Vector3d(0.0, -kSideCameraDistance, 0.8);
    camera.target = follow + Eigen::Vector3d(0.0, 0.0, -0.2);
  } else {
    // behind the followed body along its heading, looking slightly down at it
    const Eigen::Vector3d heading(std::cos(snapshot.followYaw), std::sin(snapshot.followYaw), 0.0);
    camera.eye = follow - kChaseCameraDistance * heading + Eigen::Vector3d(0.0, 0.0, kChaseCameraHeight);
    camera.target = follow;
  }
  return camera;
}

Eigen::Matrix4d viewMatrix(const Camera& camera) {
  // orthonormal camera basis: f forward, s right, u up
  const Eigen::Vector3d f = (camera.target - camera.eye).normalized();
  Eigen::Vector3d s = f.cross(camera.up);
  if (s.squaredNorm() < 1e-12) s = f.cross(Eigen::Vector3d::UnitY());  // looking straight along up
  s.normalize();
  const Eigen::Vector3d u = s.cross(f);

  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(camera.eye);
  m(1, 3) = -u.dot(camera.eye);
  m(2, 3) = f.dot(camera.eye);
  return m;
}

Eigen::Matrix4d projectionMatrix(const Camera& camera, double zNear, double zFar) {
  const double aspect = static_cast<double>(camera.width) / static_cast<double>(camera.height);
  const double f = 1.0 / std::tan(camera.fovYDeg * kPi / 360.0);
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = f / aspect;
  m(1, 1) = f;
  m(2, 2) = (zFar + zNear) / (zNear - zFar);
  m(2, 3) = 2.0 * zFar * zNear / (zNear - zFar);
  m(3, 2) = -1.0;
  return m;
}

bool projectToPixel(const Camera& camera, const Eigen::Vector3d& world, double* px, double* py) {
  const Eigen::Vector4d clip =
      projectionMatrix(camera, kProjectNear, kProjectFar) * viewMatrix(camera) * world.homogeneous();
  if (clip.w() <= 1e-9) return false;  // behind the eye

  // clip -> normalised device coordinates -> pixels, flipping y so row 0 is the top of the image
  const double ndcX = clip.x() / clip.w();
  const double ndcY = clip.y() / clip.w();
  *px = (ndcX + 1.0) * 0.5 * camera.width;
  *py = (1.0 - ndcY) * 0.5 * camera.height;
  return *px >= 0.0 && *px < camera.width && *py >= 0.0 && *py < camera.height;
}

}  // namespace engine
