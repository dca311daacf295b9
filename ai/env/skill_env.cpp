// skill_env.cpp — the training environment of a skill.
#include "ai/env/skill_env.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "ai/env/ball_task.h"
#include "ai/env/terrain.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/input/command.h"
#include "engine/input/input_timeline.h"
#include "engine/loop/clock.h"

namespace ai {
namespace {

// a double in [0, 1) from 53 random bits (portable across standard libraries)
double unit(std::mt19937_64& rng) { return double(rng() >> 11) * (1.0 / 9007199254740992.0); }
double uniform(std::mt19937_64& rng, const robot::Range& r) { return r.lo + (r.hi - r.lo) * unit(rng); }

// one velocity draw with the keyboard's interlock: one of vx, vy, wz non-zero, or all zero. Forward gets half of
// the non-zero commands, sideways and turning a quarter each; a kind whose range is [0, 0] (not used by the
// skill) gives its share to the others
void drawVelocity(std::mt19937_64& rng, const robot::CommandDef& c, const CommandDraws& d, robot::SkillCommand* out) {
  const double pick = unit(rng);
  if (pick < d.zeroProbability) return;
  auto used = [](const robot::Range& r) { return r.lo != 0.0 || r.hi != 0.0; };
  const double wx = used(c.vx) ? 0.5 : 0.0, wy = used(c.vy) ? 0.25 : 0.0, ww = used(c.wz) && d.turnInPlace ? 0.25 : 0.0;
  const double which = (pick - d.zeroProbability) / (1.0 - d.zeroProbability) * (wx + wy + ww);
  if (which < wx)
    out->vx = uniform(rng, c.vx);
  else if (which < wx + wy)
    out->vy = uniform(rng, c.vy);
  else if (ww > 0)
    out->wz = uniform(rng, c.wz);
}

}  // namespace

struct SkillEnv::Env {
  robot::RobotModel model;  // a copy: the base mass is randomised per episode
  std::unique_ptr<engine::PhysicsWorld> world;
  std::unique_ptr<robot::Robot> robot;
  std::mt19937_64 rng;
  robot::Sensors sensors;
  robot::SkillCommand command;
  robot::SkillState state;  // the runtime: the trainee's clock, filtered action, a handover's prior fading out, line
  std::array<float, robot::kActionSize> previousAction{};
  int tick = 0, nextCommandTick = 0, nextPushTick = 0;
  int liftAskedTicks = 0;  // consecutive ticks a lift of >= kFootLiftHeight / 2 has been asked (lifted_foot_touch_s)
  double episodeReturn = 0;
  std::vector<double> termSums;
  double physicsSeconds = 0;
  // per-step outputs
  float reward = 0;
  uint8_t terminated = 0, truncated = 0;
  double finishedReturn = 0;  // the finished episode's return (reported as float; the curriculum's in full)
  int finishedLength = 0;
  double amplitudeTarget = 0;   // where a ramped amplitude command is heading
  robot::SkillCommand target;   // the latest draw, which a ramped velocity command is heading for
  bool headingSteered = false;  // [training] heading_steer steers this episode (heading_steer_share)
  double steer = 0;             // [draws] steer: the draw's turn while moving, on top of the interlocked command
  double keysWz = 0;            // the interlocked (keys') yaw rate, without the steer
  int startStep = 0;            // rollout step the episode began at (curriculum)
  engine::BallId ball = -1;     // the kick's ball (-1: none)
  engine::BallState ballState;
  Eigen::Vector2d kickDirection = Eigen::Vector2d::UnitX();
  std::array<float, robot::kObservationSize> finalObservation{};
  Eigen::Vector2d anchor = Eigen::Vector2d::Zero();  // hold_position: where a zero command (or a push) began
  const robot::EntryState* entry = nullptr;          // a play episode: the handover state it started from
  engine::CommandInput keys;                         // ... its keys ...
  engine::InputTimeline events{{}};                  // ... replayed from the entry's segment
  int playTicks = 0;                                 // ... its length [ticks]
  bool waitsForStill = false;  // ... and whether its keys ask for a still skill (a jump then holds its closing stand)
  double yawRateSmoothed = 0;  // line_turn: the world yaw rate, low-passed over kLineTurnSeconds
};

SkillEnv::SkillEnv(const robot::RobotModel& model, const SkillSpec& skill, const std::string& treePath,
                   const SkillEnvOptions& options)
    : model_(model),
      skill_(skill),
      treeSkill_(skill),
      terms_(resolveRewardTerms(skill, treePath)),
      options_(options),
      pool_(options.threads) {
  if (skill_.handover > 0) {
    if (!options_.parent || !options_.parentPolicy)
      throw engine::Error("skill '" + skill_.name +
                          "' trains handover episodes: the environment needs its parent's policy");
    parent_ = *options_.parent;
    for (const HandoverStage& v : options_.via) via_.push_back(*v.skill);
  }
  if (skill_.handoverBack > 0) {
    if (!options_.back.skill || !options_.back.policy)
      throw engine::Error("skill '" + skill_.name + "' trains handover episodes from '" + skill_.handoverBackFrom +
                          "': the environment needs that skill's policy");
    backChild_ = *options_.back.skill;
  }
  if (skill_.playShare > 0) {
    const std::string dir = std::filesystem::path(treePath).parent_path().string();
    const std::string path = (dir.empty() ? std::string() : dir + "/") + skill_.playEntries;
    for (robot::EntryState& e : robot::loadEntries(path))
      if (e.skill == skill_.name) playEntries_.push_back(std::move(e));
    if (playEntries_.empty())
      throw engine::Error(path + ": no handover state into '" + skill_.name + "' ([training] play_entries)");
    for (const robot::EntryState& e : playEntries_) {
      std::unique_ptr<levels::Level>& level = playLevels_[e.level];
      if (!level) level = std::make_unique<levels::Level>(levels::loadLevel(engine::projectFile(e.level)));
    }
    for (const robot::SkillDef& d : robot::loadSkillTree(treePath, model).skills) playSet_.skills.push_back({d, {}});
    for (const robot::EntryState& e : playEntries_) robot::entryRuntime(e, playSet_);  // every skill named is known
  }
  for (int i = 0; i < options.numEnvs; ++i) {
    envs_.push_back(std::make_unique<Env>());
    envs_.back()->model = model_;
    envs_.back()->termSums.assign(terms_.size(), 0.0);
  }
  applyLesson();
}

void SkillEnv::makeRoutes() {
  trainee_.def = skill_;
  if (skill_.handover > 0) {
    std::vector<HandoverStage> stages{{&parent_, options_.parentPolicy}};
    for (size_t k = 0; k < via_.size(); ++k) stages.push_back({&via_[k], options_.via[k].policy});
    route_ = makeHandoverRoute(stages, skill_);
  }
  if (skill_.handoverBack > 0) {
    backSkill_ = skill_;
    backSkill_.handoverSeconds = skill_.handoverBackSeconds;
    backSkill_.handoverVx = {0.0, 0.0};
    backRoute_ = makeHandoverRoute({{&backChild_, options_.back.policy}}, backSkill_);
  }
}

int SkillEnv::lessonCount() const {
  return int(std::max(treeSkill_.terrain.lessons.size(), treeSkill_.curriculum.lessons()));
}

double SkillEnv::advanceAt() const {
  return treeSkill_.curriculum.lessons() == 0 ? treeSkill_.terrain.advanceAt : treeSkill_.curriculum.advanceAt;
}

void SkillEnv::applyLesson() {
  const CurriculumDef& c = treeSkill_.curriculum;
  if (c.lessons() == 0) return makeRoutes();
  const size_t l = size_t(std::clamp(lesson_, 0, int(c.lessons()) - 1));
  if (!c.vxMax.empty()) skill_.commands.vx.hi = c.vxMax[l];
  if (!c.amplitudeMax.empty()) skill_.commands.amplitude.hi = c.amplitudeMax[l];
  if (!c.halfPeriodTicks.empty()) skill_.prior.halfPeriodTicks = c.halfPeriodTicks[l];
  if (!c.stride.empty()) skill_.prior.stride = c.stride[l];
  makeRoutes();
}

SkillEnv::~SkillEnv() = default;

std::vector<std::string> SkillEnv::rewardTermNames() const {
  std::vector<std::string> names;
  for (const WeightedTerm& t : terms_) names.push_back(t.term->name);
  return names;
}

double SkillEnv::physicsSeconds() const {
  double s = 0;
  for (const auto& e : envs_) s += e->physicsSeconds;
  return s;
}

// commands follow the keyboard's interlock: one of vx, vy, wz non-zero, or all zero
void SkillEnv::sampleCommand(Env& e) {
  const robot::CommandDef& c = skill_.commands;
  const CommandDraws& d = skill_.draws;
  const robot::SkillCommand now = e.command;  // ramped commands continue from where they are
  e.command = robot::SkillCommand{};
  drawVelocity(e.rng, c, d, &e.command);
  if (c.amplitude.hi > 0) {
    e.amplitudeTarget = uniform(e.rng, c.amplitude);
    // drawn only when asked for, so other skills' streams are unchanged
    if (d.amplitudeZero > 0 && unit(e.rng) < d.amplitudeZero) e.amplitudeTarget = 0.0;
    e.command.amplitude = d.amplitudeRate > 0 ? now.amplitude : e.amplitudeTarget;
  }
  robot::takeCommandDraw(now, d.ramp, &e.command, &e.target);
  if (d.steer > 0) {  // drawn only when asked for, so other skills' streams are unchanged
    const double turn = d.steer * (2.0 * unit(e.rng) - 1.0);
    e.steer = e.target.vx != 0.0 || e.target.vy != 0.0 ? turn : 0.0;
    if (!d.ramp) e.keysWz = e.target.wz;  // (ramped: the keys' yaw rate goes on from where it was)
    steerCommand(e);
  }
  e.anchor = e.sensors.basePosition.head<2>();
  const double stretch = d.resampleJitter > 0 ? 1.0 + d.resampleJitter * (2.0 * unit(e.rng) - 1.0) : 1.0;
  e.nextCommandTick = e.tick + std::max(1, int(std::lround(d.resampleSeconds * stretch / engine::kTickSeconds)));
}

// [draws] steer: while the command moves the robot, its yaw rate is the keys' (0 under the interlock) plus the
// draw's turn, as play's heading hold adds a turn to W (robot::shapeCommand)
void SkillEnv::steerCommand(Env& e) const {
  e.command.wz = e.keysWz;
  if (e.command.vx != 0.0 || e.command.vy != 0.0) e.command.wz += e.steer;
}

void SkillEnv::resetEnv(Env& e, bool allowHandover) {
  const RandomisationDef& r = skill_.randomisation;
  double friction = 1.0;
  e.model.articulation.base.mass = model_.articulation.base.mass;
  if (options_.randomise) {
    friction = uniform(e.rng, r.friction);
    e.model.articulation.base.mass += uniform(e.rng, r.addedMass);
  }
  e.robot.reset();
  e.world = std::make_unique<engine::PhysicsWorld>();
  e.entry = nullptr;
  // [training] play_share: a play episode (drawn only when asked for, so other skills' episodes are unchanged)
  if (!playEntries_.empty() && allowHandover && unit(e.rng) < skill_.playShare) return startFromEntry(e, friction);
  e.world->addGround(friction);
  // [terrain] rise, tread, steps: this episode's staircase (drawn only when asked for)
  const TerrainDef& t = skill_.terrain;
  double u[3] = {0, 0, 0};
  if (t.draw.drawn())
    for (double& x : u) x = unit(e.rng);
  const Staircase staircase = drawStaircase(t, t.draw, stepHeight(), u[0], u[1], u[2]);
  addTerrain(*e.world, staircase.terrain, staircase.rise, friction);
  // on stairs the robot starts facing them (+X, within +-entry_heading_deg); elsewhere any heading
  const bool stairs = t.kind == TerrainDef::Kind::Stairs;
  const double yaw = stairs ? t.entryYaw * (2.0 * unit(e.rng) - 1.0) : M_PI * (2.0 * unit(e.rng) - 1.0);
  // the draw is the ground's coefficient; the robot's own stays 1 as in the levels (Bullet multiplies the two,
  // so giving the feet the draw too made the contact coefficient its square: 0.25-1.56 for [0.5, 1.25])
  e.robot = std::make_unique<robot::Robot>(e.model, *e.world, 0.0, 0.0, yaw);
  robot::JointArray q = e.robot->command().target;
  for (double& v : q) v += 0.02 * (2.0 * unit(e.rng) - 1.0);
  Eigen::Isometry3d base = e.robot->linkPose(*e.world, -1);
  // [terrain] spawn_along: some episodes start on a tread, the way down among them (drawn only when asked for)
  if (stairs && t.spawnAlong > 0 && unit(e.rng) < t.spawnAlong) {
    const double along = unit(e.rng), v = unit(e.rng);
    const Eigen::Vector2d at = stairsSpawn(staircase.terrain, staircase.rise, along, v);
    base.translation() += Eigen::Vector3d(at.x(), 0.0, at.y());
  }
  e.robot->teleport(*e.world, base, q);
  e.sensors = e.robot->sense(*e.world);
  e.state = robot::SkillState{};
  robot::enterSkill(&e.state, trainee_, e.sensors, 0);
  robot::SkillCommand handedOver;  // the keys' command at the switch (zero for an ordinary episode)
  // (the draw is made only for a skill with handover episodes, so other skills' episodes are unchanged)
  const double draw = allowHandover && skill_.handover + skill_.handoverBack > 0 ? unit(e.rng) : 1.0;
  if (draw < skill_.handover + skill_.handoverBack) {
    if (!handOver(e, draw >= skill_.handover, &handedOver)) {
      resetEnv(e, false);  // the parent fell before the switch: an ordinary episode instead
      return;
    }
    // a ceiling goes over the robot once it lies (a slab over the arena, the robot under its middle)
    addCeiling(*e.world, skill_.terrain, e.sensors.basePosition.head<2>(), 0.0, 20.0, 40.0, 40.0, friction);
  }
  e.previousAction = e.state.action;
  // the episode's motion starts here (after a handover: lying), facing the way the robot faces
  Eigen::Vector2d& lineStart = e.state.lineStart;
  Eigen::Vector2d& lineHeading = e.state.lineAlong;
  lineStart = e.sensors.basePosition.head<2>();
  lineHeading = robot::groundHeading(e.sensors);
  if (skill_.lineJitterHeading > 0 || skill_.lineJitterOffset > 0) {  // (drawn only when asked for)
    lineHeading = Eigen::Rotation2Dd(skill_.lineJitterHeading * (2.0 * unit(e.rng) - 1.0)) * lineHeading;
    lineStart +=
        skill_.lineJitterOffset * (2.0 * unit(e.rng) - 1.0) * Eigen::Vector2d(-lineHeading.y(), lineHeading.x());
  }
  // [training] heading_steer_share: steered episodes drawn only when a share below 1 asks for it (others unchanged)
  e.headingSteered =
      skill_.headingSteer > 0 && (skill_.headingSteerShare >= 1.0 || unit(e.rng) < skill_.headingSteerShare);
  // [ball] absent: some episodes without one (drawn only when asked for, so other skills' episodes are unchanged)
  const bool ball = skill_.ball.enabled && !(skill_.ball.absent > 0 && unit(e.rng) < skill_.ball.absent);
  e.ball = ball ? placeBall(*e.world, skill_.ball, e.sensors, e.rng, &e.kickDirection) : -1;
  if (e.ball >= 0) e.ballState = e.world->ballState(e.ball);
  e.tick = 0;
  e.yawRateSmoothed = 0;
  e.state.lineSteerError = 0;
  e.liftAskedTicks = 0;
  e.episodeReturn = 0;
  // every episode starts at amplitude 0; a ramped velocity command goes on from the handover's, as the keys' ramp
  // does in play across a switch (W held from the walk into the run: from the walk's command up to the run's)
  e.command = robot::SkillCommand{};
  if (skill_.draws.ramp) e.command.vx = handedOver.vx, e.command.vy = handedOver.vy, e.command.wz = handedOver.wz;
  e.keysWz = e.command.wz, e.steer = 0;
  sampleCommand(e);
  if (e.ball >= 0) ballIntoCommand(e.sensors, e.ballState, &e.command);
  const double pushEvery = r.pushEverySeconds;
  e.nextPushTick = options_.randomise && pushEvery > 0
                       ? int(std::lround((0.5 + unit(e.rng)) * pushEvery / engine::kTickSeconds))
                       : INT32_MAX;
  advanceCommand(e);
}

// a play episode: the level's static geometry, the robot and the runtime as the entry left them (the joints' speeds
// jittered by up to kPlayJitter so that repeated draws of an entry differ), the keys' state and the segment's events
void SkillEnv::startFromEntry(Env& e, double friction) {
  constexpr double kPlayJitter = 0.1;  // [rad/s]
  const robot::EntryState& entry = playEntries_[size_t(e.rng() % playEntries_.size())];
  const levels::Level& level = *playLevels_.at(entry.level);
  e.world->addGround(friction);
  for (const levels::BoxDef& b : level.boxes)
    e.world->addStaticBox(b.centre, Eigen::Quaterniond(Eigen::AngleAxisd(b.yaw, Eigen::Vector3d::UnitZ())),
                          0.5 * b.size, b.friction);
  for (const levels::QuestionBoxDef& q : level.questionBoxes)  // as the course adds them
    e.world->addStaticBox(q.centre, Eigen::Quaterniond::Identity(), 0.5 * q.size, 1.0);
  e.robot = std::make_unique<robot::Robot>(e.model, *e.world, 0.0, 0.0, 0.0);
  engine::ArticulationState body = entry.body;
  for (double& v : body.qd) v += kPlayJitter * (2.0 * unit(e.rng) - 1.0);
  e.world->setState(e.robot->id(), body);
  e.sensors = e.robot->sense(*e.world);
  e.state = robot::entryRuntime(entry, playSet_);
  e.state.active = &trainee_;  // (its policy runs batched, outside)
  e.previousAction = e.state.action;
  e.entry = &entry;
  e.keys = engine::CommandInput(entry.limits);
  e.keys.restore(entry.keys);
  e.events = engine::InputTimeline(entry.events);
  const int maxTicks = int(std::lround(skill_.termination.episodeSeconds / engine::kTickSeconds));
  e.playTicks =
      std::min(maxTicks, int(entry.segmentTicks) + int(std::lround(kPlayEpisodeMarginSeconds / engine::kTickSeconds)));
  e.ball = -1;
  e.headingSteered = false;
  e.tick = 0;
  e.yawRateSmoothed = 0;
  e.liftAskedTicks = 0;
  e.episodeReturn = 0;
  e.steer = 0, e.keysWz = 0;
  e.anchor = e.sensors.basePosition.head<2>();
  e.nextPushTick = INT32_MAX, e.nextCommandTick = INT32_MAX;
  playCommand(e);
}

// the play episode's next tick of keys, as play's input and control systems take them: the segment's events of the
// tick, the keys' ramp, then the runtime's shapeCommand (heading hold, a ground skill's line steer); skill keys are
// not followed (the skill being trained stays in control)
void SkillEnv::playCommand(Env& e) const {
  for (const engine::KeyEvent& k : e.events.eventsAt(e.entry->tick + 1 + e.tick)) e.keys.apply(k);
  e.keys.tick();
  const engine::CommandState& c = e.keys.state();
  robot::SwitchRequest request;
  request.vx = c.vx, request.vy = c.vy, request.wz = c.wz, request.amplitude = c.amplitude;
  request.vRate = e.keys.limits().vRate, request.wzRate = e.keys.limits().wzRate;
  e.command = robot::shapeCommand(&e.state, e.sensors, request);
  const robot::Skill* wanted = c.skillRequest >= 0 ? playSet_.byKey(c.skillRequest) : nullptr;
  e.waitsForStill = wanted && wanted->def.name != skill_.name && robot::waitsForStill(e.state, wanted);
}

// The command moves one tick toward its draw before it is observed, as the keys ramp before play's control step:
// the policy sees the command its action is then taken under.
void SkillEnv::advanceCommand(Env& e) const {
  // the amplitude command ramps like the R / F keys when the skill says so
  if (skill_.draws.amplitudeRate > 0) {
    const double step = skill_.draws.amplitudeRate * engine::kTickSeconds;
    e.command.amplitude += std::clamp(e.amplitudeTarget - e.command.amplitude, -step, step);
  }
  if (skill_.draws.ramp) {
    const engine::CommandLimits keys;                     // the keyboard's rates
    if (skill_.draws.steer > 0) e.command.wz = e.keysWz;  // the ramp sees the keys' command, not the steer
    engine::rampVelocityCommand(e.target.vx, e.target.vy, e.target.wz, keys.vRate, keys.wzRate, &e.command.vx,
                                &e.command.vy, &e.command.wz);
    if (skill_.draws.steer > 0) e.keysWz = e.command.wz, steerCommand(e);
  }
}

// a handover episode's start: runHandover along route_ (the parent, then the skills routed through)
bool SkillEnv::handOver(Env& e, bool back, robot::SkillCommand* commandAtSwitch) {
  if (!runHandover(model_, e.model, *e.world, *e.robot, &e.sensors, back ? backRoute_ : route_, e.rng, &e.state,
                   commandAtSwitch))
    return false;
  e.state.active = &trainee_;  // the same skill as the route's last (its policy runs batched, outside)
  return true;
}

HandoverRoute makeHandoverRoute(const std::vector<HandoverStage>& stages, const SkillSpec& destination) {
  HandoverRoute r;
  for (const HandoverStage& st : stages) r.set.skills.push_back({*st.skill, st.policy});
  r.set.skills.push_back({destination, {}});
  r.driver = stages.empty() ? nullptr : stages.front().skill;
  r.destinationSpec = &destination;
  return r;
}

bool runHandover(const robot::RobotModel& nominal, const robot::RobotModel& actual, engine::PhysicsWorld& world,
                 robot::Robot& robot, robot::Sensors* sensors, const HandoverRoute& route, std::mt19937_64& rng,
                 robot::SkillState* state, robot::SkillCommand* commandAtSwitch) {
  const std::vector<robot::Skill>& skills = route.set.skills;
  const robot::Skill& destination = route.destination();
  const SkillSpec& skill = *route.destinationSpec;
  const SkillSpec& driver = *route.driver;
  // the keys: the drive's command (W held at handover_vx, or one draw), ramping at the keyboard's rates
  robot::SkillCommand keys, target;
  if (skill.handoverVx.lo != 0 || skill.handoverVx.hi != 0)
    target.vx = uniform(rng, skill.handoverVx);  // W held
  else
    drawVelocity(rng, driver.commands, driver.draws, &target);
  int run = std::max(1, int(std::lround(uniform(rng, skill.handoverSeconds) / engine::kTickSeconds)));
  const engine::CommandLimits limits;
  robot::SwitchRequest request;
  request.vRate = limits.vRate, request.wzRate = limits.wzRate;
  *state = robot::SkillState{};
  robot::SkillCommand command;
  int64_t tick = 0;
  size_t stage = 0;  // the stage whose key is pressed ...
  int driven = 0;    // ... and the ticks it has driven since it took over
  for (;; ++tick) {
    if (state->active == &skills[stage] && driven >= run) {  // its drive is over: the next key
      ++stage;
      driven = 0;
      const bool via = stage + 1 < skills.size();  // a stage routed through drives at no movement key
      if (via) run = int(std::lround(uniform(rng, skill.handoverViaSeconds) / engine::kTickSeconds));
      if (via || robot::isStillSkill(skill)) target = robot::SkillCommand{};
    }
    request.wanted = &skills[stage];
    engine::rampVelocityCommand(target.vx, target.vy, target.wz, limits.vRate, limits.wzRate, &keys.vx, &keys.vy,
                                &keys.wz);
    request.vx = keys.vx, request.vy = keys.vy, request.wz = keys.wz;
    const robot::RouteResult routed = robot::route(route.set, state, *sensors, request, tick);
    if (state->active == &destination) {
      *commandAtSwitch = command;
      return true;
    }
    if (!routed.switchedTo && state->postureWaitTicks > kMaxHandoverWaitTicks) return false;  // never got there
    if (!state->active) {  // the standing controller until the first skill takes over
      robot.setCommand(robot::Robot::standingCommand(actual));
    } else {
      command = robot::shapeCommand(state, *sensors, request);
      robot::PdCommand pd;
      robot::controlStep(nominal, actual, state, *sensors, world, command, robot::waitsForStill(*state, request.wanted),
                         &pd);
      robot.setCommand(pd);
      if (state->active == &skills[stage]) ++driven;
    }
    robot::stepPhysicsTick(robot, world);
    *sensors = robot.sense(world);
    robot::updateDrift(*sensors, &state->drift);
    if (state->active && robot::hasFallen(state->active->def.termination, *sensors)) return false;
  }
}

void SkillEnv::observe(const Env& e, float* out) const {
  robot::observe(model_, e.state, e.sensors, *e.world, e.command, out);
}

void SkillEnv::reset(uint64_t seed, Eigen::MatrixXf* observations) {
  observations->resize(robot::kObservationSize, numEnvs());
  std::mt19937_64 seeder(seed);
  seeder.discard(uint64_t(options_.firstEnv));  // a rank's share: the run's environment n takes the seeder's n-th draw
  for (auto& e : envs_) e->rng.seed(seeder());
  finished_.clear();
  rolloutSteps_ = 0;
  for (auto& e : envs_) e->startStep = 0;
  pool_.parallelFor(numEnvs(), [&](int i) {
    resetEnv(*envs_[size_t(i)]);
    observe(*envs_[size_t(i)], observations->col(i).data());
  });
}

void SkillEnv::step(const Eigen::MatrixXf& actions, StepResult* result) {
  const int n = numEnvs();
  const int maxTicks = int(std::lround(skill_.termination.episodeSeconds / engine::kTickSeconds));
  result->observations.resize(robot::kObservationSize, n);
  result->finalObservations.resize(robot::kObservationSize, n);

  pool_.parallelFor(n, [&](int i) {
    Env& e = *envs_[size_t(i)];
    e.previousAction = e.state.action;

    // control: the runtime's step from the policy's output (filtered action, clock, prior, a handover's fade)
    robot::PdCommand pd;
    robot::act(e.model, &e.state, actions.col(i).data(), e.command, e.entry && e.waitsForStill, &pd);
    e.robot->setCommand(pd);
    const auto t0 = std::chrono::steady_clock::now();
    robot::stepPhysicsTick(*e.robot, *e.world);
    e.physicsSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    e.sensors = e.robot->sense(*e.world);
    ++e.tick;
    if (e.ball >= 0) {
      e.ballState = e.world->ballState(e.ball);
      ballIntoCommand(e.sensors, e.ballState, &e.command);
    }

    if (e.entry) {
      // a play episode's command is its keys' (playCommand: shapeCommand steers as play does)
    } else if (skill_.commands.lineSteer > 0) {
      // [commands] line_steer: steered back toward the line as the crawl card (and a player) steers
      robot::SkillCommand line;
      robot::lineIntoCommand(e.sensors, e.state.lineStart, e.state.lineAlong, &line);
      e.command.wz = robot::steerTowardLine(skill_.commands, skill_.commands.lineSteer, line, &e.state.lineSteerError);
    } else if (e.headingSteered) {
      // [training] heading_steer: squared up to +X as the stairs card (and play's heading hold) steers
      e.command.wz = robot::squareToPlusX(e.sensors.yaw, skill_.headingSteer, skill_.commands);
    } else if (e.command.wz != 0.0) {
      // heading_hold's heading turns with the commanded yaw rate: facing where the commands lead (not a steer back
      // toward the line)
      e.state.lineAlong = Eigen::Rotation2Dd(e.command.wz * engine::kTickSeconds) * e.state.lineAlong;
    }

    const double yawRate = (e.sensors.baseRotation * e.sensors.angularVelocity).z();
    e.yawRateSmoothed += (yawRate - e.yawRateSmoothed) * engine::kTickSeconds / kLineTurnSeconds;

    // reward
    RewardContext ctx{&e.sensors,
                      &e.command,
                      &e.state.action,
                      &e.previousAction,
                      &skill_,
                      e.ball >= 0 ? &e.ballState : nullptr,
                      e.kickDirection,
                      &e.anchor,
                      e.state.phase.tp,
                      &e.state.lineStart,
                      &e.state.lineAlong,
                      e.yawRateSmoothed,
                      e.world.get()};
    double reward = 0;
    for (size_t k = 0; k < terms_.size(); ++k) {
      const double v = terms_[k].weight * terms_[k].term->value(ctx);
      e.termSums[k] = v;
      reward += v;
    }
    // legged_gym's only_positive_rewards: with a negative total a fall would be the agent's best move
    if (skill_.onlyPositiveRewards) reward = std::max(reward, 0.0);
    e.reward = float(reward);
    e.episodeReturn += reward;

    // disturbances and command changes for the next tick
    if (e.tick >= e.nextPushTick) {
      engine::ArticulationState s;
      e.world->readState(e.robot->id(), &s);
      const double angle = 2.0 * M_PI * unit(e.rng), speed = uniform(e.rng, skill_.randomisation.pushSpeed);
      s.baseLinearVelocity += Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0) * speed;
      e.world->setState(e.robot->id(), s);
      e.nextPushTick = e.tick + int(std::lround(skill_.randomisation.pushEverySeconds / engine::kTickSeconds));
      e.anchor = e.sensors.basePosition.head<2>();  // a push moves the robot: hold where it is pushed from
    }
    if (e.tick >= e.nextCommandTick) {
      sampleCommand(e);
      if (e.ball >= 0) ballIntoCommand(e.sensors, e.ballState, &e.command);
    }

    // episode end: a fall terminates (and, when the skill asks, the lifted foot touching down), the time limit
    // truncates
    bool fell = robot::hasFallen(skill_.termination, e.sensors);
    if (skill_.termination.liftedFootTouchSeconds > 0) {
      e.liftAskedTicks = askedFootLift(skill_, e.command.amplitude) >= 0.5 * kFootLiftHeight ? e.liftAskedTicks + 1 : 0;
      const long graceTicks = std::lround(skill_.termination.liftedFootTouchSeconds / engine::kTickSeconds);
      if (e.liftAskedTicks >= graceTicks && e.sensors.footContact[1]) fell = true;
    }
    e.terminated = fell;
    e.truncated = !fell && e.tick >= (e.entry ? e.playTicks : maxTicks);
    if (e.terminated || e.truncated) {
      observe(e, e.finalObservation.data());
      e.finishedReturn = e.episodeReturn;
      e.finishedLength = e.tick;
      resetEnv(e);
    } else if (e.entry) {
      playCommand(e);
    } else {
      advanceCommand(e);
    }
    observe(e, result->observations.col(i).data());
  });

  // gather in environment order (independent of threading)
  result->rewards.resize(n);
  result->terminated.assign(size_t(n), 0);
  result->truncated.assign(size_t(n), 0);
  result->episodeReturns.clear();
  result->episodeLengths.clear();
  result->rewardTermSums.assign(terms_.size(), 0.0);
  for (int i = 0; i < n; ++i) {
    Env& e = *envs_[size_t(i)];
    result->rewards[i] = e.reward;
    result->terminated[size_t(i)] = e.terminated;
    result->truncated[size_t(i)] = e.truncated;
    if (e.truncated)
      for (int k = 0; k < robot::kObservationSize; ++k) result->finalObservations(k, i) = e.finalObservation[size_t(k)];
    if (e.terminated || e.truncated) {
      result->episodeReturns.push_back(float(e.finishedReturn));
      result->episodeLengths.push_back(e.finishedLength);
      // the curriculum's record, in environment order so that it does not depend on threads
      if (lessonCount() > 1) {
        finished_.push_back({e.finishedReturn, e.startStep, rolloutSteps_, options_.firstEnv + i});
        e.startStep = rolloutSteps_ + 1;  // the fresh episode's first step is the next one
      }
    }
    for (size_t k = 0; k < terms_.size(); ++k) result->rewardTermSums[k] += e.termSums[k];
  }
  ++rolloutSteps_;
}

void SkillEnv::endRollout() {
  if (lessonCount() <= 1) return;
  // the episodes still running were cut by the rollout's end: they count for what they played
  for (int i = 0; i < numEnvs(); ++i)
    if (envs_[size_t(i)]->tick > 0)
      finished_.push_back(
          {envs_[size_t(i)]->episodeReturn, envs_[size_t(i)]->startStep, rolloutSteps_, options_.firstEnv + i});
  // under mpirun, every rank's episodes in the order one process records them (by step, then environment): every
  // rank's curriculum takes the same measure
  if (options_.comm && options_.comm->size() > 1) {
    std::string mine(finished_.size() * sizeof(Finished), '\0');
    if (!finished_.empty()) std::memcpy(mine.data(), finished_.data(), mine.size());
    finished_.clear();
    for (const std::string& bytes : options_.comm->gather(mine)) {
      const size_t at = finished_.size(), count = bytes.size() / sizeof(Finished);
      finished_.resize(at + count);
      if (count > 0) std::memcpy(&finished_[at], bytes.data(), count * sizeof(Finished));
    }
    std::stable_sort(finished_.begin(), finished_.end(), [](const Finished& a, const Finished& b) {
      return a.endStep != b.endStep ? a.endStep < b.endStep : a.env < b.env;
    });
  }
  const int maxTicks = int(std::lround(skill_.termination.episodeSeconds / engine::kTickSeconds));
  const int minTicks = std::min(maxTicks, int(std::lround(1.0 / engine::kTickSeconds)));
  bool advance = false;
  for (const Finished& f : finished_) {
    const int possible = std::min(maxTicks, rolloutSteps_ - f.startStep);
    if (possible < minTicks || lesson_ + 1 >= lessonCount()) continue;
    // an exponential average over the lesson's episodes, bias-corrected (it starts at 0, so dividing by
    // 1 - 0.98^k weighs the first episodes evenly instead of letting the first one decide), over at least two
    // episodes per environment (two rollouts' worth)
    smoothed_ = 0.98 * smoothed_ + 0.02 * (f.episodeReturn / double(possible));
    ++lessonEpisodes_;
    advance = advance || (curriculumScore() > advanceAt() && lessonEpisodes_ >= 2 * globalEnvs());
  }
  finished_.clear();
  if (advance) {  // the next rollout trains the next lesson
    ++lesson_;
    lessonEpisodes_ = 0;
    smoothed_ = 0;
    applyLesson();
  }
}

double SkillEnv::curriculumScore() const {
  return lessonEpisodes_ > 0 ? smoothed_ / (1.0 - std::pow(0.98, lessonEpisodes_)) : 0.0;
}

double SkillEnv::stepHeight() const {
  const std::vector<double>& lessons = skill_.terrain.lessons;
  return lessons.empty() ? 0.0 : lessons[size_t(std::min<int>(lesson_, int(lessons.size()) - 1))];
}

std::string SkillEnv::curriculumNote() const {
  if (lessonCount() == 0) return {};
  char what[96];
  if (!treeSkill_.curriculum.vxMax.empty())
    std::snprintf(what, sizeof what, "forward commands up to %.2f m/s, T1 %d, stride %.2f", skill_.commands.vx.hi,
                  skill_.prior.halfPeriodTicks, skill_.prior.stride);
  else if (!treeSkill_.curriculum.amplitudeMax.empty())
    std::snprintf(what, sizeof what, "amplitude commands up to %.2f", skill_.commands.amplitude.hi);
  else
    std::snprintf(what, sizeof what, "steps %.2f m", stepHeight());
  char buf[256];
  std::snprintf(buf, sizeof buf, "lesson %d/%d (%s; smoothed return per step %.2f of %.2f over %d episodes)",
                lesson_ + 1, lessonCount(), what, curriculumScore(), advanceAt(), lessonEpisodes_);
  return buf;
}

std::string SkillEnv::saveState() const {
  std::string out(2 * sizeof(int) + sizeof(double), '\0');
  std::memcpy(out.data(), &lesson_, sizeof(int));
  std::memcpy(out.data() + sizeof(int), &lessonEpisodes_, sizeof(int));
  std::memcpy(out.data() + 2 * sizeof(int), &smoothed_, sizeof(double));
  return out;
}

void SkillEnv::loadState(const std::string& bytes) {
  if (bytes.empty()) return;  // a checkpoint from before curricula: lesson 0
  if (bytes.size() != 2 * sizeof(int) + sizeof(double)) throw engine::Error("skill env state: wrong size");
  std::memcpy(&lesson_, bytes.data(), sizeof(int));
  std::memcpy(&lessonEpisodes_, bytes.data() + sizeof(int), sizeof(int));
  std::memcpy(&smoothed_, bytes.data() + 2 * sizeof(int), sizeof(double));
  if (lesson_ < 0 || (lesson_ > 0 && lesson_ >= lessonCount()))
    throw engine::Error("skill env state: lesson " + std::to_string(lesson_) + " does not exist");
  applyLesson();
}

}  // namespace ai
