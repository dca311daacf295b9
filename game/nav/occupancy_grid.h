// occupancy_grid.h — the garden's map as the robot knows it: a grid of cells over a rectangle of the level's
// top-down 2D layer (engine::PlaneWorld, world (x, y)), built by circle queries at each cell's centre, so that a
// cell is blocked when the robot's body (a disc of the robot's radius) standing there would touch a wall: the
// obstacles are inflated by the robot's radius and the planner treats the robot as a point.
//
// A cell whose disc touches a staircase (and no wall) is a stair cell: it carries the staircase's axis and may be
// crossed only along it (either way: up or down). Bodies that move (balls, boxes, ghosts) are not in the map: the
// planner marks them as temporary obstacles where they are seen (game/nav/planner.h). Tag meanings:
// engine/plane/plane_tags.h.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace engine {
class PlaneWorld;
}

namespace game::nav {

/// The robot's radius in the map [m]: the G1 seen from above (shoulder joints at +-0.14 m from the pelvis, hanging
/// hands at roughly +-0.25 m, feet stepping up to about 0.25 m ahead of or behind it) plus about 0.1 m for the gait's
/// sway and the pelvis's distance from the path it follows.
constexpr double kRobotRadius = 0.35;

/// What part of the world the grid maps, and how finely.
struct GridDef {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< the rectangle's lower-left corner (min x, min y) [m]
  Eigen::Vector2d size = Eigen::Vector2d(10, 10);    ///< its width along x and height along y [m]
  double cellSize = 0.1;                             ///< [m]
  double robotRadius = kRobotRadius;                 ///< obstacles are inflated by this [m]
};

enum class CellKind : uint8_t { Free, Blocked, Stairs };

/// Cells, row by row from the origin (cell (ix, iy) spans origin + cellSize * [ix, ix+1) x [iy, iy+1)).
/// Outside the grid counts as blocked.
class OccupancyGrid {
 public:
  OccupancyGrid() = default;
  OccupancyGrid(const Eigen::Vector2d& origin, double cellSize, int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }
  double cellSize() const { return cellSize_; }
  const Eigen::Vector2d& origin() const { return origin_; }

  bool inside(int ix, int iy) const { return ix >= 0 && iy >= 0 && ix < width_ && iy < height_; }
  /// The cell holding world point p (it may be outside the grid).
  Eigen::Vector2i cellAt(const Eigen::Vector2d& p) const;
  /// The world position of a cell's centre.
  Eigen::Vector2d centre(int ix, int iy) const;

  /// Blocked outside the grid.
  CellKind kind(int ix, int iy) const;
  /// A stair cell's axis [rad], folded to [0, pi) (the heading it is climbed along, or the opposite one).
  double stairAxis(int ix, int iy) const;
  void set(int ix, int iy, CellKind kind, double stairAxis = 0);

  /// A temporary obstacle (a movable body seen there, or where the robot got stuck): blocked until cleared.
  bool temporary(int ix, int iy) const;
  void setTemporary(int ix, int iy, bool on);
  void clearTemporary();

  /// The robot may stand in the cell: inside, not blocked, not temporarily blocked.
  bool traversable(int ix, int iy) const;
  /// Moving through the cell with `heading` [rad] is allowed: always on a free cell; on a stair cell only when the
  /// heading is within `tolerance` [rad] of its axis, either way along it.
  bool allowsHeading(int ix, int iy, double heading, double tolerance) const;

 private:
  size_t index(int ix, int iy) const {
    return static_cast<size_t>(iy) * static_cast<size_t>(width_) + static_cast<size_t>(ix);
  }
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  double cellSize_ = 0.1;
  int width_ = 0, height_ = 0;
  std::vector<CellKind> kind_;
  std::vector<float> axis_;
  std::vector<uint8_t> temporary_;
};

/// Maps def's rectangle (width = ceil(size.x / cellSize) cells, likewise the height): each cell is classed by the
/// tags of the bodies a circle of def.robotRadius at its centre overlaps: any wall tag -> Blocked, else any stair
/// tag -> Stairs (the axis of the first such tag), else Free. Movable tags are ignored.
OccupancyGrid buildOccupancyGrid(const engine::PlaneWorld& plane, const GridDef& def);

/// Marks as temporary every cell within `halfWindow` [m] (a square) of `around` whose disc of `robotRadius`
/// overlaps a movable body (engine::isMovableTag). Returns how many cells it marked.
int markMovables(OccupancyGrid* grid, const engine::PlaneWorld& plane, const Eigen::Vector2d& around, double halfWindow,
                 double robotRadius);

/// Marks as temporary every cell whose centre is within `radius` of `centre` (e.g. where the robot got stuck).
int markDisc(OccupancyGrid* grid, const Eigen::Vector2d& centre, double radius);

/// The angle between a heading and an axis [rad], 0 .. pi/2 (an axis has no direction).
double angleToAxis(double heading, double axis);

}  // namespace game::nav
