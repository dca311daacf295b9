// plane_world.cpp — Box2D 2.4 implementation of engine::PlaneWorld.
#include "engine/plane/plane_world.h"

#include <box2d/box2d.h>

#include <algorithm>

namespace engine {

struct PlaneWorld::Impl {
  b2World world{b2Vec2(0.0f, 0.0f)};
  std::vector<b2Body*> bodies;
};

PlaneWorld::PlaneWorld() : impl_(std::make_unique<Impl>()) {}
PlaneWorld::~PlaneWorld() = default;

void PlaneWorld::addStaticRect(const Eigen::Vector2d& centre, const Eigen::Vector2d& halfSize, double angle, int tag) {
  b2BodyDef def;
  def.type = b2_staticBody;
  def.position.Set(float(centre.x()), float(centre.y()));
  def.angle = float(angle);
  def.userData.pointer = static_cast<uintptr_t>(tag + 1);
  b2Body* body = impl_->world.CreateBody(&def);
  b2PolygonShape box;
  box.SetAsBox(float(halfSize.x()), float(halfSize.y()));
  body->CreateFixture(&box, 0.0f);
  impl_->bodies.push_back(body);
}

int PlaneWorld::addKinematicCircle(const Eigen::Vector2d& centre, double radius, int tag) {
  b2BodyDef def;
  def.type = b2_kinematicBody;
  def.position.Set(float(centre.x()), float(centre.y()));
  def.userData.pointer = static_cast<uintptr_t>(tag + 1);
  b2Body* body = impl_->world.CreateBody(&def);
  b2CircleShape circle;
  circle.m_radius = float(radius);
  b2FixtureDef fixture;
  fixture.shape = &circle;
  fixture.isSensor = true;  // it passes through the level; catching is a rule, not a collision
  body->CreateFixture(&fixture);
  impl_->bodies.push_back(body);
  return static_cast<int>(impl_->bodies.size()) - 1;
}

void PlaneWorld::setVelocity(int body, const Eigen::Vector2d& v) {
  impl_->bodies.at(static_cast<size_t>(body))->SetLinearVelocity(b2Vec2(float(v.x()), float(v.y())));
}

void PlaneWorld::setPosition(int body, const Eigen::Vector2d& centre) {
  b2Body* b = impl_->bodies.at(static_cast<size_t>(body));
  b->SetTransform(b2Vec2(float(centre.x()), float(centre.y())), b->GetAngle());
}

Eigen::Vector2d PlaneWorld::position(int body) const {
  const b2Vec2 p = impl_->bodies.at(static_cast<size_t>(body))->GetPosition();
  return Eigen::Vector2d(p.x, p.y);
}

RayHit PlaneWorld::rayCast(const Eigen::Vector2d& from, const Eigen::Vector2d& to) const {
  struct Closest : b2RayCastCallback {
    RayHit best;
    float ReportFixture(b2Fixture* f, const b2Vec2& p, const b2Vec2& n, float fraction) override {
      best.hit = true;
      best.point = Eigen::Vector2d(p.x, p.y);
      best.normal = Eigen::Vector2d(n.x, n.y);
      best.fraction = fraction;
      best.tag = static_cast<int>(f->GetBody()->GetUserData().pointer) - 1;
      return fraction;  // clip the ray: only closer hits are reported from now on
    }
  } cb;
  // Box2D works in float and asserts on a ray of zero length: one shorter than float's resolution hits nothing
  const b2Vec2 a(float(from.x()), float(from.y())), b(float(to.x()), float(to.y()));
  if ((b - a).LengthSquared() > 0.0f) impl_->world.RayCast(&cb, a, b);
  return cb.best;
}

std::vector<int> PlaneWorld::queryCircle(const Eigen::Vector2d& centre, double radius) const {
  struct Overlaps : b2QueryCallback {
    std::vector<b2Fixture*> found;
    bool ReportFixture(b2Fixture* f) override {
      found.push_back(f);
      return true;
    }
  } cb;
  b2AABB box;
  box.lowerBound = b2Vec2(float(centre.x() - radius), float(centre.y() - radius));
  box.upperBound = b2Vec2(float(centre.x() + radius), float(centre.y() + radius));
  impl_->world.QueryAABB(&cb, box);

  // exact test of each candidate against the circle
  b2CircleShape circle;
  circle.m_radius = float(radius);
  const b2Transform at(b2Vec2(float(centre.x()), float(centre.y())), b2Rot(0.0f));
  std::vector<std::pair<size_t, int>> hits;
  for (b2Fixture* f : cb.found) {
    if (!b2TestOverlap(f->GetShape(), 0, &circle, 0, f->GetBody()->GetTransform(), at)) continue;
    const size_t order = static_cast<size_t>(std::find(impl_->bodies.begin(), impl_->bodies.end(), f->GetBody()) -
                                             impl_->bodies.begin());
    hits.emplace_back(order, static_cast<int>(f->GetBody()->GetUserData().pointer) - 1);
  }
  std::sort(hits.begin(), hits.end());
  std::vector<int> tags;
  for (const auto& h : hits)
    if (std::find(tags.begin(), tags.end(), h.second) == tags.end()) tags.push_back(h.second);
  return tags;
}

void PlaneWorld::step(double dt) { impl_->world.Step(float(dt), 8, 3); }

int PlaneWorld::bodyCount() const { return static_cast<int>(impl_->bodies.size()); }

bool PlaneWorld::staticBounds(Eigen::Vector2d* lo, Eigen::Vector2d* hi) const {
  bool any = false;
  Eigen::Vector2d low(0, 0), high(0, 0);
  for (const b2Body* body : impl_->bodies) {
    if (body->GetType() != b2_staticBody) continue;
    for (const b2Fixture* f = body->GetFixtureList(); f; f = f->GetNext()) {
      for (int child = 0; child < f->GetShape()->GetChildCount(); ++child) {
        b2AABB box;
        f->GetShape()->ComputeAABB(&box, body->GetTransform(), child);
        const Eigen::Vector2d a(box.lowerBound.x, box.lowerBound.y), b(box.upperBound.x, box.upperBound.y);
        low = any ? low.cwiseMin(a) : a;
        high = any ? high.cwiseMax(b) : b;
        any = true;
      }
    }
  }
  if (!any) return false;
  *lo = low;
  *hi = high;
  return true;
}

}  // namespace engine
