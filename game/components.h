// components.h — plain-data components of the game's entities (engine::Registry).
// Systems in session.cpp read and write them; the renderer sees them only through a SceneSnapshot.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>

namespace game {

/// A static box of the level: in the Bullet world, in the 2D layer, and drawn.
struct StaticBox {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d halfExtents = Eigen::Vector3d::Zero();
  uint32_t rgba = 0;
};

/// The ground plane.
struct Ground {
  double friction = 1.0;
};

/// The robot's entity marker (the Robot object itself lives in the Session).
struct RobotTag {
  uint32_t rgba = 0;
};

}  // namespace game
