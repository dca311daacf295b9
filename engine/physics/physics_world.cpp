// physics_world.cpp — Bullet btMultiBody implementation of engine::PhysicsWorld.
// Link frames (URDF) are converted to Bullet's per-link principal-inertia frames once, at build time;
// every public call speaks link frames. Rotor inertia is expected inside LinkDef::inertia already.
#include "engine/physics/physics_world.h"

#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>
#include <btBulletDynamicsCommon.h>

#include <Eigen/Eigenvalues>
#include <limits>

#include "engine/core/error.h"
#include "engine/core/hash.h"

namespace engine {
namespace {

btVector3 toBt(const Eigen::Vector3d& v) { return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z())); }
btQuaternion toBt(const Eigen::Quaterniond& q) {
  return btQuaternion(btScalar(q.x()), btScalar(q.y()), btScalar(q.z()), btScalar(q.w()));
}
btTransform toBt(const Eigen::Isometry3d& t) {
  return btTransform(toBt(Eigen::Quaterniond(t.rotation())), toBt(Eigen::Vector3d(t.translation())));
}
Eigen::Vector3d toEigen(const btVector3& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Quaterniond toEigen(const btQuaternion& q) { return Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()); }

// the principal-axes frame of a link's inertia, in the link frame, and the principal moments
struct InertialFrame {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Eigen::Vector3d moments = Eigen::Vector3d::Ones();
};

InertialFrame principalFrame(const LinkDef& link) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(link.inertia);
  Eigen::Matrix3d axes = solver.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) *= -1.0;
  InertialFrame f;
  f.pose.linear() = axes;
  f.pose.translation() = link.com;
  f.moments = solver.eigenvalues().cwiseMax(1e-9);
  return f;
}

}  // namespace

struct PhysicsWorld::Impl {
  struct Articulation {
    btMultiBody* body = nullptr;
    std::vector<Eigen::Isometry3d> inertialInLink;  // index 0 = base, i + 1 = link i
    std::vector<double> contactForce;               // same indexing
    std::vector<double> mass;                       // same indexing
  };

  PhysicsSettings settings;
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btMultiBodyConstraintSolver solver;
  std::unique_ptr<btMultiBodyDynamicsWorld> world;

  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btCollisionObject>> objects;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> constraints;
  std::vector<std::unique_ptr<btMultiBody>> bodies;
  std::vector<Articulation> articulations;
  std::vector<btRigidBody*> balls;  // owned by `objects`
  int contactPoints = 0;
  double lastDt = 0.002;

  btCollisionShape* own(btCollisionShape* s) {
    shapes.emplace_back(s);
    return s;
  }

  const Articulation& get(ArticulationId id) const {
    if (id < 0 || id >= static_cast<int>(articulations.size())) throw Error("physics: bad articulation id");
    return articulations[static_cast<size_t>(id)];
  }

  btCollisionShape* makeLinkShape(const LinkDef& link, const Eigen::Isometry3d& inertialInLink) {
    if (link.colliders.empty()) return nullptr;
    auto* compound = static_cast<btCompoundShape*>(own(new btCompoundShape()));
    for (const ColliderDef& c : link.colliders) {
      btCollisionShape* s = nullptr;
      switch (c.kind) {
        case ShapeKind::Box:
          s = own(new btBoxShape(toBt(c.halfExtents)));
          break;
        case ShapeKind::Sphere:
          s = own(new btSphereShape(btScalar(c.radius)));
          break;
        case ShapeKind::Capsule:
          s = own(new btCapsuleShapeZ(btScalar(c.radius), btScalar(2.0 * c.halfLength)));
          break;
        case ShapeKind::Plane:
          throw Error("physics: a link collider cannot be a plane");
      }
      compound->addChildShape(toBt(inertialInLink.inverse() * c.pose), s);
    }
    return compound;
  }
};

PhysicsWorld::PhysicsWorld(const PhysicsSettings& settings) : impl_(std::make_unique<Impl>()) {
  impl_->settings = settings;
  impl_->world = std::make_unique<btMultiBodyDynamicsWorld>(&impl_->dispatcher, &impl_->broadphase, &impl_->solver,
                                                            &impl_->config);
  impl_->world->setGravity(btVector3(0, 0, btScalar(-settings.gravity)));
  impl_->world->getSolverInfo().m_numIterations = settings.solverIterations;
}

PhysicsWorld::~PhysicsWorld() {
  // remove everything from the world before the owners below free it
  auto* w = impl_->world.get();
  for (auto& c : impl_->constraints) w->removeMultiBodyConstraint(c.get());
  for (auto& c : impl_->colliders) w->removeCollisionObject(c.get());
  for (auto& b : impl_->bodies) w->removeMultiBody(b.get());
  for (auto& o : impl_->objects) {
    if (auto* rb = btRigidBody::upcast(o.get()))
      w->removeRigidBody(rb);
    else
      w->removeCollisionObject(o.get());
  }
  impl_->world.reset();
}

void PhysicsWorld::addGround(double friction, double height) {
  auto* shape = impl_->own(new btStaticPlaneShape(btVector3(0, 0, 1), btScalar(height)));
  btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, shape);
  info.m_friction = btScalar(friction);
  auto* body = new btRigidBody(info);
  impl_->objects.emplace_back(body);
  impl_->world->addRigidBody(body);
}

int PhysicsWorld::addStaticBox(const Eigen::Vector3d& centre, const Eigen::Quaterniond& rotation,
                               const Eigen::Vector3d& halfExtents, double friction) {
  auto* shape = impl_->own(new btBoxShape(toBt(halfExtents)));
  btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, shape);
  info.m_friction = btScalar(friction);
  info.m_startWorldTransform = btTransform(toBt(rotation), toBt(centre));
  auto* body = new btRigidBody(info);
  impl_->objects.emplace_back(body);
  impl_->world->addRigidBody(body);
  return static_cast<int>(impl_->objects.size()) - 1;
}

double PhysicsWorld::groundHeight(double x, double y, double fromZ) const {
  const btVector3 from{btScalar(x), btScalar(y), btScalar(fromZ)};
  const btVector3 to{btScalar(x), btScalar(y), btScalar(fromZ - 10.0)};
  btCollisionWorld::ClosestRayResultCallback hit(from, to);
  hit.m_collisionFilterMask = btBroadphaseProxy::StaticFilter;  // static bodies only: not the robot, not a ball
  impl_->world->rayTest(from, to, hit);
  if (!hit.hasHit()) return -std::numeric_limits<double>::infinity();
  return double(hit.m_hitPointWorld.z());
}

BallId PhysicsWorld::addBall(const BallDef& def, const Eigen::Vector3d& centre) {
  if (!(def.radius > 0) || !(def.mass > 0)) throw Error("physics: a ball needs a positive radius and mass");
  auto* shape = impl_->own(new btSphereShape(btScalar(def.radius)));
  btVector3 inertia(0, 0, 0);
  shape->calculateLocalInertia(btScalar(def.mass), inertia);
  btRigidBody::btRigidBodyConstructionInfo info(btScalar(def.mass), nullptr, shape, inertia);
  info.m_friction = btScalar(def.friction);
  info.m_restitution = btScalar(def.restitution);
  info.m_rollingFriction = btScalar(def.rollingFriction);
  info.m_startWorldTransform = btTransform(btQuaternion::getIdentity(), toBt(centre));
  auto* body = new btRigidBody(info);
  body->setActivationState(DISABLE_DEACTIVATION);
  impl_->objects.emplace_back(body);
  impl_->world->addRigidBody(body);
  impl_->balls.push_back(body);
  return static_cast<BallId>(impl_->balls.size()) - 1;
}

BallState PhysicsWorld::ballState(BallId id) const {
  if (id < 0 || id >= ballCount()) throw Error("physics: bad ball id");
  const btRigidBody* b = impl_->balls[static_cast<size_t>(id)];
  BallState s;
  const btVector3& p = b->getWorldTransform().getOrigin();
  s.position = Eigen::Vector3d(p.x(), p.y(), p.z());
  s.velocity = Eigen::Vector3d(b->getLinearVelocity().x(), b->getLinearVelocity().y(), b->getLinearVelocity().z());
  s.angularVelocity =
      Eigen::Vector3d(b->getAngularVelocity().x(), b->getAngularVelocity().y(), b->getAngularVelocity().z());
  return s;
}

void PhysicsWorld::setBallState(BallId id, const BallState& s) {
  if (id < 0 || id >= ballCount()) throw Error("physics: bad ball id");
  btRigidBody* b = impl_->balls[static_cast<size_t>(id)];
  b->setWorldTransform(btTransform(btQuaternion::getIdentity(), toBt(s.position)));
  b->setLinearVelocity(toBt(s.velocity));
  b->setAngularVelocity(toBt(s.angularVelocity));
}

int PhysicsWorld::ballCount() const { return static_cast<int>(impl_->balls.size()); }

ArticulationId PhysicsWorld::addArticulation(const ArticulationDef& def, const Eigen::Isometry3d& basePose,
                                             double friction) {
  const int n = static_cast<int>(def.links.size());
  Impl::Articulation art;

  // principal inertia frames and zero-pose world transforms of every link frame and inertial frame
  std::vector<InertialFrame> inertial(static_cast<size_t>(n) + 1);
  std::vector<Eigen::Isometry3d> linkWorld(static_cast<size_t>(n) + 1), inWorld(static_cast<size_t>(n) + 1);
  inertial[0] = principalFrame(def.base);
  linkWorld[0] = basePose;
  inWorld[0] = basePose * inertial[0].pose;
  for (int i = 0; i < n; ++i) {
    const LinkDef& l = def.links[static_cast<size_t>(i)];
    if (l.parent < -1 || l.parent >= i) throw Error("physics: link '" + l.name + "' comes before its parent");
    const size_t k = static_cast<size_t>(i) + 1;
    inertial[k] = principalFrame(l);
    linkWorld[k] = linkWorld[static_cast<size_t>(l.parent + 1)] * l.jointFrame;
    inWorld[k] = linkWorld[k] * inertial[k].pose;
  }

  auto* mb = new btMultiBody(n, btScalar(def.base.mass), toBt(inertial[0].moments), false, false);
  impl_->bodies.emplace_back(mb);
  mb->setBasePos(toBt(Eigen::Vector3d(inWorld[0].translation())));
  mb->setWorldToBaseRot(toBt(Eigen::Quaterniond(inWorld[0].rotation())).inverse());
  art.inertialInLink.push_back(inertial[0].pose);
  art.mass.push_back(def.base.mass);

  for (int i = 0; i < n; ++i) {
    const LinkDef& l = def.links[static_cast<size_t>(i)];
    const size_t k = static_cast<size_t>(i) + 1, p = static_cast<size_t>(l.parent + 1);
    const Eigen::Matrix3d rThis = inWorld[k].rotation(), rParent = inWorld[p].rotation();
    const Eigen::Vector3d pivot = linkWorld[k].translation();
    const Eigen::Quaterniond parentToThis(rThis.transpose() * rParent);
    const Eigen::Vector3d axisInThis = inertial[k].pose.linear().transpose() * l.axis.normalized();
    const Eigen::Vector3d parentComToPivot = rParent.transpose() * (pivot - inWorld[p].translation());
    const Eigen::Vector3d pivotToCom = rThis.transpose() * (inWorld[k].translation() - pivot);
    mb->setupRevolute(i, btScalar(l.mass), toBt(inertial[k].moments), l.parent, toBt(parentToThis), toBt(axisInThis),
                      toBt(parentComToPivot), toBt(pivotToCom), true);
    art.inertialInLink.push_back(inertial[k].pose);
    art.mass.push_back(l.mass);
  }
  mb->finalizeMultiDof();
  mb->setHasSelfCollision(false);
  mb->setLinearDamping(0);
  mb->setAngularDamping(0);
  mb->setCanSleep(false);
  impl_->world->addMultiBody(mb);

  // colliders: one compound per link, children placed in the link's inertial frame
  for (int i = -1; i < n; ++i) {
    const LinkDef& l = i < 0 ? def.base : def.links[static_cast<size_t>(i)];
    const size_t k = static_cast<size_t>(i + 1);
    btCollisionShape* shape = impl_->makeLinkShape(l, inertial[k].pose);
    if (!shape) continue;
    auto* col = new btMultiBodyLinkCollider(mb, i);
    impl_->colliders.emplace_back(col);
    col->setCollisionShape(shape);
    col->setWorldTransform(toBt(inWorld[k]));
    col->setFriction(btScalar(friction));
    impl_->world->addCollisionObject(col, btBroadphaseProxy::DefaultFilter, btBroadphaseProxy::AllFilter);
    if (i < 0)
      mb->setBaseCollider(col);
    else
      mb->getLink(i).m_collider = col;
  }
  if (impl_->settings.jointLimits) {
    for (int i = 0; i < n; ++i) {
      const LinkDef& l = def.links[static_cast<size_t>(i)];
      auto* c = new btMultiBodyJointLimitConstraint(mb, i, btScalar(l.lower), btScalar(l.upper));
      impl_->constraints.emplace_back(c);
      impl_->world->addMultiBodyConstraint(c);
    }
  }
  art.body = mb;
  art.contactForce.assign(static_cast<size_t>(n) + 1, 0.0);
  impl_->articulations.push_back(std::move(art));

  btAlignedObjectArray<btQuaternion> scratchQ;
  btAlignedObjectArray<btVector3> scratchM;
  mb->forwardKinematics(scratchQ, scratchM);
  mb->updateCollisionObjectWorldTransforms(scratchQ, scratchM);
  return static_cast<ArticulationId>(impl_->articulations.size()) - 1;
}

void PhysicsWorld::setState(ArticulationId id, const ArticulationState& s) {
  const Impl::Articulation& a = impl_->get(id);
  btMultiBody* mb = a.body;
  const Eigen::Isometry3d& base = a.inertialInLink[0];
  const Eigen::Matrix3d rLink = s.baseRotation.toRotationMatrix();
  const Eigen::Vector3d com = s.basePosition + rLink * base.translation();
  mb->setBasePos(toBt(com));
  mb->setWorldToBaseRot(toBt(Eigen::Quaterniond(rLink * base.linear())).inverse());
  mb->setBaseOmega(toBt(s.baseAngularVelocity));
  mb->setBaseVel(toBt(s.baseLinearVelocity + s.baseAngularVelocity.cross(com - s.basePosition)));
  for (int i = 0; i < mb->getNumLinks(); ++i) {
    mb->setJointPos(i, btScalar(s.q.at(static_cast<size_t>(i))));
    mb->setJointVel(i, btScalar(s.qd.at(static_cast<size_t>(i))));
  }
  btAlignedObjectArray<btQuaternion> scratchQ;
  btAlignedObjectArray<btVector3> scratchM;
  mb->forwardKinematics(scratchQ, scratchM);
  mb->updateCollisionObjectWorldTransforms(scratchQ, scratchM);
}

void PhysicsWorld::readState(ArticulationId id, ArticulationState* s) const {
  const Impl::Articulation& a = impl_->get(id);
  const btMultiBody* mb = a.body;
  const Eigen::Isometry3d& base = a.inertialInLink[0];
  const Eigen::Quaterniond rIn = toEigen(mb->getWorldToBaseRot()).conjugate();
  const Eigen::Matrix3d rLink = rIn.toRotationMatrix() * base.linear().transpose();
  const Eigen::Vector3d com = toEigen(mb->getBasePos());
  s->baseRotation = Eigen::Quaterniond(rLink).normalized();
  s->basePosition = com - rLink * base.translation();
  s->baseAngularVelocity = toEigen(mb->getBaseOmega());
  s->baseLinearVelocity = toEigen(mb->getBaseVel()) + s->baseAngularVelocity.cross(s->basePosition - com);
  const size_t n = static_cast<size_t>(mb->getNumLinks());
  s->q.resize(n);
  s->qd.resize(n);
  for (size_t i = 0; i < n; ++i) {
    s->q[i] = mb->getJointPos(static_cast<int>(i));
    s->qd[i] = mb->getJointVel(static_cast<int>(i));
  }
}

Eigen::Isometry3d PhysicsWorld::linkPose(ArticulationId id, int link) const {
  const Impl::Articulation& a = impl_->get(id);
  Eigen::Isometry3d inertialWorld;
  if (link < 0) {
    inertialWorld.linear() = toEigen(a.body->getWorldToBaseRot()).conjugate().toRotationMatrix();
    inertialWorld.translation() = toEigen(a.body->getBasePos());
  } else {
    const btTransform& t = a.body->getLink(link).m_cachedWorldTransform;
    inertialWorld.linear() = toEigen(t.getRotation()).toRotationMatrix();
    inertialWorld.translation() = toEigen(t.getOrigin());
  }
  inertialWorld.makeAffine();
  return inertialWorld * a.inertialInLink[static_cast<size_t>(link + 1)].inverse();
}

Eigen::Vector3d PhysicsWorld::centreOfMass(ArticulationId id) const {
  const Impl::Articulation& a = impl_->get(id);
  Eigen::Vector3d sum = a.mass[0] * toEigen(a.body->getBasePos());
  double total = a.mass[0];
  for (int i = 0; i < a.body->getNumLinks(); ++i) {
    const double m = a.mass[static_cast<size_t>(i) + 1];
    sum += m * toEigen(a.body->getLink(i).m_cachedWorldTransform.getOrigin());
    total += m;
  }
  return sum / total;
}

void PhysicsWorld::setJointTorques(ArticulationId id, const double* tau) {
  btMultiBody* mb = impl_->get(id).body;
  for (int i = 0; i < mb->getNumLinks(); ++i) mb->addJointTorque(i, btScalar(tau[i]));
}

double PhysicsWorld::contactNormalForce(ArticulationId id, int link) const {
  return impl_->get(id).contactForce.at(static_cast<size_t>(link + 1));
}

void PhysicsWorld::step(double dt) {
  impl_->lastDt = dt;
  impl_->world->stepSimulation(btScalar(dt), 0, btScalar(dt));

  // torques last one substep; gather contact normal forces per link (impulse / dt)
  for (auto& a : impl_->articulations) {
    a.body->clearForcesAndTorques();
    std::fill(a.contactForce.begin(), a.contactForce.end(), 0.0);
  }
  impl_->contactPoints = 0;
  btDispatcher* d = impl_->world->getDispatcher();
  for (int m = 0; m < d->getNumManifolds(); ++m) {
    btPersistentManifold* manifold = d->getManifoldByIndexInternal(m);
    const btCollisionObject* bodies[2] = {manifold->getBody0(), manifold->getBody1()};
    for (const btCollisionObject* o : bodies) {
      const auto* col = btMultiBodyLinkCollider::upcast(o);
      if (!col) continue;
      for (auto& a : impl_->articulations) {
        if (a.body != col->m_multiBody) continue;
        for (int p = 0; p < manifold->getNumContacts(); ++p) {
          const btManifoldPoint& pt = manifold->getContactPoint(p);
          if (pt.getDistance() > btScalar(0.001)) continue;
          a.contactForce[static_cast<size_t>(col->m_link + 1)] += double(pt.m_appliedImpulse) / dt;
          ++impl_->contactPoints;
        }
      }
    }
  }
}

int PhysicsWorld::articulationCount() const { return static_cast<int>(impl_->articulations.size()); }

int PhysicsWorld::contactPointCount() const { return impl_->contactPoints; }

uint64_t PhysicsWorld::stateHash() const {
  Hasher h;
  auto vec = [&](const btVector3& v) {
    h.value(v.x());
    h.value(v.y());
    h.value(v.z());
  };
  for (const auto& a : impl_->articulations) {
    const btMultiBody* mb = a.body;
    vec(mb->getBasePos());
    const btQuaternion& r = mb->getWorldToBaseRot();
    h.value(r.x());
    h.value(r.y());
    h.value(r.z());
    h.value(r.w());
    vec(mb->getBaseVel());
    vec(mb->getBaseOmega());
    for (int i = 0; i < mb->getNumLinks(); ++i) {
      h.value(mb->getJointPos(i));
      h.value(mb->getJointVel(i));
    }
  }
  for (const btRigidBody* b : impl_->balls) {
    vec(b->getWorldTransform().getOrigin());
    const btQuaternion r = b->getWorldTransform().getRotation();
    h.value(r.x());
    h.value(r.y());
    h.value(r.z());
    h.value(r.w());
    vec(b->getLinearVelocity());
    vec(b->getAngularVelocity());
  }
  return h.value();
}

}  // namespace engine
