// nav_planner_test.cpp — the garden's map and planner (game/nav/): the grid built from the 2D layer, A* and its
// pulled-taut paths on hand-made maps whose lengths are worked out in the comments, and replanning around a ball (maps:
// nav_maps.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/plane/plane_tags.h"
#include "engine/plane/plane_world.h"
#include "game/nav/occupancy_grid.h"
#include "game/nav/planner.h"
#include "tests/game/nav_maps.h"

namespace {

using game::nav::CellKind;
using namespace nav_maps;

// ---- the map ------------------------------------------------------------------------------------------------------

TEST(NavGrid, InflatesWallsByTheRobotRadius) {
  engine::PlaneWorld plane;
  addRect(plane, 4.5, 0.0, 5.5, 4.0);  // a wall 1 m thick, 4 m long
  const game::nav::OccupancyGrid g = game::nav::buildOccupancyGrid(plane, coarseRoom());
  ASSERT_EQ(g.width(), 20);
  ASSERT_EQ(g.height(), 12);
  EXPECT_EQ(g.kind(7, 3), CellKind::Free);     // centre (3.75, 1.75): 0.75 m from the wall's face
  EXPECT_EQ(g.kind(8, 3), CellKind::Blocked);  // centre (4.25, 1.75): 0.25 m from it
  EXPECT_EQ(g.kind(9, 3), CellKind::Blocked);  // inside
  EXPECT_EQ(g.kind(11, 3), CellKind::Blocked);
  EXPECT_EQ(g.kind(12, 3), CellKind::Free);
  EXPECT_EQ(g.kind(9, 8), CellKind::Blocked);  // (4.75, 4.25): 0.25 m above the wall's end
  EXPECT_EQ(g.kind(8, 8), CellKind::Free);     // (4.25, 4.25): 0.354 m from its corner
  EXPECT_EQ(g.kind(9, 9), CellKind::Free);
  EXPECT_EQ(g.kind(-1, 3), CellKind::Blocked);  // outside the map
}

TEST(NavGrid, DefaultCellsAreBlockedWithinTheRobotRadiusOfAWall) {
  engine::PlaneWorld plane;
  addRect(plane, 2.0, -5.0, 3.0, 5.0);  // a wall face at x = 2
  game::nav::GridDef def;
  def.origin = V2(-0.05, -0.05);  // cell centres on whole decimetres
  def.size = V2(4, 2);
  const game::nav::OccupancyGrid g = game::nav::buildOccupancyGrid(plane, def);
  EXPECT_NEAR(def.robotRadius, 0.35, 1e-12);
  const int row = g.cellAt(V2(0, 1)).y();
  EXPECT_EQ(g.kind(g.cellAt(V2(1.6, 1)).x(), row), CellKind::Free);     // 0.40 m from the face
  EXPECT_EQ(g.kind(g.cellAt(V2(1.7, 1)).x(), row), CellKind::Blocked);  // 0.30 m
}

TEST(NavGrid, MovableBodiesAreNotPartOfTheMapButAreMarkedWhenSeen) {
  engine::PlaneWorld plane;
  plane.addKinematicCircle(V2(5.0, 3.0), 0.2, engine::kMovableTagBase);  // a ball
  plane.addKinematicCircle(V2(8.0, 3.0), 0.4, -1);                       // a ghost (the course's tag)
  game::nav::OccupancyGrid g = game::nav::buildOccupancyGrid(plane, coarseRoom());
  EXPECT_EQ(g.kind(9, 5), CellKind::Free);  // (4.75, 2.75): overlaps the ball
  // cells whose 0.3 m disc reaches a body: centres within 0.5 m of the ball, 0.7 m of the ghost
  EXPECT_EQ(game::nav::markMovables(&g, plane, V2(5, 3), 1.0, 0.3), 4);  // (4.75|5.25, 2.75|3.25)
  EXPECT_TRUE(g.temporary(9, 5));
  EXPECT_FALSE(g.traversable(9, 5));
  EXPECT_FALSE(g.temporary(15, 5));  // the ghost is outside the window
  g.clearTemporary();
  EXPECT_TRUE(g.traversable(9, 5));
}

// ---- A* and its paths -------------------------------------------------------------------------------------------

TEST(NavPlanner, CrossesAnEmptyRoomInAStraightLine) {
  engine::PlaneWorld plane;
  const game::nav::OccupancyGrid g = game::nav::buildOccupancyGrid(plane, coarseRoom());
  const game::nav::Path p = game::nav::planPath(g, V2(1.25, 1.25), V2(8.75, 4.25));
  ASSERT_TRUE(p.found);
  // on the grid: 15 cells across, 6 up = 6 diagonal + 9 straight moves = (6 sqrt2 + 9) x 0.5 m = 8.743 m
  EXPECT_NEAR(p.gridCost, (6 * kSqrt2 + 9) * 0.5, 1e-9);
  // pulled taut: the straight line, sqrt(7.5^2 + 3^2) = 8.078 m
  ASSERT_EQ(p.points.size(), 2u);
  EXPECT_NEAR(p.length(), std::sqrt(7.5 * 7.5 + 3.0 * 3.0), 1e-9);
  EXPECT_TRUE(p.stairs.empty());
}

TEST(NavPlanner, FindsTheShortestPathAroundAWall) {
  engine::PlaneWorld plane;
  addRect(plane, 4.5, 0.0, 5.5, 4.0);  // from the floor up to y = 4: the way round is over its end
  const game::nav::OccupancyGrid g = game::nav::buildOccupancyGrid(plane, coarseRoom());
  const game::nav::Path p = game::nav::planPath(g, V2(1.25, 1.25), V2(8.75, 1.25));
  ASSERT_TRUE(p.found);
  // Blocked: columns 8-11 (x 4.0-6.0) up to row 7, and columns 9-10 in row 8 (y 4.0-4.5). Columns 9 and 10 are
  // crossed in row 9 or higher, entered by a straight move from (8, 9) (the diagonal from (8, 8) would cut the
  // corner of (9, 8)) and left straight to (11, 9). Start (2, 2) -> (8, 9): 6 across, 7 up = 6 sqrt2 + 1; then 3
  // straight; (11, 9) -> goal (17, 2) again 6 sqrt2 + 1: (12 sqrt2 + 5) x 0.5 m = 10.985 m.
  EXPECT_NEAR(p.gridCost, (12 * kSqrt2 + 5) * 0.5, 1e-9);
  // Pulled taut: over the centres of (8, 9) and (11, 9), the nearest cells to the wall's end that see the start and
  // the goal (from (9, 9) the line to the start would pass the corner of the blocked (9, 8) exactly):
  // 2 x |(4.25, 4.75) - (1.25, 1.25)| + 1.5 = 2 sqrt(3^2 + 3.5^2) + 1.5 = 10.720 m. No path outside the blocked cells
  // is shorter than the string pulled over their corners (4.0, 4.0)-(4.5, 4.5) and (5.5, 4.5): 3.25 sqrt8 + 1 = 10.192.
  ASSERT_EQ(p.points.size(), 4u);
  EXPECT_EQ(p.points[1], V2(4.25, 4.75));
  EXPECT_EQ(p.points[2], V2(5.75, 4.75));
  EXPECT_NEAR(p.length(), 2 * std::sqrt(3.0 * 3.0 + 3.5 * 3.5) + 1.5, 1e-9);
  EXPECT_GT(p.length(), 2 * 3.25 * kSqrt2 + 1);
  for (size_t i = 1; i < p.points.size(); ++i)
    EXPECT_TRUE(game::nav::lineOfSight(g, p.points[i - 1], p.points[i], 0.09)) << "segment " << i;
}

TEST(NavPlanner, ADetourAtTheDefaultResolutionHugsTheInflatedWall) {
  engine::PlaneWorld plane;
  addRect(plane, 4.5, 0.0, 5.5, 4.0);
  game::nav::GridDef def;  // 0.1 m cells, radius 0.35 m (0.36 m with Box2D's skin)
  def.size = V2(10, 6);
  const game::nav::OccupancyGrid g = game::nav::buildOccupancyGrid(plane, def);
  const game::nav::Path p = game::nav::planPath(g, V2(1.25, 1.25), V2(8.75, 1.25));
  ASSERT_TRUE(p.found);
  // The taut string around the wall inflated by r = 0.36 m: tangents from the start and the goal to circles of r
  // round the wall's top corners C1 (4.5, 4) and C2 (5.5, 4), arcs over them and the 1 m between.
  // |S - C1| = sqrt(3.25^2 + 2.75^2) = 4.2573, tangent sqrt(4.2573^2 - r^2) = 4.2421; C1 -> S points at 220.24 deg,
  // the tangent point is acos(r / 4.2573) = 85.15 deg round from it, at 135.09 deg: an arc of 45.09 deg to the top,
  // 0.2833 m. Total 2 x (4.2421 + 0.2833) + 1 = 10.051 m. Cell centres outside the inflation add a little.
  EXPECT_GT(p.length(), 10.05);
  EXPECT_LT(p.length(), 10.30);
}

TEST(NavPlanner, FindsNoPathIntoAnEnclosure) {
  engine::PlaneWorld plane;
  // a closed pen 2.5 m x 3 m with 0.2 m walls around the goal
  addRect(plane, 7.0, 1.5, 9.5, 1.7);
  addRect(plane, 7.0, 4.3, 9.5, 4.5);
  addRect(plane, 7.0, 1.5, 7.2, 4.5);
  addRect(plane, 9.3, 1.5, 9.5, 4.5);
  const game::nav::OccupancyGrid g = game::nav::buildOccupancyGrid(plane, coarseRoom());
  const V2 goal(8.25, 3.25);
  ASSERT_TRUE(g.traversable(g.cellAt(goal).x(), g.cellAt(goal).y()));  // room inside, but no way in
  const game::nav::Path p = game::nav::planPath(g, V2(1.25, 1.25), goal);
  EXPECT_FALSE(p.found);
  EXPECT_TRUE(p.points.empty());
  // and out of it neither
  EXPECT_FALSE(game::nav::planPath(g, goal, V2(1.25, 1.25)).found);
}

TEST(NavPlanner, FindsNoPathToATargetFarInsideAWall) {
  engine::PlaneWorld plane;
  addRect(plane, 4.0, 1.0, 7.0, 5.0);
  const game::nav::OccupancyGrid g = game::nav::buildOccupancyGrid(plane, coarseRoom());
  EXPECT_FALSE(game::nav::planPath(g, V2(1.25, 1.25), V2(5.5, 3.0)).found);  // 1.5 m from free cells
  // a target just inside the wall's margin is moved to the nearest free cell (snap radius 0.6 m)
  const game::nav::Path near = game::nav::planPath(g, V2(1.25, 1.25), V2(3.7, 3.25));
  ASSERT_TRUE(near.found);
  EXPECT_EQ(near.points.back(), V2(3.25, 3.25));  // cell (6, 6), the last free one before the wall, 0.45 m away
}

// A band of stairs across the whole room, x 4-6, climbing along +X: its cells (columns 7-12 with the inflation,
// x 3.5-6.5) are crossed only by moves along X.
TEST(NavPlanner, CrossesAStaircaseOnlyAlongItsAxis) {
  engine::PlaneWorld plane;
  addRect(plane, 4.0, 0.0, 6.0, 6.0, engine::stairTag(0.0));
  const game::nav::OccupancyGrid g = game::nav::buildOccupancyGrid(plane, coarseRoom());
  EXPECT_EQ(g.kind(6, 0), CellKind::Free);
  EXPECT_EQ(g.kind(7, 0), CellKind::Stairs);
  EXPECT_EQ(g.kind(12, 0), CellKind::Stairs);
  EXPECT_EQ(g.kind(13, 0), CellKind::Free);
  const game::nav::Path p = game::nav::planPath(g, V2(1.25, 0.75), V2(8.75, 5.25));
  ASSERT_TRUE(p.found);
  // From (2, 1) to (17, 10): 15 across, 9 up. Free, that is 9 sqrt2 + 6 = 18.73 moves (9.364 m). The 7 moves
  // across the stairs (6 -> 13) must be straight, which leaves 8 columns for 9 rows: 8 sqrt2 + 1, so
  // (8 sqrt2 + 8) x 0.5 m = 9.657 m.
  EXPECT_NEAR(p.gridCost, (8 * kSqrt2 + 8) * 0.5, 1e-9);
  // the pulled-taut path crosses them along X too: one span, heading 0, 3 m long (x 3.5-6.5)
  ASSERT_EQ(p.stairs.size(), 1u);
  EXPECT_NEAR(p.stairs[0].heading, 0.0, 1e-9);
  EXPECT_NEAR(p.stairs[0].to - p.stairs[0].from, 3.0, 0.15);
  for (size_t i = 1; i < p.points.size(); ++i) {
    const V2 a = p.points[i - 1], b = p.points[i];
    const bool onStairs = std::max(a.x(), b.x()) > 3.5 && std::min(a.x(), b.x()) < 6.5;
    const double heading = std::atan2(b.y() - a.y(), b.x() - a.x());
    if (onStairs) {
      EXPECT_LE(game::nav::angleToAxis(heading, 0.0), 0.09) << "segment " << i << " is off the axis";
    }
  }

  // without the staircase the same room is crossed on the diagonal
  engine::PlaneWorld open;
  const game::nav::Path free =
      game::nav::planPath(game::nav::buildOccupancyGrid(open, coarseRoom()), V2(1.25, 0.75), V2(8.75, 5.25));
  EXPECT_NEAR(free.gridCost, (9 * kSqrt2 + 6) * 0.5, 1e-9);
}

TEST(NavPlanner, AStaircaseAcrossTheWayCannotBeCrossedSideways) {
  engine::PlaneWorld plane;
  addRect(plane, 4.0, 0.0, 6.0, 6.0, engine::stairTag(M_PI / 2));  // the same band, climbing along +Y
  const game::nav::OccupancyGrid g = game::nav::buildOccupancyGrid(plane, coarseRoom());
  EXPECT_FALSE(game::nav::planPath(g, V2(1.25, 0.75), V2(8.75, 5.25)).found);
  // along it is fine: up the band's middle
  const game::nav::Path up = game::nav::planPath(g, V2(4.75, 0.75), V2(4.75, 5.25));
  ASSERT_TRUE(up.found);
  EXPECT_NEAR(up.length(), 4.5, 1e-9);
  ASSERT_EQ(up.stairs.size(), 1u);
  EXPECT_NEAR(up.stairs[0].heading, M_PI / 2, 1e-6);
  // and down it the span's heading is the other way
  const game::nav::Path down = game::nav::planPath(g, V2(4.75, 5.25), V2(4.75, 0.75));
  ASSERT_EQ(down.stairs.size(), 1u);
  EXPECT_NEAR(down.stairs[0].heading, -M_PI / 2, 1e-6);
}

TEST(NavPlanner, SamePlanTwiceIsIdentical) {
  engine::PlaneWorld plane;
  addRect(plane, 4.5, 0.0, 5.5, 4.0);
  addRect(plane, 2.0, 3.0, 3.0, 6.0);
  game::nav::GridDef def;
  def.size = V2(10, 6);
  const game::nav::OccupancyGrid g = game::nav::buildOccupancyGrid(plane, def);
  const game::nav::Path a = game::nav::planPath(g, V2(0.7, 0.9), V2(9.1, 5.3));
  const game::nav::Path b = game::nav::planPath(g, V2(0.7, 0.9), V2(9.1, 5.3));
  ASSERT_TRUE(a.found);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) EXPECT_EQ(a.points[i], b.points[i]);
  EXPECT_EQ(a.expanded, b.expanded);
}

TEST_F(NavCorridor, ReplansOverTheTopWhenABallBlocksTheBottomGap) {
  game::nav::OccupancyGrid g = game::nav::buildOccupancyGrid(plane, coarseRoom());
  const game::nav::Path before = game::nav::planPath(g, start, goal);
  ASSERT_TRUE(before.found);
  EXPECT_NEAR(before.gridCost, bottom, 1e-9);
  EXPECT_LT(game::nav::firstBlockedArc(plane, before, 0, 10, 0.3, 0.05), 0);  // clear

  plane.addKinematicCircle(V2(5.0, 0.4), 0.2, engine::kMovableTagBase);  // the ball, in the gap
  const double at = game::nav::firstBlockedArc(plane, before, 0, 10, 0.3, 0.05);
  ASSERT_GE(at, 0);
  EXPECT_LT((before.pointAt(at) - V2(5.0, 0.4)).norm(), 0.5 + 1e-9);  // where the ball is

  const game::nav::Path after = game::nav::replanAroundMovables(&g, plane, start, goal, 4.0, 0.3);
  ASSERT_TRUE(after.found);
  EXPECT_NEAR(after.gridCost, top, 1e-9);
  for (const V2& p : after.points) EXPECT_FALSE(std::abs(p.x() - 5.0) < 1.0 && p.y() < 2.0);
  EXPECT_LT(game::nav::firstBlockedArc(plane, after, 0, 20, 0.3, 0.05), 0);

  // the ball gone, the next replan goes through the gap again
  engine::PlaneWorld clear;
  addRect(clear, 4.5, 1.0, 5.5, 5.0);
  EXPECT_NEAR(game::nav::replanAroundMovables(&g, clear, start, goal, 4.0, 0.3).gridCost, bottom, 1e-9);
}

}  // namespace
