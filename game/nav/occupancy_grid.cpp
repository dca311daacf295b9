// occupancy_grid.cpp — see occupancy_grid.h.
#include "game/nav/occupancy_grid.h"

#include <algorithm>
#include <cmath>

#include "engine/plane/plane_tags.h"
#include "engine/plane/plane_world.h"

namespace game::nav {

OccupancyGrid::OccupancyGrid(const Eigen::Vector2d& origin, double cellSize, int width, int height)
    : origin_(origin),
      cellSize_(cellSize),
      width_(width),
      height_(height),
      kind_(static_cast<size_t>(width) * static_cast<size_t>(height), CellKind::Free),
      axis_(kind_.size(), 0.0f),
      temporary_(kind_.size(), 0) {}

Eigen::Vector2i OccupancyGrid::cellAt(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d q = (p - origin_) / cellSize_;
  return Eigen::Vector2i(static_cast<int>(std::floor(q.x())), static_cast<int>(std::floor(q.y())));
}

Eigen::Vector2d OccupancyGrid::centre(int ix, int iy) const {
  return origin_ + cellSize_ * Eigen::Vector2d(ix + 0.5, iy + 0.5);
}

CellKind OccupancyGrid::kind(int ix, int iy) const { return inside(ix, iy) ? kind_[index(ix, iy)] : CellKind::Blocked; }

double OccupancyGrid::stairAxis(int ix, int iy) const { return inside(ix, iy) ? axis_[index(ix, iy)] : 0.0; }

void OccupancyGrid::set(int ix, int iy, CellKind kind, double stairAxis) {
  if (!inside(ix, iy)) return;
  kind_[index(ix, iy)] = kind;
  double a = std::fmod(stairAxis, M_PI);
  if (a < 0) a += M_PI;
  axis_[index(ix, iy)] = static_cast<float>(a);
}

bool OccupancyGrid::temporary(int ix, int iy) const { return inside(ix, iy) && temporary_[index(ix, iy)] != 0; }

void OccupancyGrid::setTemporary(int ix, int iy, bool on) {
  if (inside(ix, iy)) temporary_[index(ix, iy)] = on ? 1 : 0;
}

void OccupancyGrid::clearTemporary() { std::fill(temporary_.begin(), temporary_.end(), uint8_t(0)); }

bool OccupancyGrid::traversable(int ix, int iy) const {
  return inside(ix, iy) && kind_[index(ix, iy)] != CellKind::Blocked && temporary_[index(ix, iy)] == 0;
}

bool OccupancyGrid::allowsHeading(int ix, int iy, double heading, double tolerance) const {
  if (kind(ix, iy) != CellKind::Stairs) return true;
  return angleToAxis(heading, stairAxis(ix, iy)) <= tolerance;
}

double angleToAxis(double heading, double axis) {
  double d = std::fmod(std::abs(heading - axis), M_PI);  // 0 .. pi
  return std::min(d, M_PI - d);
}

OccupancyGrid buildOccupancyGrid(const engine::PlaneWorld& plane, const GridDef& def) {
  const int w = std::max(1, static_cast<int>(std::ceil(def.size.x() / def.cellSize - 1e-9)));
  const int h = std::max(1, static_cast<int>(std::ceil(def.size.y() / def.cellSize - 1e-9)));
  OccupancyGrid grid(def.origin, def.cellSize, w, h);
  for (int iy = 0; iy < h; ++iy)
    for (int ix = 0; ix < w; ++ix) {
      bool wall = false, stairs = false;
      double axis = 0;
      for (const int tag : plane.queryCircle(grid.centre(ix, iy), def.robotRadius)) {
        if (engine::isWallTag(tag))
          wall = true;
        else if (engine::isStairTag(tag) && !stairs)
          stairs = true, axis = engine::stairHeading(tag);
      }
      grid.set(ix, iy, wall ? CellKind::Blocked : stairs ? CellKind::Stairs : CellKind::Free, axis);
    }
  return grid;
}

int markMovables(OccupancyGrid* grid, const engine::PlaneWorld& plane, const Eigen::Vector2d& around, double halfWindow,
                 double robotRadius) {
  const Eigen::Vector2i lo = grid->cellAt(around - Eigen::Vector2d::Constant(halfWindow));
  const Eigen::Vector2i hi = grid->cellAt(around + Eigen::Vector2d::Constant(halfWindow));
  int marked = 0;
  for (int iy = std::max(0, lo.y()); iy <= std::min(grid->height() - 1, hi.y()); ++iy)
    for (int ix = std::max(0, lo.x()); ix <= std::min(grid->width() - 1, hi.x()); ++ix) {
      const std::vector<int> tags = plane.queryCircle(grid->centre(ix, iy), robotRadius);
      if (std::any_of(tags.begin(), tags.end(), engine::isMovableTag)) {
        grid->setTemporary(ix, iy, true);
        ++marked;
      }
    }
  return marked;
}

int markDisc(OccupancyGrid* grid, const Eigen::Vector2d& centre, double radius) {
  const Eigen::Vector2i lo = grid->cellAt(centre - Eigen::Vector2d::Constant(radius));
  const Eigen::Vector2i hi = grid->cellAt(centre + Eigen::Vector2d::Constant(radius));
  int marked = 0;
  for (int iy = std::max(0, lo.y()); iy <= std::min(grid->height() - 1, hi.y()); ++iy)
    for (int ix = std::max(0, lo.x()); ix <= std::min(grid->width() - 1, hi.x()); ++ix)
      if ((grid->centre(ix, iy) - centre).norm() <= radius) {
        grid->setTemporary(ix, iy, true);
        ++marked;
      }
  return marked;
}

}  // namespace game::nav
