// camera.h — follow cameras and the view/projection maths shared by the renderer and by tests.
// World frame: Z up, X forward, metres. Matrices follow the OpenGL conventions (column vectors,
// camera looks down its -Z, clip space [-1, 1]). Pure maths: no GL here.
#pragma once

#include <Eigen/Core>

#include "engine/render/scene_snapshot.h"

namespace engine {

/// A pinhole camera looking from eye at target.
struct Camera {
  Eigen::Vector3d eye = Eigen::Vector3d(0, -4, 1);   ///< camera position, world frame [m]
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  ///< point at the image centre, world frame [m]
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();     ///< world direction shown as "up" in the image
  double fovYDeg = 45.0;                             ///< vertical field of view [deg]
  int width = 640;                                   ///< image width [px]
  int height = 360;                                  ///< image height [px]
};

/// Side camera distance to the follow point, sideways (-Y) [m]; X forward then runs left to right.
inline constexpr double kSideCameraDistance = 4.0;
/// Chase camera distance behind the follow point along followYaw [m].
inline constexpr double kChaseCameraDistance = 3.0;
/// Chase camera height above the follow point [m].
inline constexpr double kChaseCameraHeight = 1.2;

/// The camera for snapshot.camera: Side looks at the follow point from 4 m on its -Y side, 0.8 m up,
/// so world +X runs left to right and +Z up; Chase sits 3 m behind along followYaw and 1.2 m up.
Camera followCamera(const SceneSnapshot& snapshot, int width, int height);

/// World -> camera (eye) transform, like gluLookAt.
Eigen::Matrix4d viewMatrix(const Camera& camera);

/// Camera -> clip transform, like gluPerspective; zNear, zFar > 0 [m].
Eigen::Matrix4d projectionMatrix(const Camera& camera, double zNear, double zFar);

/// Projects a world point to pixel coordinates, (0, 0) = top-left corner of the top-left pixel, +y down.
/// Writes *px, *py whenever the point is in front of the camera; returns true only if it is also
/// inside the image.
bool projectToPixel(const Camera& camera, const Eigen::Vector3d& world, double* px, double* py);

}  // namespace engine
