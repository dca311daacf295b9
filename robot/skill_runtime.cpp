// skill_runtime.cpp — the control step and the switches (see skill_runtime.h).
#include "robot/skill_runtime.h"

#include "engine/core/error.h"
#include "engine/input/command.h"

namespace robot {

void stepPhysicsTick(Robot& robot, engine::PhysicsWorld& world) {
  for (int k = 0; k < kSubsteps; ++k) {
    robot.applyPd(world);
    world.step(kSubstepSeconds);
  }
}

// --- SkillSet ----------------------------------------------------------------------------------------------------

const Skill* SkillSet::byKey(int key) const {
  if (key < 0) return nullptr;  // keyless skills have -1
  for (const Skill& s : skills)
    if (s.def.key == key) return &s;
  return nullptr;
}

const Skill* SkillSet::byName(const std::string& name) const {
  for (const Skill& s : skills)
    if (s.def.name == name) return &s;
  return nullptr;
}

const Skill* SkillSet::root() const {
  for (const Skill& s : skills)
    if (s.def.parent.empty()) return &s;
  return nullptr;
}

int SkillSet::requestKey(const Skill& s) const {
  const Skill* at = &s;
  for (size_t hops = 0; at && at->def.key < 0 && hops <= skills.size(); ++hops) at = upFrom(*at);
  return at && at->def.key >= 0 ? at->def.key : -1;
}

const Skill* SkillSet::upFrom(const Skill& s) const {
  const std::string& name = s.def.up.empty() ? s.def.parent : s.def.up;
  return name.empty() ? nullptr : byName(name);
}

const Skill* SkillSet::nextHop(const Skill& from, const Skill& to) const {
  if (&from == &to) return nullptr;
  std::vector<const Skill*> up;  // from, then each way up while the skills there are loaded
  for (const Skill* s = &from; s && up.size() <= skills.size(); s = upFrom(*s)) up.push_back(s);
  // walk up from `to` by parents until we meet that chain; remember the child of the meeting point
  const Skill* below = nullptr;
  for (const Skill* s = &to; s; s = s->def.parent.empty() ? nullptr : byName(s->def.parent)) {
    for (size_t i = 0; i < up.size(); ++i)
      if (up[i] == s) return i > 0 ? up[1] : below;  // go up first, else down
    below = s;
    if (!s->def.parent.empty() && !byName(s->def.parent)) return nullptr;
  }
  return nullptr;
}

// --- switching -----------------------------------------------------------------------------------------------------

SkillCommand commandWithin(double vx, double vy, double wz, const CommandDef& range) {
  SkillCommand command;
  command.vx = std::clamp(vx, std::min(range.vx.lo, 0.0), std::max(range.vx.hi, 0.0));
  command.vy = std::clamp(vy, std::min(range.vy.lo, 0.0), std::max(range.vy.hi, 0.0));
  command.wz = std::clamp(wz, std::min(range.wz.lo, 0.0), std::max(range.wz.hi, 0.0));
  return command;
}

SwitchGate switchGate(const SkillSet& set, const SkillState& state, const Sensors& sensors,
                      const SwitchRequest& request, int64_t tick) {
  SwitchGate g;
  const Skill* active = state.active;
  const Skill* wanted = request.wanted;
  if (!wanted || wanted == active) return g;
  g.next = active ? set.nextHop(*active, *wanted) : wanted;
  const Skill* next = g.next;
  const bool direct = next == wanted;
  // upright skills switch when the robot is upright; a ground skill (lying down) switches as it lies, but only to
  // another ground skill or to its way up (a stand-up skill): it cannot hand a lying robot to the walk (and a stand-up
  // hands over to the walk once the robot stands: robot::postureAllowsSwitch)
  const bool ground = active && isGroundSkill(active->def);
  const bool handsOver = !active || !next || mayHandOver(active->def, next->def);
  // a hop's time: after a routed hop, and from the standing controller into a skill that starts from the default
  // pose (the jump, the kick): the jump asked for at the spawn's first tick fell at its second landing in 20 of 20
  // seeds on levels/flat, asked for 0.5 s in, in 2 of 20 (7 s of jumping)
  const bool hopWait = !direct || (!active && startsFromDefaultPose(next->def));
  const double drift = state.drift.norm();
  g.ready = handsOver && (ground || sensors.tilt < kSwitchMaxTilt) &&
            (!hopWait || tick - state.activeSince >= kMinHopTicks) &&
            (!active || !next || postureAllowsSwitch(active->def, next->def, sensors, state.postureWaitTicks)) &&
            (!active || cycleAllowsSwitch(active->def, wanted->def, state.phase, drift, state.postureWaitTicks));
  g.inPhase = !active || !next || phaseAllowsSwitch(active->def, next->def, state.phase);
  // a skill that starts from the default pose (the jump, the kick) waits for a squat or a lift to come back first
  if (next && active && startsFromDefaultPose(next->def) && request.amplitude > 0) {
    g.lowerAmplitude = true;
    g.ready = false;
  }
  g.brakes = next && active && switchWaits(active->def, next->def);
  return g;
}

RouteResult route(const SkillSet& set, SkillState* state, const Sensors& sensors, const SwitchRequest& request,
                  int64_t tick) {
  RouteResult result;
  const Skill* wanted = request.wanted;
  if (!wanted || wanted == state->active) {
    state->restWaitTicks = -1;  // the request went away (or was reached)
    state->postureWaitTicks = 0;
    return result;
  }
  const SwitchGate g = switchGate(set, *state, sensors, request, tick);
  result.lowerAmplitude = g.lowerAmplitude;
  bool ready = g.ready;
  // into a still skill from rest, into a slower one at its top speed: the active skill brakes first
  if (g.next && ready && g.brakes) {
    const SkillDef& from = state->active->def;
    // the keys' command as the active skill gets it: right after a routed hop (run -> walk -> prone, W held) the
    // keys still give the run's speed
    const SkillCommand keys = commandWithin(request.vx, request.vy, request.wz, from.commands);
    if (state->restWaitTicks < 0) {  // start braking from the command the keys give now
      state->restWaitTicks = 0;
      state->brake = keys;
    }
    // on the way to a still skill (run -> walk -> prone) every hop brakes toward rest, not only the last: the walk
    // taking over a run at its top speed and braking at once fell in 3 of 4 seeds with W held
    const SkillCommand toward = isStillSkill(wanted->def) ? SkillCommand{} : keys;
    state->brakeTarget = switchBrakeTarget(from, g.next->def, toward);
    ready = readyForSwitch(from, g.next->def, state->brakeTarget, state->brake, sensors, state->drift.norm()) ||
            state->restWaitTicks >= maxSwitchWaitTicks(g.next->def);
  }
  if (g.next && ready && g.inPhase) {  // (a skill that brakes first reaches its phase window within a cycle)
    enterSkill(state, *g.next, sensors, tick);
    state->restWaitTicks = -1;
    state->postureWaitTicks = 0;
    result.switchedTo = g.next;
  } else {
    ++state->postureWaitTicks;
  }
  return result;
}

void enterSkill(SkillState* state, const Skill& next, const Sensors& sensors, int64_t tick) {
  if (state->active) {
    state->fadePhase = state->phase;  // the old prior goes on under its own clock while it fades out
    carryPhase(state->active->def.prior, next.def.prior, &state->phase);  // same fraction of the gait cycle
  } else {
    state->action.fill(0.0f);
    state->phase = PhaseClock{};
  }
  state->fadingFrom = state->active;
  state->fadeTicks = state->active ? kSwitchFadeTicks : 0;
  state->active = &next;
  state->activeSince = tick;
  // the new skill keeps the heading held so far, on a line through where it starts (the walk taking the stairs'
  // robot 0.66 m off the stairs' line turned 1.6 rad back toward it and fell; taking the heading of the moment
  // instead, the run took over the walk's lean back to its line, 0.19 rad, and ran into levels/mario's wall)
  state->headingLineStart = sensors.basePosition.head<2>();
  // a line-keeping skill (the crawl) keeps to the one it begins on, as it trained
  state->lineStart = sensors.basePosition.head<2>();
  state->lineAlong = groundHeading(sensors);
  state->lineSteerError = 0.0;
}

namespace {

// Every number of the robot's state is finite (a diverged simulation shows NaN or inf here first)
bool sensorsFinite(const Sensors& s) {
  bool ok = s.basePosition.allFinite() && s.baseRotation.coeffs().allFinite() && s.linearVelocity.allFinite() &&
            s.angularVelocity.allFinite() && s.centreOfMass.allFinite();
  for (int j = 0; j < kNumJoints; ++j) ok = ok && std::isfinite(s.q[size_t(j)]) && std::isfinite(s.qd[size_t(j)]);
  return ok;
}

}  // namespace

namespace {

// A ground skill that trained steered back toward the line it began on ([commands] line_steer: the crawl) is steered
// so while it moves with no turn key, by the same law as its training and its card. A turn key takes over; once it is
// released the line starts again where the robot is, the way it faces then.
void steerToLine(SkillState* state, const Sensors& sensors, bool moving, SkillCommand* command) {
  const SkillDef& def = state->active->def;
  if (def.commands.lineSteer <= 0.0) return;
  if (command->wz != 0.0) {
    state->lineStart = sensors.basePosition.head<2>();
    state->lineAlong = groundHeading(sensors);
    state->lineSteerError = 0.0;
    return;
  }
  if (!moving || state->restWaitTicks >= 0) return;
  SkillCommand line;
  lineIntoCommand(sensors, state->lineStart, state->lineAlong, &line);
  command->wz = steerTowardLine(def.commands, def.commands.lineSteer, line, &state->lineSteerError);
}

// W / S (or the sideways keys) with no turn key: an upright skill that can turn keeps to the line the robot was on
// when it started moving (or the turn keys were released), facing the way it faced then, as a player would steer
// against a drift. The heading asked for leans back toward the line by atan(line_hold * offset) (the skill's
// [commands] line_hold; 0: the heading alone), and the turn rate asked for is kHeadingGain times the heading error, at
// most kHeadingMaxRate (and within the skill's wz range).
void holdHeading(SkillState* state, const Sensors& sensors, SkillCommand* command) {
  const CommandDef& range = state->active->def.commands;
  const bool moving = command->vx != 0.0 || command->vy != 0.0;
  const Eigen::Vector2d p = sensors.basePosition.head<2>();
  if (isGroundSkill(state->active->def)) {  // the upright hold below is not theirs
    state->headingRef = sensors.yaw;
    state->headingLineStart = p;
    steerToLine(state, sensors, moving, command);
    return;
  }
  const bool canTurn = range.wz.hi > 0.0 && range.wz.lo < 0.0;
  if (!moving || !canTurn || command->wz != 0.0 || state->restWaitTicks >= 0) {
    state->headingRef = sensors.yaw;
    state->headingLineStart = p;
    return;
  }
  const Eigen::Vector2d along(std::cos(state->headingRef), std::sin(state->headingRef));
  const Eigen::Vector2d d = p - state->headingLineStart;
  const double offset = along.x() * d.y() - along.y() * d.x();  // left of the line > 0
  const double wanted = state->headingRef - std::atan(range.lineHold * offset);
  const double error = std::remainder(wanted - sensors.yaw, 2.0 * M_PI);
  const double limit = headingHoldLimit(range);
  command->wz = std::clamp(kHeadingGain * error, -limit, limit);
}

}  // namespace

void applyBrake(SkillState* state, const SwitchRequest& rates, SkillCommand* command) {
  if (state->restWaitTicks < 0) return;
  const SkillCommand& to = state->brakeTarget;
  SkillCommand& b = state->brake;
  engine::rampVelocityCommand(to.vx, to.vy, to.wz, rates.vRate, rates.wzRate, &b.vx, &b.vy, &b.wz);
  command->vx = b.vx, command->vy = b.vy, command->wz = b.wz;
  ++state->restWaitTicks;
}

SkillCommand shapeCommand(SkillState* state, const Sensors& sensors, const SwitchRequest& keys) {
  SkillCommand command = commandWithin(keys.vx, keys.vy, keys.wz, state->active->def.commands);
  command.amplitude = keys.amplitude;
  holdHeading(state, sensors, &command);
  applyBrake(state, keys, &command);  // a switch waits for rest or a slower speed: brake instead of following the keys
  return command;
}

// --- the control step ----------------------------------------------------------------------------------------------

SkillCommand observedCommand(const SkillState& state, const Sensors& sensors, const engine::PhysicsWorld& world,
                             const SkillCommand& command) {
  SkillCommand seen = command;
  const CommandDef& c = state.active->def.commands;
  if (c.lineCommand) lineIntoCommand(sensors, state.lineStart, state.lineAlong, &seen);
  if (c.stepCommand) stepIntoCommand(sensors, world, c.stepLookBack, &seen);
  return seen;
}

void observe(const RobotModel& nominal, const SkillState& state, const Sensors& sensors,
             const engine::PhysicsWorld& world, const SkillCommand& command, float* out) {
  if (!sensorsFinite(sensors))
    throw engine::Error("non-finite robot state under skill '" + state.active->def.name +
                        "' (the simulation diverged: a policy, gain or model value out of range)");
  double s, c;
  phaseSignal(state.phase.tp, state.active->def.prior.halfPeriodTicks, &s, &c);
  Observation o;
  buildObservation(sensors, nominal, state.action, observedCommand(state, sensors, world, command), s, c, &o);
  std::copy(o.begin(), o.end(), out);
}

void act(const RobotModel& model, SkillState* state, const float* policyOutput, const SkillCommand& command,
         bool waitsForStill, PdCommand* out) {
  const SkillDef& def = state->active->def;
  for (int i = 0; i < kActionSize; ++i)
    if (!std::isfinite(policyOutput[i]))
      throw engine::Error("non-finite action from the policy of skill '" + def.name + "' (output " + std::to_string(i) +
                          ")");
  filterAction(def, policyOutput, &state->action);
  // a request out of jumps in a row for a still skill waits in the cycle's closing stand rather than jump again
  if (!holdsClosingStand(def, state->phase, waitsForStill)) state->phase.advance(def.prior, command);
  skillPdCommand(model, def, state->action, state->phase, command, out);
  if (state->fadingFrom && state->fadeTicks > 0) {
    // the old prior's share fades linearly: target += w (old prior - new prior), with the policy's part unchanged
    const SkillDef& from = state->fadingFrom->def;
    state->fadePhase.advance(from.prior, command);
    fadePrior(model, from, state->fadePhase, def, state->phase, command, double(state->fadeTicks) / kSwitchFadeTicks,
              out);
    --state->fadeTicks;
  }
}

void controlStep(const RobotModel& nominal, const RobotModel& model, SkillState* state, const Sensors& sensors,
                 const engine::PhysicsWorld& world, const SkillCommand& command, bool waitsForStill, PdCommand* out) {
  Eigen::MatrixXf observation(kObservationSize, 1), output;
  observe(nominal, *state, sensors, world, command, observation.data());
  state->active->policy(observation, &output);
  act(model, state, output.data(), command, waitsForStill, out);
}

bool waitsForStill(const SkillState& state, const Skill* wanted) {
  return wanted && wanted != state.active &&
         (isStillSkill(wanted->def) || (state.active && isKeyPoseCycle(state.active->def)));
}

}  // namespace robot
