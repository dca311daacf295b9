// session.cpp — builds a level's worlds and entities and runs the per-tick system pipeline.
#include "game/session.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/loop/clock.h"
#include "engine/plane/plane_tags.h"
#include "game/components.h"

namespace game {
namespace {

constexpr uint32_t kRobotColour = 0xe06a1aff;  // orange, so tests can find the robot in a frame
constexpr double kInitialJitter = 0.01;        // +- rad on every joint, from the seed
const robot::SkillSet kNoSkills;               // a session without learned skills: the standing controller

// a double in [0, 1) from 53 random bits (portable, unlike std::uniform_real_distribution)
double unit(std::mt19937_64& rng) { return double(rng() >> 11) * (1.0 / 9007199254740992.0); }

}  // namespace

Session::Session(const levels::Level& level, const robot::RobotModel& model, const SessionOptions& options)
    : level_(level), model_(model), rng_(options.seed), skills_(options.skills) {
  // ground and static boxes: one entity each, mirrored into the 3D world and the 2D layer
  const engine::Entity ground = registry_.create();
  registry_.add(ground, Ground{level.groundFriction});
  physics_.addGround(level.groundFriction);
  for (size_t i = 0; i < level.boxes.size(); ++i) {
    const levels::BoxDef& b = level.boxes[i];
    StaticBox box;
    box.centre = b.centre;
    box.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(b.yaw, Eigen::Vector3d::UnitZ()));
    box.halfExtents = 0.5 * b.size;
    box.rgba = b.seeThrough ? (b.rgba & 0xffffff00u) | 0x40u : b.rgba;
    registry_.add(registry_.create(), box);
    physics_.addStaticBox(box.centre, box.rotation, box.halfExtents, b.friction);
    // a see-through wall runs along the course beside it: in the side plane it would cover everything
    if (level.plane == levels::Plane2d::Side && !b.seeThrough)
      plane_.addStaticRect({b.centre.x(), b.centre.z()}, {0.5 * b.size.x(), 0.5 * b.size.z()}, 0.0, int(i));
    // in a map (the top plane) a staircase's steps carry the stairs tag (a flight along +X: engine/plane/plane_tags.h),
    // so that the navigation crosses them only along their axis; the side plane keeps the box index (the course's
    // autopilot sees steps by their shape)
    else if (level.plane == levels::Plane2d::Top)
      plane_.addStaticRect({b.centre.x(), b.centre.y()}, {0.5 * b.size.x(), 0.5 * b.size.y()}, b.yaw,
                           b.stairs ? engine::stairTag(b.yaw) : int(i));
  }

  // the robot at the spawn point, joints jittered around the default pose by the seed
  robot_ = std::make_unique<robot::Robot>(model, physics_, level.spawn.x(), level.spawn.y(), level.spawnYaw);
  registry_.add(registry_.create(), RobotTag{kRobotColour});
  robot_->teleport(physics_, robot_->linkPose(physics_, -1), jitteredStandingPose());
  sensors_ = robot_->sense(physics_);
  if (level.isGame() || !level.coins.empty() || !level.balls.empty())
    course_ = std::make_unique<Course>(level, physics_, plane_);
}

std::vector<BodyPoint> Session::bodyPoints() const {
  std::vector<BodyPoint> points;
  const engine::ArticulationDef& def = model_.articulation;
  for (int link = -1; link < int(def.links.size()); ++link) {
    const engine::LinkDef& l = link < 0 ? def.base : def.links[size_t(link)];
    const bool head = l.name == "torso_link";
    const bool hand = l.name.find("hand") != std::string::npos || l.name.find("elbow") != std::string::npos;
    const Eigen::Isometry3d pose = robot_->linkPose(physics_, link);
    for (const engine::ColliderDef& c : l.colliders) {
      const Eigen::Isometry3d w = pose * c.pose;
      if (c.kind == engine::ShapeKind::Capsule) {
        const Eigen::Vector3d axis = w.rotation().col(2) * c.halfLength;
        points.push_back({w.translation() + axis, c.radius, head, hand});
        points.push_back({w.translation() - axis, c.radius, head, hand});
      } else {
        const double r = c.kind == engine::ShapeKind::Sphere ? c.radius : c.halfExtents.minCoeff();
        points.push_back({w.translation(), r, head, hand});
      }
    }
  }
  return points;
}

robot::JointArray Session::jitteredStandingPose() {
  robot::JointArray q = robot::Robot::standingCommand(model_).target;
  for (double& v : q) v += kInitialJitter * (2.0 * unit(rng_) - 1.0);
  return q;
}

void Session::respawn(double x) {
  // upright, facing +X, feet on the ground in the default pose, at rest: the root skill (walk) takes the robot as
  // at a level's start and the velocity commands start from 0 (held keys ramp them up again; a request for another
  // skill routes from the root as usual). Were the fallen skill to go on, a run would start from a standstill at
  // the default pose at 2 m/s and fall again 0.56 s after every respawn on levels/mario.
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.translation() = Eigen::Vector3d(x, 0.0, model_.spawnHeight);
  // the joints jittered as at the start, by the seed's generator going on: a retry is a new attempt at the stage
  // (the same pose every time replayed the same fall forever: levels/mario's autopilot fell 10 times in a row at
  // the tunnel, tick for tick alike), and the run stays a function of the seed and the keys
  robot_->teleport(physics_, base, jitteredStandingPose());
  sensors_ = robot_->sense(physics_);
  input_.stopMotion();
  telemetry_.respawns.push_back(tick_);
  const robot::Skill* from = runtime_.active;
  const robot::Skill* root = skills_ ? skills_->root() : nullptr;
  // a fresh start: the action and clock from zero, no prior to fade out, no switch waiting
  runtime_.action.fill(0.0f);
  runtime_.phase = robot::PhaseClock{};
  if (from && root && from != root) {
    robot::enterSkill(&runtime_, *root, sensors_, tick_);
    onSwitch(from, *root);
    telemetry_.switches.back().tick = tick_ + 1;  // the root's first control step is the next tick's
    telemetry_.switches.back().respawn = true;
  }
  stuckTicks_ = 0;
  runtime_.drift = Eigen::Vector2d::Zero();
  runtime_.fadingFrom = nullptr;
  runtime_.fadeTicks = 0;
  runtime_.restWaitTicks = -1;
  runtime_.postureWaitTicks = 0;
}

robot::EntryState Session::captureEntry() const {
  if (!runtime_.active)
    throw engine::Error("captureEntry: no skill is active (the standing controller holds the robot)");
  robot::EntryState e;
  e.skill = runtime_.active->def.name;
  e.tick = tick_ - 1;  // the tick just stepped
  physics_.readState(robot_->id(), &e.body);
  if (course_)
    for (const engine::BallId id : course_->ballIds()) e.balls.push_back(physics_.ballState(id));
  e.runtime = runtime_;
  e.runtime.active = nullptr, e.runtime.fadingFrom = nullptr;
  e.fadingFrom = runtime_.fadingFrom ? runtime_.fadingFrom->def.name : std::string();
  e.keys = input_.state();
  e.limits = input_.limits();
  return e;
}

void Session::restoreEntry(const robot::EntryState& entry) {
  if (!skills_) throw engine::Error("a play-entry state needs the skills loaded");
  const std::vector<engine::BallId> balls = course_ ? course_->ballIds() : std::vector<engine::BallId>{};
  if (entry.balls.size() != balls.size())
    throw engine::Error("an entry of " + entry.level + " (seed " + std::to_string(entry.seed) + ", tick " +
                        std::to_string(entry.tick) + ") holds " + std::to_string(entry.balls.size()) +
                        " balls, the level " + std::to_string(balls.size()));
  runtime_ = robot::entryRuntime(entry, *skills_);
  physics_.setState(robot_->id(), entry.body);
  for (size_t i = 0; i < balls.size(); ++i) physics_.setBallState(balls[i], entry.balls[i]);
  input_.restore(entry.keys);
  engine::CommandLimits limits = entry.limits;  // an entry holds the keys' targets and rates; steering is the skill's
  limits.steerVx = runtime_.active->def.commands.steerVx, limits.steerWz = runtime_.active->def.commands.steerWz;
  input_.setLimits(limits);
  sensors_ = robot_->sense(physics_);
  tick_ = entry.tick + 1;
  fallen_ = down_ = false, fallTick_ = -1, stuckTicks_ = 0;
}

double Session::seconds() const { return double(tick_) * engine::kTickSeconds; }

void Session::step(const std::vector<engine::KeyEvent>& events) {
  inputSystem(events);
  controlSystem();
  physicsSystem();
  rulesSystem();
  telemetrySystem();
  ++tick_;
}

// keys -> command state (skill request, ramped vx / vy / wz with the interlock)
void Session::inputSystem(const std::vector<engine::KeyEvent>& events) {
  for (const engine::KeyEvent& e : events) input_.apply(e);
  input_.tick();
  if (input_.state().skillRequest >= 0) telemetry_.skillsRequested.insert(input_.state().skillRequest);
}

// the skill runtime: the request routed along the tree (robot::route), the keys' command shaped for the active skill
// (robot::shapeCommand), the control step (robot::controlStep); without a skill the standing controller holds the pose
void Session::controlSystem() {
  const engine::CommandState& c = input_.state();
  const engine::CommandLimits& keys = input_.limits();
  robot::SwitchRequest request;
  request.wanted = skills_ && c.skillRequest >= 0 ? skills_->byKey(c.skillRequest) : nullptr;
  request.vx = c.vx, request.vy = c.vy, request.wz = c.wz, request.amplitude = c.amplitude;
  request.vRate = keys.vRate, request.wzRate = keys.wzRate;
  const robot::Skill* from = runtime_.active;
  const robot::RouteResult routed = robot::route(skills_ ? *skills_ : kNoSkills, &runtime_, sensors_, request, tick_);
  if (routed.lowerAmplitude) input_.lowerAmplitude();
  if (routed.switchedTo) onSwitch(from, *routed.switchedTo);
  if (!runtime_.active) {
    robot_->setCommand(robot::Robot::standingCommand(model_));
    return;
  }
  telemetry_.skillsUsed.insert(runtime_.active->def.name);
  robot::SkillCommand command = robot::shapeCommand(&runtime_, sensors_, request);
  if (runtime_.active->def.commands.ballCommand && course_ && course_->firstBall() >= 0) {
    // a ball skill sees the level's ball where training showed it its own (aux slots, heading frame)
    robot::ballIntoCommand(sensors_, physics_.ballState(course_->firstBall()).position, &command);
  }
  robot::PdCommand pd;
  robot::controlStep(model_, model_, &runtime_, sensors_, physics_, command,
                     robot::waitsForStill(runtime_, request.wanted), &pd);
  robot_->setCommand(pd);
}

void Session::onSwitch(const robot::Skill* from, const robot::Skill& next) {
  telemetry_.switches.push_back({tick_, from ? from->def.name : "stand", next.def.name});
  if (next.def.commands.lineSteer > 0) keepToTunnelAxis();
  // the keys drive the new skill's command ranges (W to its top speed, and so on)
  const robot::CommandDef& r = next.def.commands;
  engine::CommandLimits limits = input_.limits();
  limits.vxForward = std::max(r.vx.hi, 0.0);
  limits.vxBackward = std::min(r.vx.lo, 0.0);
  limits.vyMax = std::max(std::abs(r.vy.lo), std::abs(r.vy.hi));
  limits.wzMax = std::max(std::abs(r.wz.lo), std::abs(r.wz.hi));
  limits.steerVx = r.steerVx, limits.steerWz = r.steerWz;
  input_.setLimits(limits);
}

bool tunnelAxisInSight(const engine::PlaneWorld& plane, const robot::Sensors& sensors, Eigen::Vector2d* along) {
  const double way = robot::groundHeading(sensors).x() >= 0 ? 1.0 : -1.0;
  const Eigen::Vector3d p = sensors.basePosition;
  const double ground = std::min(sensors.footHeight[0], sensors.footHeight[1]);
  const bool roofOver = plane.rayCast({p.x(), ground + 0.3}, {p.x(), ground + 1.0}).hit;
  // ahead: something at 0.7 m with open space under it at 0.3 m (as the autopilot sees a tunnel)
  const engine::RayHit high = plane.rayCast({p.x(), ground + 0.7}, {p.x() + way * kTunnelSight, ground + 0.7});
  const engine::RayHit low = plane.rayCast({p.x(), ground + 0.3}, {p.x() + way * kTunnelSight, ground + 0.3});
  const bool roofAhead =
      high.hit && (!low.hit || std::abs(low.point.x() - p.x()) > std::abs(high.point.x() - p.x()) + 0.3);
  if (!roofOver && !roofAhead) return false;
  *along = Eigen::Vector2d(way, 0.0);
  return true;
}

// A skill that keeps to a line (the crawl) takes the line it starts on from the way the robot lies (robot::enterSkill):
// prone left it up to 20 degrees off levels/mario's tunnel, and steered back to that line the crawl went into the
// tunnel's side wall (18 of 73 falls over autopilot seeds 1-20). With a tunnel in sight, its line runs along the
// tunnel's axis through where the robot is.
void Session::keepToTunnelAxis() {
  Eigen::Vector2d along;
  if (level_.plane != levels::Plane2d::Side || !tunnelAxisInSight(plane_, sensors_, &along)) return;
  runtime_.lineStart = sensors_.basePosition.head<2>();
  runtime_.lineAlong = along;
}

std::string Session::activeSkillName() const { return runtime_.active ? runtime_.active->def.name : "stand"; }

// PD torques are recomputed every 0.002 s substep inside the 0.01 s tick
void Session::physicsSystem() {
  robot::stepPhysicsTick(*robot_, physics_);
  plane_.step(engine::kTickSeconds);
}

// falls (a game level may respawn the robot), then the game's rules
void Session::rulesSystem() {
  const robot::Sensors previous = sensors_;
  sensors_ = robot_->sense(physics_);
  telemetry_.distance += (sensors_.basePosition - previous.basePosition).head<2>().norm();
  // a ground skill (prone, crawl: lying is its job) falls by its own termination: onto a side or the back
  const robot::Skill* active = runtime_.active;
  const bool ground = active && robot::isGroundSkill(active->def);
  // an upright skill stuck leaning or slumped (against a wall, on a knee: it cannot switch, kSwitchMaxTilt) for
  // kStuckTicks counts as down too (levels/mario's autopilot once leaned on the wall in the one-leg stand for 215 s)
  const bool slumped =
      active && !ground && (sensors_.tilt > robot::kSwitchMaxTilt || sensors_.basePosition.z() < kStuckPelvisHeight);
  stuckTicks_ = slumped ? stuckTicks_ + 1 : 0;
  robot::updateDrift(sensors_, &runtime_.drift);
  const robot::Skill* way = ground && skills_ && !active->def.up.empty() ? skills_->byName(active->def.up) : nullptr;
  const bool risingTooLong = way && !robot::isGroundSkill(way->def) && tick_ - runtime_.activeSince >= kStandUpTicks &&
                             sensors_.basePosition.z() < kStuckPelvisHeight;
  const bool down =
      ground ? robot::hasFallen(active->def.termination, sensors_) || risingTooLong
             : sensors_.basePosition.z() < kFallPelvisHeight || sensors_.tilt > kFallTilt || stuckTicks_ >= kStuckTicks;
  if (down && !down_) {
    ++telemetry_.falls;
    ++telemetry_.fallsBySkill[active ? active->def.name : std::string()];
    if (!fallen_) fallen_ = true, fallTick_ = tick_;
    if (course_ && course_->onFall(tick_)) {
      respawn(course_->respawnX());
      return;
    }
  }
  down_ = down;
  if (course_) course_->update(tick_, sensors_, bodyPoints(), physics_, plane_);
}

std::string fallsBySkillText(const std::map<std::string, int>& falls) {
  std::vector<std::pair<std::string, int>> order(falls.begin(), falls.end());
  std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  std::string text;
  for (const auto& [skill, n] : order)
    text += (text.empty() ? "" : ", ") + (skill.empty() ? std::string("no skill") : skill) + " " + std::to_string(n);
  return text;
}

void Session::telemetrySystem() {
  const double z = sensors_.basePosition.z();
  telemetry_.minPelvisHeight = std::min(telemetry_.minPelvisHeight, z);
  telemetry_.maxPelvisHeight = std::max(telemetry_.maxPelvisHeight, z);
  telemetry_.sumPelvisHeight += z;
  telemetry_.maxTilt = std::max(telemetry_.maxTilt, sensors_.tilt);
  ++telemetry_.ticks;
}

uint64_t Session::stateHash() const {
  engine::Hasher h;
  h.value(physics_.stateHash());
  h.value(tick_);
  const engine::CommandState& c = input_.state();
  h.value(c.skillRequest);
  h.value(c.vx);
  h.value(c.vy);
  h.value(c.wz);
  h.value(c.amplitude);
  h.value(c.keysHeld);
  h.bytes(runtime_.action.data(), sizeof(float) * runtime_.action.size());
  h.value(runtime_.phase.tp);
  if (course_) course_->hash(physics_, plane_, &h);
  return h.value();
}

std::string Session::hudLine() const {
  const engine::CommandState& c = input_.state();
  char buf[160];
  const std::string keys = engine::keysHeldString(c);
  // a request without a loaded skill model shows as "stand<3"
  std::string skill = activeSkillName();
  if (!runtime_.active && c.skillRequest >= 0) skill += "<" + std::to_string(c.skillRequest);
  std::snprintf(buf, sizeof buf, "T %.2f  %s  keys %s  v %+.1f %+.1f w %+.1f%s", seconds(), skill.c_str(),
                keys.empty() ? "-" : keys.c_str(), c.vx, c.vy, c.wz, fallen_ && !course_ ? "  FALLEN" : "");
  std::string hud = buf;
  if (course_) {  // the game's figures on a second line (on one, a 640 px frame cut them off)
    char game[160];
    const double ghost = course_->ghostDistance();
    std::snprintf(game, sizeof game, "\nscore %d  coins %d  ghost %s%s", course_->score(),
                  course_->coins() + course_->gifts(),
                  ghost < 0 ? "-" : (std::to_string(ghost).substr(0, 4) + " m").c_str(),
                  course_->outcome() == Outcome::Won    ? "  WON"
                  : course_->outcome() == Outcome::Lost ? "  LOST"
                                                        : "");
    hud += game;
  }
  return hud;
}

engine::SceneSnapshot Session::snapshot(engine::CameraMode camera) const {
  engine::SceneSnapshot s;
  s.camera = camera;
  s.follow = sensors_.basePosition;
  s.followYaw = sensors_.yaw;
  engine::DrawShape ground;
  ground.kind = engine::ShapeKind::Plane;
  s.shapes.push_back(ground);

  // level boxes
  registry_.each<StaticBox>([&](engine::Entity, const StaticBox& b) {
    engine::DrawShape d;
    d.kind = engine::ShapeKind::Box;
    d.position = b.centre;
    d.rotation = b.rotation;
    d.halfExtents = b.halfExtents;
    d.rgba = b.rgba;
    s.shapes.push_back(d);
  });

  // robot links as their collision primitives
  registry_.each<RobotTag>([&](engine::Entity, const RobotTag& tag) {
    const engine::ArticulationDef& def = model_.articulation;
    for (int link = -1; link < int(def.links.size()); ++link) {
      const engine::LinkDef& l = link < 0 ? def.base : def.links[size_t(link)];
      const Eigen::Isometry3d pose = robot_->linkPose(physics_, link);
      for (const engine::ColliderDef& c : l.colliders) {
        const Eigen::Isometry3d w = pose * c.pose;
        engine::DrawShape d;
        d.kind = c.kind;
        d.position = w.translation();
        d.rotation = Eigen::Quaterniond(w.rotation());
        d.halfExtents = c.halfExtents;
        d.radius = c.radius;
        d.halfLength = c.halfLength;
        d.rgba = (l.name == "torso_link" || l.name == "pelvis") ? 0x3a3f4aff : tag.rgba;
        s.shapes.push_back(d);
      }
    }
  });
  if (course_) course_->draw(physics_, plane_, &s);
  s.hud = hudLine();
  return s;
}

}  // namespace game
