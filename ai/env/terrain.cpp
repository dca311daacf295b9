// terrain.cpp — see terrain.h. The staircase is the level format's (levels::expandStairs), so training, the
// card and levels build the same steps.
#include "ai/env/terrain.h"

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

double terrainEndX(const robot::TerrainDef& t) {
  return t.kind == robot::TerrainDef::Kind::Stairs ? levels::stairsEndX(stairsOf(t, 0.1)) : 0.0;
}

}  // namespace ai
