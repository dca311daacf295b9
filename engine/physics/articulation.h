// articulation.h — plain-data description of an articulated body (a floating base and revolute links),
// built by robot/ from a URDF and turned into a Bullet btMultiBody by engine::PhysicsWorld.
// Frames follow URDF: a link frame sits on its joint axis; inertia is about the CoM in link-frame axes.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "engine/render/scene_snapshot.h"

namespace engine {

/// A primitive collider attached to a link. Capsule axis is local Z.
struct ColliderDef {
  std::string name;
  ShapeKind kind = ShapeKind::Box;                         ///< Box, Sphere or Capsule
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< collider frame in the link frame
  Eigen::Vector3d halfExtents = Eigen::Vector3d::Zero();   ///< Box half sizes [m]
  double radius = 0.0;                                     ///< Sphere/Capsule radius [m]
  double halfLength = 0.0;                                 ///< Capsule half segment length [m]
};

/// One body of the articulation. For the base, the joint fields are unused.
struct LinkDef {
  std::string name;
  int parent = -1;                                ///< index into ArticulationDef::links, -1 = base
  double mass = 0.0;                              ///< [kg]
  Eigen::Vector3d com = Eigen::Vector3d::Zero();  ///< CoM in the link frame [m]
  Eigen::Matrix3d inertia =
      Eigen::Matrix3d::Identity();  ///< about the CoM, link axes [kg m^2] (rotor inertia included)
  std::string joint;                ///< name of the joint to the parent
  Eigen::Isometry3d jointFrame = Eigen::Isometry3d::Identity();  ///< joint frame in the parent link frame (q = 0)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();               ///< revolute axis in the joint (= link) frame
  double lower = 0.0, upper = 0.0;                               ///< joint limits [rad]
  std::vector<ColliderDef> colliders;
};

/// A floating-base articulation: base + links in topological order (parents before children).
struct ArticulationDef {
  LinkDef base;
  std::vector<LinkDef> links;
};

/// Kinematic state of an articulation, in world coordinates.
struct ArticulationState {
  Eigen::Vector3d basePosition = Eigen::Vector3d::Zero();            ///< base link-frame origin [m]
  Eigen::Quaterniond baseRotation = Eigen::Quaterniond::Identity();  ///< base link frame -> world
  Eigen::Vector3d baseLinearVelocity = Eigen::Vector3d::Zero();      ///< of the base origin, world [m/s]
  Eigen::Vector3d baseAngularVelocity = Eigen::Vector3d::Zero();     ///< world [rad/s]
  std::vector<double> q;                                             ///< joint positions [rad], link order
  std::vector<double> qd;                                            ///< joint velocities [rad/s]
};

}  // namespace engine
