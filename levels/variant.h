// variant.h — variants of the Mario course (levels/mario) drawn from a seed: the same stages in the same order
// (a flat start with coins and the ghost, a staircase up and down, a tunnel, question boxes, a ball, a goal), with
// the geometry the skills must cope with drawn within ranges, and everything that depends on it (coins, checkpoints
// with room to stand, the ball, the goal, the walls) placed from it. A variant is a level file like any other;
// `treelearn variant` writes one and `treelearn bench --variants N` plays them. Deterministic per seed on every
// platform: std::mt19937_64 with the mapping to [0, 1) written out here (not std::uniform_real_distribution, whose
// output the standard leaves to the library), values rounded to millimetres before anything is placed from them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "levels/level.h"

namespace levels {

/// The ranges a variant's geometry is drawn from (uniform within each; both ends included up to the rounding).
struct VariantRanges {
  static constexpr int kStepsMin = 3, kStepsMax = 6;           ///< risers up (as many treads back down)
  static constexpr double kRiseMin = 0.08, kRiseMax = 0.15;    ///< step height [m]
  static constexpr double kTreadMin = 0.28, kTreadMax = 0.60;  ///< tread depth [m] (the top landing stays 1 m)
  static constexpr double kTunnelLengthMin = 3.0, kTunnelLengthMax = 6.0;  ///< [m]
  static constexpr double kClearanceMin = 0.55, kClearanceMax = 0.65;      ///< the tunnel's opening [m]
  /// Question boxes: anywhere over the flat from kBoxesFrom to kBoxesTo metres past the tunnel's end (the robot is
  /// up again 1.2 m past it), at least kBoxGap apart along x (one jump each), in the base level's order.
  static constexpr double kBoxesFrom = 2.5, kBoxesTo = 7.0, kBoxGap = 1.0;
  /// The ball: its centre kBallFromWallMin-kBallFromWallMax from the inner face of the left or right wall, or on
  /// the centre line (one of the three, equally likely).
  static constexpr double kBallFromWallMin = 0.3, kBallFromWallMax = 0.6;
  static constexpr double kGhostMaxSpeedMin = 2.0, kGhostMaxSpeedMax = 2.4;  ///< [m/s]
};

/// Where the ball lies across the course.
enum class BallSide { Left, Middle, Right };

/// The values drawn for one seed (rounded to millimetres).
struct MarioVariant {
  uint64_t seed = 0;
  int steps = 4;
  double rise = 0.10, tread = 0.60;
  double tunnelLength = 3.5, clearance = 0.6;
  std::vector<double> boxesPastTunnel;  ///< each question box's x minus the tunnel's end [m], increasing
  BallSide ballSide = BallSide::Middle;
  double ballFromWall = 0;  ///< [m] (drawn for every seed; used unless the ball is in the middle)
  double ghostMaxSpeed = 2.2;
};

/// Draws seed's variant for a base level with `questionBoxes` question boxes.
MarioVariant drawMarioVariant(uint64_t seed, int questionBoxes);

/// The variant as level TOML. The base level (levels/mario) gives what is not drawn: the name (the variant is
/// "NAME-variant-SEED"), time limit, rules, the ghost's settings but its top speed, the question boxes' contents,
/// height and size, the ball's radius and mass, the goal's size. Throws engine::Error (naming the base's file) when
/// the base is not a Mario-style course: a game level with one ghost, one ball, one goal and a question box. The
/// text always loads (parseLevel), checkpoints included.
std::string marioVariantToml(const Level& base, const MarioVariant& variant);

/// One line for humans: "4 steps 0.123 x 0.456 m, tunnel 4.200 m long at 0.612 m, boxes at 31.2 and 33.0, ...".
std::string describeVariant(const MarioVariant& variant);

}  // namespace levels
