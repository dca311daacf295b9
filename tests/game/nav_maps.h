// nav_maps.h — hand-made maps for the navigation tests (tests/game/nav_*_test.cpp).
//
// Most maps use 0.5 m cells and a 0.3 m robot radius, so that the inflation is exactly one ring of cells beside a
// wall (a cell centre 0.25 m from a wall is blocked, 0.75 m is free, and a centre diagonal to a wall's corner is
// 0.354 m from it: free) and grid path lengths come out in whole moves: 1 cell straight, sqrt(2) diagonal.
// Box2D gives every polygon a 0.01 m skin, so the inflation is radius + 0.01 m.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine/plane/plane_world.h"
#include "game/nav/occupancy_grid.h"
#include "game/nav/planner.h"

namespace nav_maps {

using V2 = Eigen::Vector2d;

inline const double kSqrt2 = std::sqrt(2.0);

// a 10 m x 6 m room of 0.5 m cells (20 x 12), robot radius 0.3 m
inline game::nav::GridDef coarseRoom() {
  game::nav::GridDef def;
  def.origin = V2(0, 0);
  def.size = V2(10, 6);
  def.cellSize = 0.5;
  def.robotRadius = 0.3;
  return def;
}

// a rectangle given by its corners
inline void addRect(engine::PlaneWorld& plane, double x0, double y0, double x1, double y1, int tag = 0) {
  plane.addStaticRect(V2(0.5 * (x0 + x1), 0.5 * (y0 + y1)), V2(0.5 * (x1 - x0), 0.5 * (y1 - y0)), 0.0, tag);
}

inline game::nav::Path handMadePath(const std::vector<V2>& points) {
  game::nav::Path p;
  p.found = true;
  p.points = points;
  p.arc.assign(1, 0.0);
  for (size_t i = 1; i < points.size(); ++i) p.arc.push_back(p.arc.back() + (points[i] - points[i - 1]).norm());
  return p;
}

// A wall across the room with gaps at the bottom (y 0-1) and the top (y 5-6); a ball rolls into the bottom gap.
class NavCorridor : public ::testing::Test {
 protected:
  void SetUp() override { addRect(plane, 4.5, 1.0, 5.5, 5.0); }
  engine::PlaneWorld plane;
  const V2 start{3.25, 1.25}, goal{8.75, 1.25};
  // grid costs, cells (6, 2) -> (17, 2): through the bottom gap, (8, 0) is reached by 2 diagonals and left by 3
  // straight moves to (11, 0), then 2 diagonals and 4 straight: 4 sqrt2 + 7 moves = 6.328 m. Over the top:
  // (6, 2) -> (8, 11) is 2 sqrt2 + 7, 3 straight, (11, 11) -> (17, 2) is 6 sqrt2 + 3: 8 sqrt2 + 13 = 12.157 m.
  const double bottom = (4 * kSqrt2 + 7) * 0.5, top = (8 * kSqrt2 + 13) * 0.5;
};

}  // namespace nav_maps
