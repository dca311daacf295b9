// session.cpp — builds a level's worlds and entities and runs the per-tick system pipeline.
#include "game/session.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/core/hash.h"
#include "engine/loop/clock.h"
#include "game/components.h"

namespace game {
namespace {

constexpr uint32_t kRobotColour = 0xe06a1aff;  // orange, so tests can find the robot in a frame
constexpr double kInitialJitter = 0.01;        // +- rad on every joint, from the seed

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
    else if (level.plane == levels::Plane2d::Top)
      plane_.addStaticRect({b.centre.x(), b.centre.y()}, {0.5 * b.size.x(), 0.5 * b.size.y()}, b.yaw, int(i));
  }

  // the robot at the spawn point, joints jittered around the default pose by the seed
  robot_ = std::make_unique<robot::Robot>(model, physics_, level.spawn.x(), level.spawn.y(), level.spawnYaw);
  registry_.add(registry_.create(), RobotTag{kRobotColour});
  robot_->teleport(physics_, robot_->linkPose(physics_, -1), jitteredStandingPose());
  sensors_ = robot_->sense(physics_);
  if (level.isGame()) course_ = std::make_unique<Course>(level, physics_, plane_);
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
  // skill routes from the root as usual). Until session 9 the fallen skill went on: a run started from a standstill
  // at the default pose at 2 m/s and fell again 0.56 s after every respawn on levels/mario.
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.translation() = Eigen::Vector3d(x, 0.0, model_.spawnHeight);
  // the joints jittered as at the start, by the seed's generator going on: a retry is a new attempt at the stage
  // (the same pose every time replayed the same fall forever: levels/mario's autopilot fell 10 times in a row at
  // the tunnel, tick for tick alike), and the run stays a function of the seed and the keys
  robot_->teleport(physics_, base, jitteredStandingPose());
  action_.fill(0.0f);
  phase_ = robot::PhaseClock{};
  sensors_ = robot_->sense(physics_);
  input_.stopMotion();
  telemetry_.respawns.push_back(tick_);
  const SkillRuntime* root = nullptr;
  if (skills_)
    for (const SkillRuntime& s : skills_->skills)
      if (s.def.parent.empty()) root = &s;
  if (active_ && root && active_ != root) {
    switchTo(root);
    telemetry_.switches.back().tick = tick_ + 1;  // the root's first control step is the next tick's
    telemetry_.switches.back().respawn = true;
  }
  stuckTicks_ = 0;
  drift_ = Eigen::Vector2d::Zero();
  fadingFrom_ = nullptr;  // a fresh start: no prior to fade out
  fadeTicks_ = 0;
  restWaitTicks_ = -1;
  postureWaitTicks_ = 0;
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


namespace {
// the keys' velocity command clamped into a skill's command ranges (and to 0 where a range excludes it): the keys
// ramp within the active skill's ranges (setLimits), and the clamp covers the ramp's way there after a switch
robot::SkillCommand keysWithin(const engine::CommandState& c, const robot::CommandDef& range) {
  robot::SkillCommand command;
  command.vx = std::clamp(c.vx, std::min(range.vx.lo, 0.0), std::max(range.vx.hi, 0.0));
  command.vy = std::clamp(c.vy, std::min(range.vy.lo, 0.0), std::max(range.vy.hi, 0.0));
  command.wz = std::clamp(c.wz, std::min(range.wz.lo, 0.0), std::max(range.wz.hi, 0.0));
  return command;
}
}  // namespace

// the requested skill drives the robot if its model is loaded; otherwise the standing controller does.
// A request for a skill that is not a parent or child of the active one is routed along the tree, one switch
// at a time, each once the robot is upright and the previous hop has run kMinHopTicks; into a still skill or a
// slower one (run -> walk) the active skill first brakes (robot::switchWaits). A switch takes effect
// in the tick it is made: the new network reads the same observation, the filtered action carries over (the
// layouts are shared, so the joint targets do not jump) and the gait phase keeps its fraction of the cycle.
void Session::controlSystem() {
  const int key = input_.state().skillRequest;
  const SkillRuntime* wanted = skills_ && key >= 0 ? skills_->byKey(key) : nullptr;
  if (wanted && wanted != active_) {
    const SkillRuntime* next = active_ ? skills_->nextHop(*active_, *wanted) : wanted;
    const bool direct = next == wanted;
    // upright skills switch when the robot is upright; a ground skill (lying down) switches as it lies, but only
    // to another ground skill or to its way up (a stand-up skill): it cannot hand a lying robot to the walk
    const bool ground = active_ && robot::isGroundSkill(active_->def);
    const bool handsOver = !active_ || !next || robot::mayHandOver(active_->def, next->def);
    // (and a stand-up hands over to the walk once the robot stands: robot::postureAllowsSwitch)
    // a hop's time: after a routed hop, and from the standing controller into a skill that starts from the default
    // pose (the jump, the kick): the jump asked for at the spawn's first tick fell at its second landing in 20 of 20
    // seeds on levels/flat, asked for 0.5 s in, in 2 of 20 (7 s of jumping)
    const bool hopWait = !direct || (!active_ && robot::startsFromDefaultPose(next->def));
    bool ready = handsOver && (ground || sensors_.tilt < kSwitchMaxTilt) && (!hopWait || tick_ - activeSince_ >= kMinHopTicks) &&
                 (!active_ || !next || robot::postureAllowsSwitch(active_->def, next->def, sensors_, postureWaitTicks_)) &&
                 (!active_ || robot::cycleAllowsSwitch(active_->def, wanted->def, phase_, drift_.norm(), postureWaitTicks_));
    const bool inPhase = !active_ || !next || robot::phaseAllowsSwitch(active_->def, next->def, phase_);
    // a skill that starts from the default pose (the jump, the kick) waits for a squat or a lift to come back first
    if (next && active_ && robot::startsFromDefaultPose(next->def) && input_.state().amplitude > 0) {
      input_.lowerAmplitude();
      ready = false;
    }
    // into a still skill from rest, into a slower one at its top speed: the active skill brakes first
    if (next && ready && active_ && robot::switchWaits(active_->def, next->def)) {
      // the keys' command as the active skill gets it: right after a routed hop (run -> walk -> prone, W held) the
      // keys still give the run's speed
      const robot::SkillCommand keysCommand = keysWithin(input_.state(), active_->def.commands);
      if (restWaitTicks_ < 0) {  // start braking from the command the keys give now
        restWaitTicks_ = 0;
        brake_ = keysCommand;
      }
      // on the way to a still skill (run -> walk -> prone) every hop brakes toward rest, not only the last: the
      // walk taking over a run at its top speed and braking at once fell in 3 of 4 seeds with W held
      const robot::SkillCommand wantedCommand = robot::isStillSkill(wanted->def) ? robot::SkillCommand{} : keysCommand;
      brakeTarget_ = robot::switchBrakeTarget(active_->def, next->def, wantedCommand);
      ready = robot::readyForSwitch(active_->def, next->def, brakeTarget_, brake_, sensors_, drift_.norm()) ||
              restWaitTicks_ >= robot::maxSwitchWaitTicks(next->def);
    }
    if (next && ready && inPhase) {  // (a skill that brakes first reaches its phase window within a cycle)
      switchTo(next);
      restWaitTicks_ = -1;
      postureWaitTicks_ = 0;
    } else {
      ++postureWaitTicks_;
    }
  } else {
    restWaitTicks_ = -1;  // the request went away (or was reached)
    postureWaitTicks_ = 0;
  }
  if (!active_) {
    robot_->setCommand(robot::Robot::standingCommand(model_));
    return;
  }
  telemetry_.skillsUsed.insert(active_->def.name);
  const engine::CommandState& c = input_.state();
  robot::SkillCommand command = keysWithin(c, active_->def.commands);
  command.amplitude = c.amplitude;
  holdHeading(&command);
  if (restWaitTicks_ >= 0) {  // a switch waits for rest or a slower speed: brake instead of following the keys
    const engine::CommandLimits& keys = input_.limits();
    const robot::SkillCommand& to = brakeTarget_;
    engine::rampVelocityCommand(to.vx, to.vy, to.wz, keys.vRate, keys.wzRate, &brake_.vx, &brake_.vy, &brake_.wz);
    command.vx = brake_.vx, command.vy = brake_.vy, command.wz = brake_.wz;
    ++restWaitTicks_;
  }
  if (active_->def.ball.enabled && course_ && course_->firstBall() >= 0) {
    // a ball skill sees the level's ball where training showed it its own (aux slots, heading frame)
    robot::ballIntoCommand(sensors_, physics_.ballState(course_->firstBall()).position, &command);
  }
  if (active_->def.commands.lineCommand) robot::lineIntoCommand(sensors_, skillLineStart_, skillLineAlong_, &command);
  if (active_->def.commands.stepCommand) robot::stepIntoCommand(sensors_, physics_, active_->def.commands.stepLookBack, &command);
  double s, co;
  robot::phaseSignal(phase_.tp, active_->def.prior.halfPeriodTicks, &s, &co);
  robot::Observation o;
  robot::buildObservation(sensors_, model_, action_, command, s, co, &o);
  observation_ = Eigen::Map<const Eigen::VectorXf>(o.data(), robot::kObservationSize);
  active_->policy(observation_, &policyOutput_);
  robot::filterAction(active_->def, policyOutput_.data(), &action_);
  // a request out of jumps in a row for a still skill waits in the cycle's closing stand rather than jump again
  const bool waitsForStill = wanted && wanted != active_ && robot::isStillSkill(wanted->def);
  if (!robot::holdsClosingStand(active_->def, phase_, waitsForStill)) phase_.advance(active_->def.prior, command);
  robot::PdCommand pd;
  robot::skillPdCommand(model_, active_->def, action_, phase_, command, &pd);
  if (fadingFrom_ && fadeTicks_ > 0) {
    // the old prior's share fades linearly: target += w (old prior - new prior), with the policy's part unchanged
    fadePhase_.advance(fadingFrom_->def.prior, command);
    robot::fadePrior(model_, fadingFrom_->def, fadePhase_, active_->def, phase_, command,
                     double(fadeTicks_) / kSwitchFadeTicks, &pd);
    --fadeTicks_;
  }
  robot_->setCommand(pd);
}

// W / S (or the sideways keys) with no turn key: an upright skill that can turn keeps to the line the robot was on
// when it started moving (or the turn keys were released), facing the way it faced then, as a player would steer
// against a drift. The heading asked for leans back toward the line by atan(line_hold * offset) (the skill's
// [commands] line_hold; 0: the heading alone), and the turn rate
// asked for is kHeadingGain times the heading error, at most kHeadingMaxRate (and within the skill's wz range).
void Session::holdHeading(robot::SkillCommand* command) {
  const robot::CommandDef& range = active_->def.commands;
  const bool moving = command->vx != 0.0 || command->vy != 0.0;
  if (robot::isGroundSkill(active_->def)) {  // the upright hold below is not theirs
    headingRef_ = sensors_.yaw;
    lineStart_ = sensors_.basePosition.head<2>();
    steerToLine(moving, command);
    return;
  }
  const bool canTurn = range.wz.hi > 0.0 && range.wz.lo < 0.0;
  const Eigen::Vector2d p = sensors_.basePosition.head<2>();
  if (!moving || !canTurn || command->wz != 0.0 || restWaitTicks_ >= 0) {
    headingRef_ = sensors_.yaw;
    lineStart_ = p;
    return;
  }
  const Eigen::Vector2d along(std::cos(headingRef_), std::sin(headingRef_));
  const Eigen::Vector2d d = p - lineStart_;
  const double offset = along.x() * d.y() - along.y() * d.x();  // left of the line > 0
  const double wanted = headingRef_ - std::atan(range.lineHold * offset);
  const double error = std::remainder(wanted - sensors_.yaw, 2.0 * M_PI);
  const double limit = headingHoldLimit(range);
  command->wz = std::clamp(kHeadingGain * error, -limit, limit);
}

// A ground skill that trained steered back toward the line it began on ([training] line_steer: the crawl) is steered
// so in play while it moves with no turn key, by the same law as its training and its card. A turn key takes over;
// once it is released the line starts again where the robot is, the way it faces then.
void Session::steerToLine(bool moving, robot::SkillCommand* command) {
  const robot::SkillDef& def = active_->def;
  if (def.lineSteer <= 0.0) return;
  if (command->wz != 0.0) {
    restartSkillLine();
    return;
  }
  if (!moving || restWaitTicks_ >= 0) return;
  robot::SkillCommand line;
  robot::lineIntoCommand(sensors_, skillLineStart_, skillLineAlong_, &line);
  command->wz = robot::steerTowardLine(def.commands, def.lineSteer, line, &lineSteerError_);
}

void Session::restartSkillLine() {
  skillLineStart_ = sensors_.basePosition.head<2>();
  skillLineAlong_ = robot::groundHeading(sensors_);
  lineSteerError_ = 0.0;
}

void Session::switchTo(const SkillRuntime* next) {
  telemetry_.switches.push_back({tick_, active_ ? active_->def.name : "stand", next->def.name});
  if (active_) {
    fadePhase_ = phase_;  // the old prior goes on under its own clock while it fades out
    robot::carryPhase(active_->def.prior, next->def.prior, &phase_);  // same fraction of the gait cycle
  } else {
    action_.fill(0.0f);
    phase_ = robot::PhaseClock{};
  }
  fadingFrom_ = active_;
  fadeTicks_ = active_ ? kSwitchFadeTicks : 0;
  active_ = next;
  activeSince_ = tick_;
  // the new skill keeps the heading held so far, on a line through where it starts (the walk taking the stairs'
  // robot 0.66 m off the stairs' line turned 1.6 rad back toward it and fell; taking the heading of the moment
  // instead, the run took over the walk's lean back to its line, 0.19 rad, and ran into levels/mario's wall)
  lineStart_ = sensors_.basePosition.head<2>();
  restartSkillLine();  // a line-keeping skill (the crawl) keeps to the one it begins on, as it trained
  // the keys drive the new skill's command ranges (W to its top speed, and so on)
  const robot::CommandDef& r = next->def.commands;
  engine::CommandLimits limits = input_.limits();
  limits.vxForward = std::max(r.vx.hi, 0.0);
  limits.vxBackward = std::min(r.vx.lo, 0.0);
  limits.vyMax = std::max(std::abs(r.vy.lo), std::abs(r.vy.hi));
  limits.wzMax = std::max(std::abs(r.wz.lo), std::abs(r.wz.hi));
  input_.setLimits(limits);
}

std::string Session::activeSkillName() const { return active_ ? active_->def.name : "stand"; }

// PD torques are recomputed every 0.002 s substep inside the 0.01 s tick
void Session::physicsSystem() {
  for (int k = 0; k < kSubsteps; ++k) {
    robot_->applyPd(physics_);
    physics_.step(kSubstepSeconds);
  }
  plane_.step(engine::kTickSeconds);
}

// falls (a game level may respawn the robot), then the game's rules
void Session::rulesSystem() {
  const robot::Sensors previous = sensors_;
  sensors_ = robot_->sense(physics_);
  telemetry_.distance += (sensors_.basePosition - previous.basePosition).head<2>().norm();
  // a ground skill (prone, crawl: lying is its job) falls by its own termination: onto a side or the back
  const bool ground = active_ && robot::isGroundSkill(active_->def);
  // an upright skill stuck leaning or slumped (against a wall, on a knee: it cannot switch, kSwitchMaxTilt) for
  // kStuckTicks counts as down too (levels/mario's autopilot once leaned on the wall in the one-leg stand for 215 s)
  const bool slumped = active_ && !ground && (sensors_.tilt > kSwitchMaxTilt || sensors_.basePosition.z() < kStuckPelvisHeight);
  stuckTicks_ = slumped ? stuckTicks_ + 1 : 0;
  robot::updateDrift(sensors_, &drift_);
  const SkillRuntime* way = ground && skills_ && !active_->def.up.empty() ? skills_->byName(active_->def.up) : nullptr;
  const bool risingTooLong = way && !robot::isGroundSkill(way->def) && tick_ - activeSince_ >= kStandUpTicks &&
                             sensors_.basePosition.z() < kStuckPelvisHeight;
  const bool down = ground ? robot::hasFallen(active_->def.termination, sensors_) || risingTooLong
                           : sensors_.basePosition.z() < kFallPelvisHeight || sensors_.tilt > kFallTilt ||
                                 stuckTicks_ >= kStuckTicks;
  if (down && !down_) {
    ++telemetry_.falls;
    ++telemetry_.fallsBySkill[active_ ? active_->def.name : std::string()];
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
  h.bytes(action_.data(), sizeof(float) * action_.size());
  h.value(phase_.tp);
  if (course_) course_->hash(physics_, plane_, &h);
  return h.value();
}

std::string Session::hudLine() const {
  const engine::CommandState& c = input_.state();
  char buf[160];
  const std::string keys = engine::keysHeldString(c);
  // a request without a loaded skill model shows as "stand<3"
  std::string skill = activeSkillName();
  if (!active_ && c.skillRequest >= 0) skill += "<" + std::to_string(c.skillRequest);
  std::snprintf(buf, sizeof buf, "T %.2f  %s  keys %s  v %+.1f %+.1f w %+.1f%s", seconds(), skill.c_str(),
                keys.empty() ? "-" : keys.c_str(), c.vx, c.vy, c.wz, fallen_ && !course_ ? "  FALLEN" : "");
  std::string hud = buf;
  if (course_) {  // the game's figures on a second line (on one, a 640 px frame cut them off)
    char game[160];
    const double ghost = course_->ghostDistance();
    std::snprintf(game, sizeof game, "\nscore %d  coins %d  ghost %s%s", course_->score(), course_->coins() + course_->gifts(),
                  ghost < 0 ? "-" : (std::to_string(ghost).substr(0, 4) + " m").c_str(),
                  course_->outcome() == Outcome::Won ? "  WON" : course_->outcome() == Outcome::Lost ? "  LOST" : "");
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
