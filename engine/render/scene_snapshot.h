// scene_snapshot.h — what the renderer draws: plain data filled by the simulation side once per frame.
// Simulation code never includes the renderer; the renderer never includes Bullet or Box2D.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace engine {

/// Shape kinds the renderer can draw (robot links are drawn as their collision primitives).
enum class ShapeKind : uint8_t { Box, Sphere, Capsule, Plane };

/// One primitive in world coordinates (metres). Capsule axis is local Z.
struct DrawShape {
  ShapeKind kind = ShapeKind::Box;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();            ///< centre, world frame [m]
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  ///< local -> world
  Eigen::Vector3d halfExtents = Eigen::Vector3d::Zero();         ///< Box: half sizes [m]
  double radius = 0.0;                                           ///< Sphere/Capsule radius [m]
  double halfLength = 0.0;                                       ///< Capsule: half the segment length [m]
  uint32_t rgba = 0xb0b0b0ff;                                    ///< colour, 0xRRGGBBAA (AA < 255: see-through)
};

/// Camera modes that follow a target point.
enum class CameraMode : uint8_t { Side, Chase };

/// Everything needed to draw one frame.
struct SceneSnapshot {
  std::vector<DrawShape> shapes;
  Eigen::Vector3d follow = Eigen::Vector3d::Zero();  ///< the point the camera follows (robot pelvis) [m]
  double followYaw = 0.0;                            ///< heading of the followed body, for Chase [rad]
  CameraMode camera = CameraMode::Side;
  std::string hud;  ///< HUD text drawn top-left (lines split at \n)
};

}  // namespace engine
