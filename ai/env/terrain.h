// terrain.h — building a skill's training or card terrain into a Bullet world (static boxes).
#pragma once

#include "engine/physics/physics_world.h"
#include "robot/skill_tree.h"

namespace ai {

/// Adds the terrain (flat: nothing) with this step height; the ground plane is the caller's.
void addTerrain(engine::PhysicsWorld& world, const robot::TerrainDef& terrain, double stepHeight, double friction);

/// Ceiling terrain: puts the ceiling over a robot that has lain down at `centre` (world x, y) facing `heading`
/// [rad]: a slab `length` long along the heading from `behind` metres behind the centre, `width` across (the
/// terrain's), its underside the terrain's height above the ground. Training uses a slab over the whole arena.
void addCeiling(engine::PhysicsWorld& world, const robot::TerrainDef& terrain, const Eigen::Vector2d& centre, double heading,
                double behind, double length, double width, double friction);

/// X of the far end of the stairs (where the last step down ends); 0 for flat terrain.
double terrainEndX(const robot::TerrainDef& terrain);

}  // namespace ai
