// physics_world.h — the 3D world (Bullet 3.24 btMultiBody, float build): ground, static boxes and
// articulations. Owned by the game loop and stepped with a fixed substep; Bullet types never leave the .cpp.
// Single-threaded; two worlds may run on two threads. Deterministic for the same sequence of calls.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/physics/articulation.h"

namespace engine {

/// World-wide settings.
struct PhysicsSettings {
  double gravity = 9.81;      ///< [m/s^2], along -Z
  int solverIterations = 10;  ///< constraint solver iterations per substep
  bool jointLimits = true;    ///< add a limit constraint per revolute joint
};

/// Handle of an articulation inside a PhysicsWorld.
using ArticulationId = int;

/// Handle of a ball (a dynamic sphere: the Mario ball, the kick skill's ball).
using BallId = int;

/// A ball's physical properties.
struct BallDef {
  double radius = 0.11;  ///< [m] (a size-5 football)
  double mass = 0.43;    ///< [kg]
  double friction = 0.6;
  double restitution = 0.6;       ///< bounciness, 0..1
  double rollingFriction = 0.01;  ///< [m] lever arm of Bullet's rolling resistance
};

/// A ball's state in world coordinates.
struct BallState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();
};

class PhysicsWorld {
 public:
  explicit PhysicsWorld(const PhysicsSettings& settings = {});
  ~PhysicsWorld();
  PhysicsWorld(const PhysicsWorld&) = delete;
  PhysicsWorld& operator=(const PhysicsWorld&) = delete;

  /// Adds the infinite ground plane z = height.
  void addGround(double friction, double height = 0.0);

  /// Adds a static box (centre, rotation, half sizes in metres). Returns its index.
  int addStaticBox(const Eigen::Vector3d& centre, const Eigen::Quaterniond& rotation,
                   const Eigen::Vector3d& halfExtents, double friction);

  /// Adds a ball at rest with its centre at `centre`. It never falls asleep (deterministic and responsive).
  BallId addBall(const BallDef& def, const Eigen::Vector3d& centre);

  /// The ball's position and velocities.
  BallState ballState(BallId id) const;

  /// Teleports the ball (position and velocities).
  void setBallState(BallId id, const BallState& state);

  /// Number of balls.
  int ballCount() const;

  /// Height of the highest static surface (ground plane, static boxes) under the point (x, y) at or below
  /// `fromZ` [m]: a ray cast straight down that passes through articulations and balls. -infinity if the ray,
  /// which reaches 10 m below `fromZ`, meets nothing. Read-only: it does not change the simulation.
  double groundHeight(double x, double y, double fromZ) const;

  /// Builds an articulation with its base link frame at basePose and all joints at q = 0.
  ArticulationId addArticulation(const ArticulationDef& def, const Eigen::Isometry3d& basePose, double friction);

  /// Sets base pose, base velocities (world) and joint positions/velocities at once (a teleport).
  void setState(ArticulationId id, const ArticulationState& state);

  /// Reads the full kinematic state.
  void readState(ArticulationId id, ArticulationState* state) const;

  /// World pose of a link frame (link -1 = base).
  Eigen::Isometry3d linkPose(ArticulationId id, int link) const;

  /// World position of the whole-body centre of mass [m].
  Eigen::Vector3d centreOfMass(ArticulationId id) const;

  /// Joint torques applied during the next substep only [N m], one per link.
  void setJointTorques(ArticulationId id, const double* tau);

  /// Sum of contact normal forces on a link during the last substep [N] (link -1 = base).
  double contactNormalForce(ArticulationId id, int link) const;

  /// Advances the world by dt seconds (one substep; no internal accumulator or interpolation).
  void step(double dt);

  /// Number of articulations.
  int articulationCount() const;

  /// Number of contact points touching articulation links after the last substep.
  int contactPointCount() const;

  /// Hash of the full dynamic state (bitwise), for replays and determinism tests.
  uint64_t stateHash() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace engine
