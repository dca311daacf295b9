// planner.cpp — see planner.h.
#include "game/nav/planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "engine/plane/plane_tags.h"
#include "engine/plane/plane_world.h"

namespace game::nav {
namespace {

constexpr double kSqrt2 = 1.4142135623730951;
constexpr double kInf = std::numeric_limits<double>::infinity();

// the eight moves, in the order they are tried: E, N, W, S, then NE, NW, SW, SE
constexpr int kMoves[8][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}, {1, 1}, {-1, 1}, {-1, -1}, {1, -1}};

double octile(const Eigen::Vector2i& a, const Eigen::Vector2i& b) {
  const double dx = std::abs(a.x() - b.x()), dy = std::abs(a.y() - b.y());
  return std::max(dx, dy) + (kSqrt2 - 1.0) * std::min(dx, dy);
}

// the robot may be in cell c moving with `heading`
bool passes(const OccupancyGrid& g, int ix, int iy, double heading, double tolerance) {
  return g.traversable(ix, iy) && g.allowsHeading(ix, iy, heading, tolerance);
}

// the nearest traversable cell to p within `radius` (itself when it is one); found = false if none
bool snap(const OccupancyGrid& g, const Eigen::Vector2d& p, double radius, Eigen::Vector2i* cell) {
  const Eigen::Vector2i c = g.cellAt(p);
  if (g.traversable(c.x(), c.y())) {
    *cell = c;
    return true;
  }
  const int r = static_cast<int>(std::ceil(radius / g.cellSize()));
  double best = kInf;
  for (int iy = c.y() - r; iy <= c.y() + r; ++iy)
    for (int ix = c.x() - r; ix <= c.x() + r; ++ix) {
      if (!g.traversable(ix, iy)) continue;
      const double d = (g.centre(ix, iy) - p).norm();
      if (d <= radius && d < best) best = d, *cell = Eigen::Vector2i(ix, iy);
    }
  return best < kInf;
}

// the stretches of the segment a -> b (starting at arc s0) on stair cells, appended to *spans
void addStairSpans(const OccupancyGrid& g, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double s0,
                   std::vector<StairsSpan>* spans) {
  const double len = (b - a).norm();
  if (len <= 0) return;
  const Eigen::Vector2d dir = (b - a) / len;
  const double step = 0.25 * g.cellSize();
  const int n = static_cast<int>(std::ceil(len / step));
  for (int i = 0; i <= n; ++i) {
    const double t = std::min(len, i * step);
    const Eigen::Vector2i c = g.cellAt(a + t * dir);
    if (g.kind(c.x(), c.y()) != CellKind::Stairs) continue;
    const double s = s0 + t;
    // the staircase's axis, taken the way the segment goes
    const double axis = g.stairAxis(c.x(), c.y());
    const double along = std::atan2(dir.y(), dir.x());
    const double heading = std::cos(along - axis) >= 0 ? axis : axis + M_PI;
    if (!spans->empty() && s - spans->back().to <= 1.5 * step && std::cos(spans->back().heading - heading) > 0) {
      spans->back().to = s;
    } else {
      spans->push_back({s, s, std::remainder(heading, 2 * M_PI)});
    }
  }
}

}  // namespace

Eigen::Vector2d Path::pointAt(double s) const {
  if (points.empty()) return Eigen::Vector2d::Zero();
  if (points.size() == 1 || s <= 0) return points.front();
  if (s >= length()) return points.back();
  const int i = segmentAt(s);
  const double len = arc[i + 1] - arc[i];
  const double t = len > 0 ? (s - arc[i]) / len : 0.0;
  return points[i] + t * (points[i + 1] - points[i]);
}

int Path::segmentAt(double s) const {
  if (points.size() < 2) return 0;
  const auto it = std::upper_bound(arc.begin(), arc.end(), s);
  const int i = static_cast<int>(it - arc.begin()) - 1;
  return std::clamp(i, 0, static_cast<int>(points.size()) - 2);
}

std::vector<Eigen::Vector2i> searchCells(const OccupancyGrid& g, const Eigen::Vector2i& start,
                                         const Eigen::Vector2i& goal, const PlannerParams& params, double* cost,
                                         int* expanded) {
  *cost = 0;
  if (expanded) *expanded = 0;
  if (!g.traversable(start.x(), start.y()) || !g.traversable(goal.x(), goal.y())) return {};
  const int w = g.width();
  const size_t n = static_cast<size_t>(w) * static_cast<size_t>(g.height());
  auto id = [w](int ix, int iy) { return static_cast<size_t>(iy) * static_cast<size_t>(w) + static_cast<size_t>(ix); };
  std::vector<double> gScore(n, kInf);
  std::vector<int64_t> parent(n, -1);
  std::vector<uint8_t> closed(n, 0);

  // open list entries: f, h, cell; the smallest f first, then the one nearer the goal, then the lower index
  struct Entry {
    double f, h;
    size_t cell;
    bool operator>(const Entry& o) const {
      if (f != o.f) return f > o.f;
      if (h != o.h) return h > o.h;
      return cell > o.cell;
    }
  };
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  const size_t s = id(start.x(), start.y()), t = id(goal.x(), goal.y());
  gScore[s] = 0;
  open.push({octile(start, goal), octile(start, goal), s});
  int count = 0;
  while (!open.empty()) {
    const Entry e = open.top();
    open.pop();
    if (closed[e.cell]) continue;
    closed[e.cell] = 1;
    ++count;
    if (e.cell == t) break;
    const int cx = static_cast<int>(e.cell % static_cast<size_t>(w)),
              cy = static_cast<int>(e.cell / static_cast<size_t>(w));
    for (const auto& m : kMoves) {
      const int nx = cx + m[0], ny = cy + m[1];
      const double heading = std::atan2(double(m[1]), double(m[0]));
      const double tol = params.stairMoveTolerance;
      if (!passes(g, nx, ny, heading, tol) || !g.allowsHeading(cx, cy, heading, tol)) continue;
      const bool diagonal = m[0] != 0 && m[1] != 0;
      // no corner cutting: both cells beside a diagonal move are passable the same way
      if (diagonal && (!passes(g, cx + m[0], cy, heading, tol) || !passes(g, cx, cy + m[1], heading, tol))) continue;
      const size_t next = id(nx, ny);
      if (closed[next]) continue;
      const double tentative = gScore[e.cell] + (diagonal ? kSqrt2 : 1.0);
      if (tentative < gScore[next]) {
        gScore[next] = tentative;
        parent[next] = static_cast<int64_t>(e.cell);
        const double h = octile(Eigen::Vector2i(nx, ny), goal);
        open.push({tentative + h, h, next});
      }
    }
  }
  if (expanded) *expanded = count;
  if (gScore[t] == kInf) return {};
  std::vector<Eigen::Vector2i> cells;
  for (int64_t c = static_cast<int64_t>(t); c >= 0; c = parent[static_cast<size_t>(c)])
    cells.emplace_back(static_cast<int>(c % w), static_cast<int>(c / w));
  std::reverse(cells.begin(), cells.end());
  *cost = gScore[t] * g.cellSize();
  return cells;
}

bool lineOfSight(const OccupancyGrid& g, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double stairTolerance) {
  const Eigen::Vector2d d = b - a;
  const double heading = std::atan2(d.y(), d.x());
  auto ok = [&](int ix, int iy) { return passes(g, ix, iy, heading, stairTolerance); };
  // Amanatides-Woo traversal in cell units; passing a corner exactly visits both cells beside it
  const Eigen::Vector2d p = (a - g.origin()) / g.cellSize(), q = (b - g.origin()) / g.cellSize();
  int ix = static_cast<int>(std::floor(p.x())), iy = static_cast<int>(std::floor(p.y()));
  const int ex = static_cast<int>(std::floor(q.x())), ey = static_cast<int>(std::floor(q.y()));
  if (!ok(ix, iy)) return false;
  const Eigen::Vector2d dc = q - p;
  const int stepX = dc.x() > 0 ? 1 : dc.x() < 0 ? -1 : 0, stepY = dc.y() > 0 ? 1 : dc.y() < 0 ? -1 : 0;
  double tMaxX = stepX > 0 ? (ix + 1 - p.x()) / dc.x() : stepX < 0 ? (p.x() - ix) / -dc.x() : kInf;
  double tMaxY = stepY > 0 ? (iy + 1 - p.y()) / dc.y() : stepY < 0 ? (p.y() - iy) / -dc.y() : kInf;
  const double tDeltaX = stepX != 0 ? 1.0 / std::abs(dc.x()) : kInf,
               tDeltaY = stepY != 0 ? 1.0 / std::abs(dc.y()) : kInf;
  const int limit = 2 * (std::abs(ex - ix) + std::abs(ey - iy)) + 4;
  for (int i = 0; i < limit && (ix != ex || iy != ey); ++i) {
    const double tNext = std::min(tMaxX, tMaxY);
    if (tNext > 1.0) break;
    if (std::abs(tMaxX - tMaxY) < 1e-9) {  // through a corner
      if (!ok(ix + stepX, iy) || !ok(ix, iy + stepY)) return false;
      ix += stepX, iy += stepY, tMaxX += tDeltaX, tMaxY += tDeltaY;
    } else if (tMaxX < tMaxY) {
      ix += stepX, tMaxX += tDeltaX;
    } else {
      iy += stepY, tMaxY += tDeltaY;
    }
    if (!ok(ix, iy)) return false;
  }
  return true;
}

Path planPath(const OccupancyGrid& grid, const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
              const PlannerParams& params) {
  Path path;
  Eigen::Vector2i from, to;
  if (!snap(grid, start, params.snapRadius, &from) || !snap(grid, goal, params.snapRadius, &to)) return path;
  double cost = 0;
  const std::vector<Eigen::Vector2i> cells = searchCells(grid, from, to, params, &cost, &path.expanded);
  if (cells.empty()) return path;
  path.found = true;
  path.gridCost = cost;

  // the points the cells stand for; the start and the goal as given replace their cells' centres, except where
  // they were snapped (the start is then kept in front of its snapped cell, the goal gives way to it)
  std::vector<Eigen::Vector2d> raw;
  const bool startSnapped = grid.cellAt(start) != from, goalSnapped = grid.cellAt(goal) != to;
  if (startSnapped) raw.push_back(start);
  for (const Eigen::Vector2i& c : cells) raw.push_back(grid.centre(c.x(), c.y()));
  if (!startSnapped) raw.front() = start;
  if (raw.size() == 1)
    raw.push_back(goalSnapped ? grid.centre(to.x(), to.y()) : goal);  // one cell
  else if (!goalSnapped)
    raw.back() = goal;

  // pulled taut: from each kept point, on to the furthest point after it that is still in sight (the next one
  // always is: grid moves are valid, and the step off a snapped start is taken as it is)
  path.points.push_back(raw.front());
  size_t i = 0;
  while (i + 1 < raw.size()) {
    size_t j = i + 1;
    while (j + 1 < raw.size() && lineOfSight(grid, raw[i], raw[j + 1], params.stairLineTolerance)) ++j;
    path.points.push_back(raw[j]);
    i = j;
  }
  path.arc.assign(1, 0.0);
  for (size_t k = 1; k < path.points.size(); ++k)
    path.arc.push_back(path.arc.back() + (path.points[k] - path.points[k - 1]).norm());
  for (size_t k = 0; k + 1 < path.points.size(); ++k)
    addStairSpans(grid, path.points[k], path.points[k + 1], path.arc[k], &path.stairs);
  return path;
}

double firstBlockedArc(const engine::PlaneWorld& plane, const Path& path, double fromArc, double lookahead,
                       double robotRadius, double step) {
  if (!path.found) return -1;
  const double end = std::min(path.length(), fromArc + lookahead);
  for (double s = std::max(0.0, fromArc);; s += step) {
    const double at = std::min(s, end);
    const std::vector<int> tags = plane.queryCircle(path.pointAt(at), robotRadius);
    if (std::any_of(tags.begin(), tags.end(), engine::isMovableTag)) return at;
    if (at >= end) break;
  }
  return -1;
}

Path replanAroundMovables(OccupancyGrid* grid, const engine::PlaneWorld& plane, const Eigen::Vector2d& start,
                          const Eigen::Vector2d& goal, double halfWindow, double robotRadius,
                          const PlannerParams& params) {
  grid->clearTemporary();
  markMovables(grid, plane, start, halfWindow, robotRadius);
  return planPath(*grid, start, goal, params);
}

}  // namespace game::nav
