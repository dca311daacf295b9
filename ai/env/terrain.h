// terrain.h — building a skill's training or card terrain into a Bullet world (static boxes).
#pragma once

#include "engine/physics/physics_world.h"
#include "robot/skill_tree.h"

namespace ai {

/// Adds the terrain (flat: nothing) with this step height; the ground plane is the caller's.
void addTerrain(engine::PhysicsWorld& world, const robot::TerrainDef& terrain, double stepHeight, double friction);

/// X of the far end of the stairs (where the last step down ends); 0 for flat terrain.
double terrainEndX(const robot::TerrainDef& terrain);

}  // namespace ai
