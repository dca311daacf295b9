// kinematics.h — forward kinematics of an ArticulationDef with the base at the origin (pure Eigen),
// used for the spawn height and in tests; the simulation itself reads poses from the physics world.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "engine/physics/articulation.h"

namespace robot {

/// Link-frame poses for joint positions q (base frame = identity); result[0] is the base, [i + 1] link i.
std::vector<Eigen::Isometry3d> forwardKinematics(const engine::ArticulationDef& def, const std::vector<double>& q);

/// Lowest z of any collider surface (base at the origin) for joint positions q [m].
double lowestColliderPoint(const engine::ArticulationDef& def, const std::vector<double>& q);

}  // namespace robot
