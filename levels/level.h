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
  bool seeThrough = false;  ///< a [[wall]]: collides like any box, drawn translucent
  bool stairs = false;      ///< a step of a [[stairs]] (a top-plane level's 2D layer tags it as a staircase along +X)
  int line = 0;             ///< where it was defined
};

/// What happens when the robot falls in a game level.
enum class FallRule { Lose, Respawn };

/// The rules that make a level a game (a [rules] table); such a level needs a goal.
struct RulesDef {
  bool present = false;
  FallRule falls = FallRule::Respawn;
  int fallPenalty = 50;  ///< points lost per fall (respawn at the last checkpoint passed)
  int coinValue = 10;
  int giftValue = 50;
  int winBonus = 100;               ///< plus 1 point per second left
  std::vector<double> checkpoints;  ///< respawn x positions (the spawn is always one)
};

/// A ghost that appears behind the robot once it passes appear_x and chases it in the side plane.
struct GhostDef {
  double appearX = 0;   ///< the robot's x that wakes it [m]
  double behind = 4.0;  ///< it appears this far behind the robot [m]
  double height = 1.0;  ///< height of its centre [m]
  double radius = 0.4;
  double speed = 0.6;          ///< initial speed [m/s] ...
  double acceleration = 0.05;  ///< ... growing by this [m/s^2] ...
  double maxSpeed = 2.5;       ///< ... up to this
  double catchDistance = 0.3;  ///< it catches the robot when its edge is this close to the pelvis [m]
  double vanishX = 1e9;        ///< it gives up once the robot passes this x [m]
  int line = 0;
};

/// A coin, collected when any part of the robot comes within radius.
struct CoinDef {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 0.15;
  int line = 0;
};

/// A question box: a static box that releases its content when hit from below (head or hands, going up).
struct QuestionBoxDef {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d size = Eigen::Vector3d(0.4, 0.4, 0.4);
  bool gift = false;  ///< content: a coin (false) or a gift (true)
  int line = 0;
};

/// The ball to kick (a Bullet sphere resting on the ground).
struct BallSpawnDef {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  double radius = 0.11;
  double mass = 0.43;
  int line = 0;
};

/// The goal: a trigger volume; the level is won when the ball's centre is inside it.
struct GoalDef {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d size = Eigen::Vector3d::Ones();
  int line = 0;
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

/// The room a respawn needs. A game level puts a fallen robot back upright in its default pose with both feet on
/// the ground (z = 0) at a checkpoint's x on the course's centre line (y = 0), so nothing solid may be there: the
/// G1 stands 1.32 m tall and 0.45 m across the shoulders (Unitree's figures; the model's head top is at 1.28 m
/// standing and up to 1.33 m in its stride), its feet about 0.2 m apart and 0.2 m long. A checkpoint with a box,
/// a wall, a step, a tunnel's roof or a question box within kStandHalfFootprint of it (along x and y) and lower than
/// kStandHeight is refused when the level loads: a robot put back under a ceiling's edge or into a step falls again
/// at once, for as long as the run lasts.
constexpr double kStandHeight = 1.35;        ///< [m] the robot's 1.32 m and a margin
constexpr double kStandHalfFootprint = 0.3;  ///< [m] half its 0.45 m width and a margin, also along x (a lean, a step)

/// A loaded level.
struct Level {
  std::string name, description;
  std::string path;       ///< the level file
  std::string directory;  ///< folder holding it (key scripts live there too)
  uint64_t hash = 0;      ///< content hash of the level file
  Plane2d plane = Plane2d::Side;
  double timeLimit = 0;  ///< [s], 0 = none
  double groundFriction = 1.0;
  Eigen::Vector2d spawn = Eigen::Vector2d::Zero();  ///< pelvis (x, y) [m]
  double spawnYaw = 0;                              ///< [rad]
  std::vector<BoxDef> boxes;                        ///< boxes, walls, tunnels and expanded staircases
  RulesDef rules;
  std::vector<GhostDef> ghosts;
  std::vector<CoinDef> coins;
  std::vector<QuestionBoxDef> questionBoxes;
  std::vector<BallSpawnDef> balls;
  std::vector<GoalDef> goals;

  /// A game level: it has rules and a goal, and can be won.
  bool isGame() const { return rules.present; }
};

/// Loads a level from a .toml file or from a folder holding level.toml. Throws engine::Error.
Level loadLevel(const std::string& pathOrFolder);

/// Parses level TOML text; fileName is used in messages. Throws engine::Error.
Level parseLevel(const std::string& text, const std::string& fileName);

}  // namespace levels
