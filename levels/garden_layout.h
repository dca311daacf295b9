// garden_layout.h — random garden layouts drawn from a seed, to test that the garden's navigation works on maps it has
// never seen (docs/navigation.md). Each layout keeps the garden's parts and draws where they go: a 32 m x 32 m walled
// garden, a river running north from the south wall with the same stepped bridge across it (at a drawn x and y), a
// short staircase (3 risers of 0.10 m x 0.60 m up and down, along +X) somewhere on open ground, houses of drawn sizes
// with streets of at least kStreet between them (and one pair with a kAlleyMin-kAlleyMax alley), balls and coins.
// Deterministic per seed on every platform (std::mt19937_64, 53-bit uniforms, millimetres). A layout is a level file
// like any other: `treelearn variant levels/garden --seed N --out DIR` writes one.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace levels {

/// The ranges and margins of a layout (metres).
struct GardenRanges {
  static constexpr double kSize = 32.0;                                ///< the garden, square
  static constexpr double kRiverWidth = 2.0;                           ///< west bank to east bank
  static constexpr double kRiverXMin = 11.0, kRiverXMax = 18.0;        ///< the west bank
  static constexpr double kRiverTopMin = 22.0, kRiverTopMax = 27.0;    ///< where it ends, north
  static constexpr double kBridgeYMin = 7.0, kBridgeYMax = 18.0;       ///< the bridge's axis
  static constexpr int kHousesMin = 7, kHousesMax = 10;                ///< houses (the alley's two among them)
  static constexpr double kHouseMin = 3.0, kHouseMax = 7.0;            ///< a house's side along x
  static constexpr double kHouseDepthMin = 3.0, kHouseDepthMax = 5.0;  ///< ... along y
  static constexpr double kStreet = 1.6;                               ///< between houses, and to the river's keep-out
  static constexpr double kAlleyMin = 1.1, kAlleyMax = 1.2;            ///< the one narrow passage between two houses
  static constexpr double kWallGap = 1.5;                              ///< a house to the garden wall
};

/// An axis-aligned rectangle [x0, x1] x [y0, y1] on the ground.
struct GroundRect {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

/// One layout's drawn values (millimetres).
struct GardenLayout {
  uint64_t seed = 0;
  double riverX = 15.2, riverTop = 25.0, bridgeY = 10.0;
  Eigen::Vector2d flightStart = Eigen::Vector2d(22.0, 18.0);  ///< the short staircase's first riser, its middle (+X)
  std::vector<GroundRect> houses;                             ///< the alley's pair first
  std::vector<Eigen::Vector2d> balls, coins;
};

/// Draws seed's layout.
GardenLayout drawGardenLayout(uint64_t seed);

/// The layout as level TOML (plane "top", the garden's spawn at (3, 2) facing +X); it always loads (parseLevel).
std::string gardenLayoutToml(const GardenLayout& layout);

/// One line for humans: "river at x 14.2 to y 24.9, bridge at y 12.3, 8 houses, steps at (5.1, 20.3)".
std::string describeGardenLayout(const GardenLayout& layout);

}  // namespace levels
