// level.h — a level as data, loaded from a human-editable TOML file (format: levels/README.md).
// Loading validates every field and reports "file:line: what is wrong"; the result is const afterwards.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace levels {

/// Which plane the level's 2D layer (Box2D) lives in.
enum class Plane2d { Side, Top };  ///< Side: world (x, z); Top: world (x, y)

/// A static box obstacle (also one step of a staircase).
struct BoxDef {
  std::string name;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< [m]
  Eigen::Vector3d size = Eigen::Vector3d::Ones();    ///< full sizes [m]
  double yaw = 0;                                    ///< rotation about Z [rad]
  uint32_t rgba = 0x9a7b5aff;
  double friction = 1.0;
  int line = 0;  ///< where it was defined
};

/// A straight staircase along +X: `steps` risers up (the last tread is `top` deep, a landing) and, with
/// `down`, steps - 1 treads back down, so that the way down has as many risers as the way up.
struct StairsDef {
  std::string name = "stairs";
  Eigen::Vector2d start = Eigen::Vector2d::Zero();  ///< front edge of the first step (x), centre line (y)
  int steps = 1;
  double rise = 0.1, run = 0.3, width = 1.5, top = 0.3;
  bool down = false;
  uint32_t rgba = 0xc8b08aff;
  int line = 0;
};

/// The staircase as boxes, each a column from the ground up to its tread, named NAME_up1..., NAME_down...
std::vector<BoxDef> expandStairs(const StairsDef& stairs);

/// X where the staircase ends (the back edge of its last tread).
double stairsEndX(const StairsDef& stairs);

/// A loaded level.
struct Level {
  std::string name, description;
  std::string path;          ///< the level file
  std::string directory;     ///< folder holding it (key scripts live there too)
  uint64_t hash = 0;         ///< content hash of the level file
  Plane2d plane = Plane2d::Side;
  double timeLimit = 0;      ///< [s], 0 = none
  double groundFriction = 1.0;
  Eigen::Vector2d spawn = Eigen::Vector2d::Zero();  ///< pelvis (x, y) [m]
  double spawnYaw = 0;                              ///< [rad]
  std::vector<BoxDef> boxes;                        ///< boxes and expanded staircases
};

/// Loads a level from a .toml file or from a folder holding level.toml. Throws engine::Error.
Level loadLevel(const std::string& pathOrFolder);

/// Parses level TOML text; fileName is used in messages. Throws engine::Error.
Level parseLevel(const std::string& text, const std::string& fileName);

}  // namespace levels
