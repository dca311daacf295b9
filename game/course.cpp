// course.cpp — see course.h. Geometry is simple on purpose: the robot is a set of spheres (its colliders),
// coins and releases are spheres, boxes and goals are axis-aligned.
#include "game/course.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/loop/clock.h"
#include "engine/plane/plane_tags.h"

namespace game {
namespace {

constexpr uint32_t kCoinColour = 0xffd700ff, kGiftColour = 0xff4fa3ff;
constexpr uint32_t kBoxColour = 0xf5b041ff, kUsedBoxColour = 0x8b5a2bff;
constexpr uint32_t kGhostColour = 0xeef0ffb0, kBallColour = 0xf4f4f4ff, kGoalColour = 0x40c04050;
constexpr double kReleaseRise = 0.4;         // a release pops this far above its box [m] ...
constexpr double kReleaseRiseSeconds = 0.4;  // ... in this long, then floats down in front of it
constexpr double kReleaseSettleSeconds = 0.8;
constexpr double kReleaseForward = 0.6;  // where it settles: this far past the box, at kReleaseHeight
constexpr double kReleaseHeight = 0.9;
constexpr double kHitMargin = 0.03;   // a head or hand this close below a box counts as touching it
constexpr double kHitUpSpeed = 0.05;  // ... if the pelvis moves up at least this fast [m/s]

double smooth(double t) { return t <= 0 ? 0 : t >= 1 ? 1 : t * t * (3 - 2 * t); }

}  // namespace

Course::Course(const levels::Level& level, engine::PhysicsWorld& physics, engine::PlaneWorld& plane)
    : rules_(level.rules),
      timeLimit_(level.isGame() ? level.timeLimit : 0.0),
      goals_(level.goals),
      checkpointX_(level.spawn.x()) {
  for (const levels::CoinDef& c : level.coins) {
    Collectable item;
    item.position = c.centre;
    item.radius = c.radius;
    items_.push_back(item);
  }
  for (size_t i = 0; i < level.questionBoxes.size(); ++i) {
    const levels::QuestionBoxDef& q = level.questionBoxes[i];
    boxes_.push_back({q, false});
    physics.addStaticBox(q.centre, Eigen::Quaterniond::Identity(), 0.5 * q.size, 1.0);
    plane.addStaticRect({q.centre.x(), q.centre.z()}, {0.5 * q.size.x(), 0.5 * q.size.z()}, 0.0,
                        int(level.boxes.size() + i));
  }
  for (const levels::GhostDef& g : level.ghosts) ghosts_.push_back({g, -1, false, false, g.speed});
  for (const levels::BallSpawnDef& b : level.balls) {
    engine::BallDef def;
    def.radius = b.radius;
    def.mass = b.mass;
    Ball ball{physics.addBall(def, Eigen::Vector3d(b.position.x(), b.position.y(), b.radius)), b.radius};
    // a map's 2D layer shows each ball as a moving circle (engine::isMovableTag), so the navigation sees it
    if (level.plane == levels::Plane2d::Top)
      ball.mirror = plane.addKinematicCircle(b.position, b.radius, engine::kMovableTagBase + int(balls_.size()));
    balls_.push_back(ball);
  }
}

void Course::finish(int64_t tick, Outcome outcome, const std::string& reason) {
  if (outcome_ != Outcome::Playing) return;
  outcome_ = outcome;
  reason_ = reason;
  log(tick, outcome == Outcome::Won ? CourseEventKind::Won : CourseEventKind::Lost,
      (outcome == Outcome::Won ? "won: " : "lost: ") + reason);
}

void Course::update(int64_t tick, const robot::Sensors& sensors, const std::vector<BodyPoint>& body,
                    engine::PhysicsWorld& physics, engine::PlaneWorld& plane) {
  for (const Ball& b : balls_)  // the 2D layer's circles follow the balls (before anything can end the run)
    if (b.mirror >= 0) {
      const Eigen::Vector3d p = physics.ballState(b.id).position;
      plane.setPosition(b.mirror, p.head<2>());
    }
  if (outcome_ != Outcome::Playing) return;
  const double t = double(tick) * engine::kTickSeconds;
  const Eigen::Vector3d pelvis = sensors.basePosition;
  const Eigen::Vector3d pelvisVelocity = sensors.baseRotation * sensors.linearVelocity;

  for (double cp : rules_.checkpoints)
    if (pelvis.x() >= cp && cp > checkpointX_) {
      checkpointX_ = cp;
      fallsHere_.clear();  // a new checkpoint: its own count of falls
      log(tick, CourseEventKind::Checkpoint, "checkpoint at x = " + std::to_string(cp).substr(0, 5));
    }

  // question boxes: a head or hand touching the underside while the robot moves up
  for (Box& b : boxes_) {
    if (b.used) continue;
    const Eigen::Vector3d half = 0.5 * b.def.size;
    const double bottom = b.def.centre.z() - half.z();
    for (const BodyPoint& p : body) {
      if (!p.head && !p.hand) continue;
      const bool under = std::abs(p.position.x() - b.def.centre.x()) <= half.x() + p.radius &&
                         std::abs(p.position.y() - b.def.centre.y()) <= half.y() + p.radius;
      if (under && p.position.z() + p.radius >= bottom - kHitMargin && p.position.z() < bottom &&
          pelvisVelocity.z() > kHitUpSpeed) {
        b.used = true;
        Collectable item;
        item.gift = b.def.gift;
        item.releasedTick = tick;
        item.from = Eigen::Vector3d(b.def.centre.x(), b.def.centre.y(), b.def.centre.z() + half.z() + 0.15);
        item.position = item.from;
        items_.push_back(item);
        log(tick, CourseEventKind::BoxHit,
            std::string("question box at x = ") + std::to_string(b.def.centre.x()).substr(0, 5) + " hit: a " +
                (b.def.gift ? "gift" : "coin") + " pops out");
        break;
      }
    }
  }

  // releases move; anything the body touches is collected
  for (Collectable& c : items_) {
    if (c.collected) continue;
    if (c.releasedTick >= 0) {
      const double age = double(tick - c.releasedTick) * engine::kTickSeconds;
      const Eigen::Vector3d top = c.from + Eigen::Vector3d(0, 0, kReleaseRise);
      const Eigen::Vector3d rest(c.from.x() + kReleaseForward, c.from.y(), kReleaseHeight);
      c.position = age < kReleaseRiseSeconds
                       ? c.from + (top - c.from) * smooth(age / kReleaseRiseSeconds)
                       : top + (rest - top) * smooth((age - kReleaseRiseSeconds) / kReleaseSettleSeconds);
    }
    for (const BodyPoint& p : body)
      if ((p.position - c.position).norm() <= c.radius + p.radius) {
        c.collected = true;
        (c.gift ? gifts_ : coins_) += 1;
        score_ += c.gift ? rules_.giftValue : rules_.coinValue;
        log(tick, CourseEventKind::Collected,
            std::string(c.gift ? "gift" : "coin") + " collected (score " + std::to_string(score_) + ")");
        break;
      }
  }

  // ghosts chase the pelvis in the side plane (x, z)
  ghostDistance_ = -1;
  const Eigen::Vector2d target(pelvis.x(), pelvis.z());
  for (Ghost& g : ghosts_) {
    if (g.gone) continue;
    if (!g.awake && pelvis.x() >= g.def.appearX) {
      g.awake = true;
      const Eigen::Vector2d start(pelvis.x() - g.def.behind, g.def.height);
      if (g.body < 0)
        g.body = plane.addKinematicCircle(start, g.def.radius, -1);
      else
        plane.setPosition(g.body, start);
      log(tick, CourseEventKind::GhostAppears,
          "a ghost appears " + std::to_string(g.def.behind).substr(0, 4) + " m behind");
    }
    if (g.park) {  // asleep again after a respawn: still, and out of the way of the autopilot's ray casts
      g.park = false;
      plane.setVelocity(g.body, Eigen::Vector2d::Zero());
      plane.setPosition(g.body, {-1000.0, g.def.height});
    }
    if (!g.awake) continue;
    if (pelvis.x() >= g.def.vanishX) {
      g.gone = true;
      plane.setVelocity(g.body, Eigen::Vector2d::Zero());
      log(tick, CourseEventKind::GhostGivesUp, "the ghost gives up");
      continue;
    }
    const Eigen::Vector2d at = plane.position(g.body);
    const Eigen::Vector2d gap = target - at;
    const double edge = gap.norm() - g.def.radius;
    ghostDistance_ = ghostDistance_ < 0 ? edge : std::min(ghostDistance_, edge);
    if (edge <= g.def.catchDistance) {
      finish(tick, Outcome::Lost, "caught by the ghost");
      return;
    }
    g.speed = std::min(g.def.maxSpeed, g.speed + g.def.acceleration * engine::kTickSeconds);
    plane.setVelocity(g.body, gap.normalized() * g.speed);
  }

  // the goal: a ball's centre inside it
  for (const Ball& b : balls_) {
    const Eigen::Vector3d p = physics.ballState(b.id).position;
    for (const levels::GoalDef& g : goals_)
      if (((p - g.centre).cwiseAbs() - 0.5 * g.size).maxCoeff() <= 0) {
        const int left = timeLimit_ > 0 ? int(std::floor(timeLimit_ - t)) : 0;
        score_ += rules_.winBonus + std::max(0, left);
        finish(tick, Outcome::Won, "the ball is in the goal");
        return;
      }
  }
  if (timeLimit_ > 0 && t >= timeLimit_) finish(tick, Outcome::Lost, "time is up");
}

bool Course::onFall(int64_t tick) {
  if (outcome_ != Outcome::Playing) return false;
  ++falls_;
  if (!rules_.present) {  // a map without rules (the garden): the fall is counted, nothing puts the robot back
    log(tick, CourseEventKind::Fell, "fell");
    return false;
  }
  if (rules_.falls == levels::FallRule::Lose) {
    finish(tick, Outcome::Lost, "fell");
    return false;
  }
  score_ -= rules_.fallPenalty;
  // a respawn loop: the falls back to this checkpoint, the oldest dropped once kRespawnLoopFalls are kept
  fallsHere_.push_back(tick);
  if (int(fallsHere_.size()) > kRespawnLoopFalls) fallsHere_.erase(fallsHere_.begin());
  if (int(fallsHere_.size()) == kRespawnLoopFalls &&
      double(tick - fallsHere_.front()) * engine::kTickSeconds <= kRespawnLoopSeconds) {
    char what[160];
    std::snprintf(what, sizeof what, "fell %d times within %.1f s back to x = %.2f, -%d: a respawn loop",
                  kRespawnLoopFalls, double(tick - fallsHere_.front()) * engine::kTickSeconds, checkpointX_,
                  rules_.fallPenalty);
    log(tick, CourseEventKind::RespawnLoop, what);
    char reason[120];
    std::snprintf(reason, sizeof reason, "a respawn loop (%d falls within %.0f s back to the checkpoint at x = %.2f)",
                  kRespawnLoopFalls, kRespawnLoopSeconds, checkpointX_);
    finish(tick, Outcome::Lost, reason);
    return false;
  }
  log(tick, CourseEventKind::Fell,
      "fell: back to x = " + std::to_string(checkpointX_).substr(0, 5) + ", -" + std::to_string(rules_.fallPenalty));
  // a ghost that woke beyond the checkpoint goes back to sleep: it wakes again (behind, at its first speed) when the
  // robot passes its appear_x again (before, a respawn at the start put the robot under the chasing ghost)
  for (Ghost& g : ghosts_)
    if (g.awake && !g.gone && g.def.appearX >= checkpointX_) {
      g.awake = false, g.park = true;
      g.speed = g.def.speed;
    }
  return true;
}

void Course::draw(const engine::PhysicsWorld& physics, const engine::PlaneWorld& plane,
                  engine::SceneSnapshot* out) const {
  auto sphere = [&](const Eigen::Vector3d& p, double r, uint32_t rgba) {
    engine::DrawShape d;
    d.kind = engine::ShapeKind::Sphere;
    d.position = p;
    d.radius = r;
    d.rgba = rgba;
    out->shapes.push_back(d);
  };
  auto box = [&](const Eigen::Vector3d& c, const Eigen::Vector3d& size, uint32_t rgba) {
    engine::DrawShape d;
    d.kind = engine::ShapeKind::Box;
    d.position = c;
    d.halfExtents = 0.5 * size;
    d.rgba = rgba;
    out->shapes.push_back(d);
  };
  for (const Collectable& c : items_)
    if (!c.collected) sphere(c.position, c.radius, c.gift ? kGiftColour : kCoinColour);
  for (const Box& b : boxes_) box(b.def.centre, b.def.size, b.used ? kUsedBoxColour : kBoxColour);
  for (const Ghost& g : ghosts_)
    if (g.awake && !g.gone) {
      const Eigen::Vector2d p = plane.position(g.body);
      sphere(Eigen::Vector3d(p.x(), 0.0, p.y()), g.def.radius, kGhostColour);
    }
  for (const Ball& b : balls_) sphere(physics.ballState(b.id).position, b.radius, kBallColour);
  for (const levels::GoalDef& g : goals_) box(g.centre, g.size, kGoalColour);
}

void Course::hash(const engine::PhysicsWorld&, const engine::PlaneWorld& plane, engine::Hasher* h) const {
  h->value(score_);
  h->value(coins_);
  h->value(gifts_);
  h->value(falls_);
  h->value(int(outcome_));
  h->value(checkpointX_);
  for (const Collectable& c : items_) h->value(c.collected);
  for (const Box& b : boxes_) h->value(b.used);
  for (const Ghost& g : ghosts_) {
    h->value(g.awake);
    h->value(g.gone);
    h->value(g.speed);
    if (g.awake) {
      const Eigen::Vector2d p = plane.position(g.body);
      h->value(p.x());
      h->value(p.y());
    }
  }
}

}  // namespace game
