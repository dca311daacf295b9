// terrain.h — building a skill's training or card terrain into a Bullet world (static boxes).
#pragma once

#include "ai/tree/training_tree.h"
#include "engine/physics/physics_world.h"

namespace ai {

/// One episode's staircase: its terrain (the steps and tread) and its rise [m].
struct Staircase {
  TerrainDef terrain;
  double rise = 0;
};

/// The terrain as written at the lesson's step height, or, when `draw` draws (StairsDraw::drawn), a staircase with
/// its rise, tread and number of steps drawn uniformly from draw's ranges by u0, u1 and u2 in [0, 1).
Staircase drawStaircase(const TerrainDef& terrain, const StairsDraw& draw, double lessonRise, double u0, double u1,
                        double u2);

/// Adds the terrain (flat: nothing) with this step height; the ground plane is the caller's.
void addTerrain(engine::PhysicsWorld& world, const TerrainDef& terrain, double stepHeight, double friction);

/// Ceiling terrain: puts the ceiling over a robot that has lain down at `centre` (world x, y) facing `heading`
/// [rad]: a slab `length` long along the heading from `behind` metres behind the centre, `width` across (the
/// terrain's), its underside the terrain's height above the ground. Training uses a slab over the whole arena.
void addCeiling(engine::PhysicsWorld& world, const TerrainDef& terrain, const Eigen::Vector2d& centre, double heading,
                double behind, double length, double width, double friction);

/// Where a training episode that starts along the staircase puts the pelvis (TerrainDef::spawnAlong): on one of
/// its treads, the 2 * steps - 1 column tops up to the landing and down again, chosen by u in [0, 1) with equal
/// odds. On a tread one run deep the pelvis is 0.10 m past the tread's near edge, +-0.03 m by v in [0, 1] (the
/// G1's soles reach about 0.05 m behind and 0.13 m ahead of it in the default pose, so both stay on the tread);
/// on a deeper one (the landing) anywhere from 0.10 m in to 0.25 m before its far end. Returns (x, the tread's
/// height); flat terrain: (0, 0).
Eigen::Vector2d stairsSpawn(const TerrainDef& terrain, double stepHeight, double u, double v);

/// X of the far end of the stairs (where the last step down ends); 0 for flat terrain.
double terrainEndX(const TerrainDef& terrain);

/// Stairs: X where the landing begins (the top of the way up) and where it ends (the top of the way down).
Eigen::Vector2d stairsLandingX(const TerrainDef& terrain);

}  // namespace ai
