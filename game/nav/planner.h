// planner.h — paths on the garden's occupancy grid: A* over cells (8-connected, octile heuristic, no corner
// cutting, stair cells crossed only along their axis), then the path pulled taut by line of sight, and the checks
// and replanning around movable bodies (a ball, a box, a ghost) that the 2D layer shows on the path ahead.
//
// Deterministic: the open list is ordered by (f, h, cell index), neighbours are tried in a fixed order, and no
// container depends on addresses or hashing, so the same grid and endpoints always give the same path.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "game/nav/occupancy_grid.h"

namespace engine {
class PlaneWorld;
}

namespace game::nav {

struct PlannerParams {
  /// A grid move into, out of or within a stair cell must head within this of the cell's axis [rad]: pi/8 lets
  /// only the two moves along an axis that is a multiple of 45 degrees (E and W on a staircase along +X).
  double stairMoveTolerance = M_PI / 8;
  /// A pulled-taut segment may cross stair cells only within this of their axis [rad] (about 5 degrees): the path
  /// crosses a staircase square to its steps.
  double stairLineTolerance = 0.09;
  /// A start or goal in a blocked cell (the robot pushed into a wall's margin, a target clicked on a wall) moves to
  /// the nearest traversable cell within this [m]; further away there is no path.
  double snapRadius = 0.6;
};

/// Where a path is on stair cells: arc lengths [m] from the path's start, and the heading it crosses them with
/// (the staircase's axis, taken the way the path goes: up or down).
struct StairsSpan {
  double from = 0, to = 0;
  double heading = 0;  ///< [rad]
};

/// A planned path: waypoints from the start to the goal.
struct Path {
  bool found = false;
  std::vector<Eigen::Vector2d> points;  ///< points[0] is the start as given, the last one the goal (or its snap)
  std::vector<double> arc;              ///< the path's length up to each point [m]
  std::vector<StairsSpan> stairs;       ///< in order along the path
  double gridCost = 0;                  ///< the A* path's length on the grid, before pulling it taut [m]
  int expanded = 0;                     ///< cells A* expanded (for benchmarks)

  double length() const { return arc.empty() ? 0.0 : arc.back(); }
  /// The point at arc length s (clamped to the path).
  Eigen::Vector2d pointAt(double s) const;
  /// The segment holding arc length s (0 .. points.size() - 2).
  int segmentAt(double s) const;
};

/// A* from the cell holding `start` to the cell holding `goal`, each moved to the nearest traversable cell if it is
/// not one (within params.snapRadius), then pulled taut. found = false when there is no way.
Path planPath(const OccupancyGrid& grid, const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
              const PlannerParams& params = {});

/// The A* cells alone, from start to goal cell inclusive (empty: no way); *cost is the path's length [m].
std::vector<Eigen::Vector2i> searchCells(const OccupancyGrid& grid, const Eigen::Vector2i& start,
                                         const Eigen::Vector2i& goal, const PlannerParams& params, double* cost,
                                         int* expanded = nullptr);

/// The segment a -> b touches only traversable cells (a corner it passes exactly counts both cells beside it), and
/// the stair cells among them only within stairTolerance of their axis.
bool lineOfSight(const OccupancyGrid& grid, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double stairTolerance);

/// The first arc length in [fromArc, fromArc + lookahead] (sampled every `step` m) where a disc of robotRadius on
/// the path overlaps a movable body of the 2D layer; -1 when the stretch is clear.
double firstBlockedArc(const engine::PlaneWorld& plane, const Path& path, double fromArc, double lookahead,
                       double robotRadius, double step);

/// Replanning around what moves: clears the grid's temporary obstacles, marks the movable bodies the 2D layer
/// shows within halfWindow [m] of `start` (markMovables, inflated by robotRadius), and plans again.
Path replanAroundMovables(OccupancyGrid* grid, const engine::PlaneWorld& plane, const Eigen::Vector2d& start,
                          const Eigen::Vector2d& goal, double halfWindow, double robotRadius,
                          const PlannerParams& params = {});

}  // namespace game::nav
