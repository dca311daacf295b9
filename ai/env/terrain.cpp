// terrain.cpp — see terrain.h. Step i (1-based) of the way up is a box from the ground to i * height.
#include "ai/env/terrain.h"

namespace ai {

void addTerrain(engine::PhysicsWorld& world, const robot::TerrainDef& t, double stepHeight, double friction) {
  if (t.kind != robot::TerrainDef::Kind::Stairs || stepHeight <= 0) return;
  const Eigen::Quaterniond level = Eigen::Quaterniond::Identity();
  auto box = [&](double x0, double x1, double top) {
    world.addStaticBox(Eigen::Vector3d(0.5 * (x0 + x1), 0, 0.5 * top), level,
                       Eigen::Vector3d(0.5 * (x1 - x0), 0.5 * t.width, 0.5 * top), friction);
  };
  const double upEnd = t.startX + t.steps * t.stepDepth, downStart = upEnd + t.topDepth;
  for (int i = 1; i <= t.steps; ++i) {
    const double top = i * stepHeight;
    box(t.startX + (i - 1) * t.stepDepth, t.startX + i * t.stepDepth, top);                  // up
    box(downStart + (t.steps - i) * t.stepDepth, downStart + (t.steps - i + 1) * t.stepDepth, top);  // down
  }
  box(upEnd, downStart, t.steps * stepHeight);  // the landing
}

double terrainEndX(const robot::TerrainDef& t) {
  if (t.kind != robot::TerrainDef::Kind::Stairs) return 0;
  return t.startX + 2 * t.steps * t.stepDepth + t.topDepth;
}

}  // namespace ai
