// terrain.cpp — see terrain.h. The staircase is the level format's (levels::expandStairs), so training, the
// card and levels build the same steps.
#include "ai/env/terrain.h"

#include <Eigen/Geometry>
#include <cmath>

#include "levels/level.h"

namespace ai {
namespace {

levels::StairsDef stairsOf(const robot::TerrainDef& t, double stepHeight) {
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

void addTerrain(engine::PhysicsWorld& world, const robot::TerrainDef& t, double stepHeight, double friction) {
  if (t.kind != robot::TerrainDef::Kind::Stairs || stepHeight <= 0) return;
  for (const levels::BoxDef& b : levels::expandStairs(stairsOf(t, stepHeight)))
    world.addStaticBox(b.centre, Eigen::Quaterniond::Identity(), 0.5 * b.size, friction);
}

void addCeiling(engine::PhysicsWorld& world, const robot::TerrainDef& t, const Eigen::Vector2d& centre, double heading,
                double behind, double length, double width, double friction) {
  if (t.kind != robot::TerrainDef::Kind::Ceiling) return;
  constexpr double kThickness = 0.2;
  const Eigen::Vector2d along(std::cos(heading), std::sin(heading));
  const Eigen::Vector2d mid = centre + along * (0.5 * length - behind);
  world.addStaticBox(Eigen::Vector3d(mid.x(), mid.y(), t.ceilingHeight + 0.5 * kThickness),
                     Eigen::Quaterniond(Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ())),
                     Eigen::Vector3d(0.5 * length, 0.5 * width, 0.5 * kThickness), friction);
}

double terrainEndX(const robot::TerrainDef& t) {
  return t.kind == robot::TerrainDef::Kind::Stairs ? levels::stairsEndX(stairsOf(t, 0.1)) : 0.0;
}

}  // namespace ai
