// terrain.cpp — see terrain.h. The staircase is the level format's (levels::expandStairs), so training, the
// card and levels build the same steps.
#include "ai/env/terrain.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "levels/level.h"

namespace ai {
namespace {

levels::StairsDef stairsOf(const TerrainDef& t, double stepHeight) {
  levels::StairsDef d;
  d.start = Eigen::Vector2d(t.startX, 0.0);
  d.steps = t.steps;
  d.rise = stepHeight;
  d.run = t.stepDepth;
  d.width = t.width;
  d.top = t.topDepth;
  d.down = true;
  return d;
}

}  // namespace

Staircase drawStaircase(const TerrainDef& terrain, const StairsDraw& draw, double lessonRise, double u0, double u1,
                        double u2) {
  Staircase s{terrain, lessonRise};
  if (!draw.drawn()) return s;
  s.rise = draw.rise.lo + u0 * (draw.rise.hi - draw.rise.lo);
  s.terrain.stepDepth = draw.tread.lo + u1 * (draw.tread.hi - draw.tread.lo);
  const int fewest = int(draw.steps.lo), most = int(draw.steps.hi);
  s.terrain.steps = std::min(most, fewest + int(u2 * (most - fewest + 1)));
  return s;
}

void addTerrain(engine::PhysicsWorld& world, const TerrainDef& t, double stepHeight, double friction) {
  if (t.kind != TerrainDef::Kind::Stairs || stepHeight <= 0) return;
  for (const levels::BoxDef& b : levels::expandStairs(stairsOf(t, stepHeight)))
    world.addStaticBox(b.centre, Eigen::Quaterniond::Identity(), 0.5 * b.size, friction);
}

void addCeiling(engine::PhysicsWorld& world, const TerrainDef& t, const Eigen::Vector2d& centre, double heading,
                double behind, double length, double width, double friction) {
  if (t.kind != TerrainDef::Kind::Ceiling) return;
  constexpr double kThickness = 0.2;
  const Eigen::Vector2d along(std::cos(heading), std::sin(heading));
  const Eigen::Vector2d mid = centre + along * (0.5 * length - behind);
  world.addStaticBox(Eigen::Vector3d(mid.x(), mid.y(), t.ceilingHeight + 0.5 * kThickness),
                     Eigen::Quaterniond(Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ())),
                     Eigen::Vector3d(0.5 * length, 0.5 * width, 0.5 * kThickness), friction);
}

Eigen::Vector2d stairsSpawn(const TerrainDef& t, double stepHeight, double u, double v) {
  if (t.kind != TerrainDef::Kind::Stairs || t.steps < 1) return Eigen::Vector2d::Zero();
  const std::vector<levels::BoxDef> treads = levels::expandStairs(stairsOf(t, std::max(stepHeight, 1e-3)));
  const int n = int(treads.size());
  const levels::BoxDef& b = treads[std::clamp(int(u * n), 0, n - 1)];
  const double nearEdge = b.centre.x() - 0.5 * b.size.x();
  constexpr double kIn = 0.10, kJitter = 0.03, kBeforeFar = 0.25;
  const double x = b.size.x() <= kIn + kBeforeFar ? nearEdge + kIn + kJitter * (2.0 * v - 1.0)
                                                  : nearEdge + kIn + v * (b.size.x() - kIn - kBeforeFar);
  return Eigen::Vector2d(x, stepHeight > 0 ? b.size.z() : 0.0);
}

double terrainEndX(const TerrainDef& t) {
  return t.kind == TerrainDef::Kind::Stairs ? levels::stairsEndX(stairsOf(t, 0.1)) : 0.0;
}

Eigen::Vector2d stairsLandingX(const TerrainDef& t) {
  const levels::StairsDef d = stairsOf(t, 0.1);
  const double top = d.start.x() + (d.steps - 1) * d.run;
  return {top, top + d.top};
}

}  // namespace ai
