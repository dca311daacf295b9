// plane_world.h — a level's 2D layer (Box2D 2.4): static obstacles projected into the level's plane
// (the Mario side plane or the garden's top-down map), later ghosts; ray casts and proximity queries for
// the autopilot. Stepped on the fixed tick by the game loop; Box2D types stay in the .cpp.
// What a body's tag means (a wall, a staircase and its axis, something movable): engine/plane/plane_tags.h.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace engine {

/// Closest hit of a ray cast.
struct RayHit {
  bool hit = false;
  Eigen::Vector2d point = Eigen::Vector2d::Zero();   ///< [m]
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();  ///< unit surface normal at the hit
  double fraction = 1.0;                             ///< along the ray, 0..1
  int tag = -1;                                      ///< tag of the body hit
};

class PlaneWorld {
 public:
  PlaneWorld();
  ~PlaneWorld();
  PlaneWorld(const PlaneWorld&) = delete;
  PlaneWorld& operator=(const PlaneWorld&) = delete;

  /// Adds a static rectangle (centre, half sizes in metres, rotation in radians) carrying a caller's tag.
  void addStaticRect(const Eigen::Vector2d& centre, const Eigen::Vector2d& halfSize, double angle, int tag);

  /// Adds a kinematic circle (moved only by its velocity, e.g. a ghost) at centre; returns a handle.
  int addKinematicCircle(const Eigen::Vector2d& centre, double radius, int tag);

  /// Sets a kinematic body's velocity [m/s] (it moves by it in step()).
  void setVelocity(int body, const Eigen::Vector2d& velocity);
  /// Moves a body to `centre` at once (a teleport; its velocity is kept).
  void setPosition(int body, const Eigen::Vector2d& centre);

  /// A body's current position.
  Eigen::Vector2d position(int body) const;

  /// Closest hit along the segment from -> to.
  RayHit rayCast(const Eigen::Vector2d& from, const Eigen::Vector2d& to) const;

  /// Tags of bodies whose shapes overlap the circle (centre, radius), in creation order, without duplicates.
  std::vector<int> queryCircle(const Eigen::Vector2d& centre, double radius) const;

  /// Advances dynamic bodies by dt seconds (fixed tick).
  void step(double dt);

  /// Number of bodies.
  int bodyCount() const;

  /// The bounding box of every static body's shape (lower-left in *lo, upper-right in *hi) [m]; false (and the
  /// outputs untouched) when there is none. A map of the layer (the garden's navigation) covers this rectangle.
  bool staticBounds(Eigen::Vector2d* lo, Eigen::Vector2d* hi) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace engine
