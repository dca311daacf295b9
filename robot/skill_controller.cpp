// skill_controller.cpp — action + prior -> PD targets.
#include "robot/skill_controller.h"

#include <algorithm>
#include <cmath>

#include "engine/loop/clock.h"

namespace robot {
namespace {

// leg joint indices in kJointNames order
constexpr size_t kLeftHipPitch = 0, kLeftKnee = 3, kLeftAnklePitch = 4;
constexpr size_t kRightHipPitch = 6, kRightKnee = 9, kRightAnklePitch = 10;
constexpr size_t kLeftShoulderPitch = 13, kRightShoulderPitch = 18;

}  // namespace

void phaseActivation(int tp, int t1, double* u1, double* u2) {
  *u1 = *u2 = 0.0;
  if (tp > 0 && tp <= t1)
    *u1 = 0.5 * (1.0 - std::cos(2.0 * M_PI * tp / t1));
  else if (tp > t1)
    *u2 = 0.5 * (1.0 - std::cos(2.0 * M_PI * (tp - t1) / t1));
}

void phaseSignal(int tp, int t1, double* s, double* c) {
  *s = std::sin(M_PI * tp / t1);
  *c = std::cos(M_PI * tp / t1);
}

void filterAction(const SkillDef& skill, const float* policyOutput, std::array<float, kActionSize>* applied) {
  const float f = float(skill.actionFilter);
  for (size_t j = 0; j < size_t(kActionSize); ++j) {
    const float a = std::clamp(policyOutput[j], float(-kActionClip), float(kActionClip));
    (*applied)[j] = f * (*applied)[j] + (1.0f - f) * a;
  }
}

void takeCommandDraw(const SkillCommand& before, bool ramp, SkillCommand* command, SkillCommand* target) {
  *target = *command;
  if (!ramp) return;
  command->vx = before.vx;
  command->vy = before.vy;
  command->wz = before.wz;
}

bool commandIsZero(const SkillCommand& c) { return c.vx == 0.0 && c.vy == 0.0 && c.wz == 0.0; }

void PhaseClock::advance(const PriorDef& prior, const SkillCommand& command) {
  if (prior.kind == PriorDef::Kind::Keyframes)  // one shot: holds at the last key; repeating: wraps
    tp = prior.cycleTicks == 0        ? std::min(tp + 1, prior.halfPeriodTicks)
         : tp + 1 >= prior.cycleTicks ? prior.cycleStartTick
                                      : tp + 1;
  else
    advance(prior.halfPeriodTicks);
  const bool stepping = prior.kind == PriorDef::Kind::Phase && !(prior.standStill && commandIsZero(command));
  const double target = stepping ? 1.0 : 0.0;
  if (prior.standRampTicks <= 0)
    gait = target;
  else
    gait += std::clamp(target - gait, -1.0 / prior.standRampTicks, 1.0 / prior.standRampTicks);
}

void skillPdCommand(const RobotModel& model, const SkillDef& skill, const std::array<float, kActionSize>& action,
                    const PhaseClock& phase, const SkillCommand& command, PdCommand* out) {
  const int tp = phase.tp;
  for (size_t j = 0; j < size_t(kNumJoints); ++j) {
    const double a = std::clamp(double(action[j]), -kActionClip, kActionClip);
    out->target[j] = model.joints[j].defaultPosition + skill.actionScale[j] * a;
    out->kp[j] = skill.kp[j];
    out->kd[j] = skill.kd[j];
  }
  if (skill.prior.kind == PriorDef::Kind::Phase) {
    double u1, u2;
    phaseActivation(tp, skill.prior.halfPeriodTicks, &u1, &u2);
    const double dh = !skill.prior.standStill          ? skill.prior.dh
                      : skill.prior.standRampTicks > 0 ? skill.prior.dh * phase.gait
                      : commandIsZero(command)         ? 0.0
                                                       : skill.prior.dh;
    const double left = dh * u1 + skill.prior.d0, right = dh * u2 + skill.prior.d0;
    // hip pitch forward (negative), knee bends twice as much, ankle keeps the foot level
    out->target[kLeftHipPitch] -= left;
    out->target[kLeftKnee] += 2.0 * left;
    out->target[kLeftAnklePitch] -= left;
    out->target[kRightHipPitch] -= right;
    out->target[kRightKnee] += 2.0 * right;
    out->target[kRightAnklePitch] -= right;
    // the stride: hips swing with the forward command, ankles keep the soles parallel to the ground
    const double swing = skill.prior.stride * command.vx * std::cos(M_PI * tp / skill.prior.halfPeriodTicks);
    out->target[kLeftHipPitch] += swing;
    out->target[kLeftAnklePitch] -= swing;
    out->target[kRightHipPitch] -= swing;
    out->target[kRightAnklePitch] += swing;
    const double arms = skill.prior.armSwing * command.vx * std::cos(M_PI * tp / skill.prior.halfPeriodTicks);
    out->target[kLeftShoulderPitch] -= arms;
    out->target[kRightShoulderPitch] += arms;
  }
  if (skill.prior.kind == PriorDef::Kind::Pose) {
    double first, late;
    poseStages(skill.prior, command.amplitude, &first, &late);
    for (size_t j = 0; j < size_t(kNumJoints); ++j)
      out->target[j] += first * skill.prior.poseOffset[j] + late * skill.prior.lateOffset[j];
  }
  if (skill.prior.kind == PriorDef::Kind::Kick) {
    const double p = double(tp) / (2.0 * skill.prior.halfPeriodTicks);  // 0..1 through the kick cycle
    const double lift = p < 0.35  ? 0.5 * (1.0 - std::cos(M_PI * p / 0.35))
                        : p < 0.8 ? 1.0
                                  : 0.5 * (1.0 + std::cos(M_PI * (p - 0.8) / 0.2));
    const double swing = p >= 0.4 && p < 0.6 ? 0.5 * (1.0 - std::cos(2.0 * M_PI * (p - 0.4) / 0.2)) : 0.0;
    for (size_t j = 0; j < size_t(kNumJoints); ++j)
      out->target[j] += lift * skill.prior.poseOffset[j] + swing * skill.prior.swingOffset[j];
  }
  if (skill.prior.kind == PriorDef::Kind::Keyframes) {
    // the keys before and after tp (the default pose at tick 0 before the first), eased with a half cosine
    const std::vector<PriorDef::Keyframe>& keys = skill.prior.keyframes;
    size_t next = 0;
    while (next < keys.size() && keys[next].tick < tp) ++next;
    const JointArray zero{};
    if (next == keys.size()) {
      for (size_t j = 0; j < size_t(kNumJoints); ++j) out->target[j] += keys.back().offset[j];
    } else {
      const int t0 = next == 0 ? 0 : keys[next - 1].tick;
      const JointArray& from = next == 0 ? zero : keys[next - 1].offset;
      const double u = double(std::max(0, tp - t0)) / double(keys[next].tick - t0);
      const double w = 0.5 * (1.0 - std::cos(M_PI * u));
      for (size_t j = 0; j < size_t(kNumJoints); ++j) out->target[j] += (1.0 - w) * from[j] + w * keys[next].offset[j];
    }
  }
  if (skill.prior.kind == PriorDef::Kind::Jump) {
    const double p = double(tp) / (2.0 * skill.prior.halfPeriodTicks);  // 0..1 through the jump cycle
    const double c = p < 0.6 ? skill.prior.crouch * 0.5 * (1.0 - std::cos(2.0 * M_PI * p / 0.6)) : 0.0;
    for (size_t j = 0; j < size_t(kNumJoints); ++j) out->target[j] += c * skill.prior.poseOffset[j];
  }
  for (size_t j = 0; j < size_t(kNumJoints); ++j)  // the turn term (zero unless the prior has one)
    out->target[j] =
        std::clamp(out->target[j] + skill.prior.turn[j] * command.wz, model.joints[j].lower, model.joints[j].upper);
}

bool startsFromDefaultPose(const SkillDef& skill) {
  return !isGroundSkill(skill) && skill.prior.kind == PriorDef::Kind::Keyframes;
}

namespace {
// at rest on both feet (atRestForSwitch) and neither rising nor sinking
bool restingLevel(const Sensors& sensors) {
  return atRestForSwitch(sensors) && std::abs((sensors.baseRotation * sensors.linearVelocity).z()) < kRestSpeed;
}
}  // namespace

bool isStandingSettled(const Sensors& sensors) {
  if (!restingLevel(sensors)) return false;
  for (int j = 0; j < kNumLegJoints; ++j)
    if (std::abs(sensors.qd[size_t(j)]) >= kSettledJointSpeed) return false;
  return true;
}

bool isStillSkill(const SkillDef& skill) {
  const CommandDef& c = skill.commands;
  return c.vx.lo == 0 && c.vx.hi == 0 && c.vy.lo == 0 && c.vy.hi == 0 && c.wz.lo == 0 && c.wz.hi == 0;
}

bool atRestForSwitch(const Sensors& sensors) {
  const Eigen::Vector3d v = sensors.baseRotation * sensors.linearVelocity;
  const double wz = (sensors.baseRotation * sensors.angularVelocity).z();
  return v.head<2>().norm() < kRestSpeed && std::abs(wz) < kRestYawRate && sensors.footContact[0] &&
         sensors.footContact[1];
}

void updateDrift(const Sensors& sensors, Eigen::Vector2d* drift) {
  const Eigen::Vector2d v = (sensors.baseRotation * sensors.linearVelocity).head<2>();
  *drift += (v - *drift) * (engine::kTickSeconds / kDriftSeconds);  // one control tick
}

namespace {
// the lowest forward speed a skill trains at: its vx.lo if positive and it has no vy or wz command (with one, the
// keyboard's interlock trains it at vx = 0 too: the run turns on the spot), else at most 0
double lowestSpeed(const SkillDef& s) {
  const CommandDef& c = s.commands;
  const bool sideways = c.vy.lo != 0 || c.vy.hi != 0 || c.wz.lo != 0 || c.wz.hi != 0;
  return c.vx.lo > 0 && !sideways ? c.vx.lo : std::min(c.vx.lo, 0.0);
}
double topSpeed(const SkillDef& s) { return std::max(s.commands.vx.hi, 0.0); }
// the forward speeds both skills train at: [larger lowest, smaller top] (never empty: hi >= lo)
void speedBand(const SkillDef& from, const SkillDef& to, double* lo, double* hi) {
  *lo = std::max(lowestSpeed(from), lowestSpeed(to));
  *hi = std::max(*lo, std::min(topSpeed(from), topSpeed(to)));
}
}  // namespace

int maxSwitchWaitTicks(const SkillDef& to) {
  if (!isStillSkill(to)) return kMaxSlowWaitTicks;
  return to.settleFirst ? kMaxSettleWaitTicks : kMaxRestWaitTicks;
}

bool switchWaits(const SkillDef& from, const SkillDef& to) {
  if (isStillSkill(from)) return false;
  return isStillSkill(to) || topSpeed(from) > topSpeed(to) || lowestSpeed(from) < lowestSpeed(to);
}

SkillCommand switchBrakeTarget(const SkillDef& from, const SkillDef& to, const SkillCommand& wanted) {
  SkillCommand target;
  if (isStillSkill(to)) return target;
  target = wanted;
  double lo, hi;
  speedBand(from, to, &lo, &hi);
  target.vx = std::clamp(wanted.vx, lo, hi);
  if (target.vx != wanted.vx && target.vx != 0) target.vy = target.wz = 0;  // the keys' interlock: vx alone moves
  return target;
}

bool readyForSwitch(const SkillDef& from, const SkillDef& to, const SkillCommand& target, const SkillCommand& brake,
                    const Sensors& sensors, double drift) {
  if (isStillSkill(to))
    return commandIsZero(brake) && atRestForSwitch(sensors) && (!to.settleFirst || drift < kSettleDrift);
  const Eigen::Vector3d v = sensors.baseRotation * sensors.linearVelocity;
  Eigen::Vector2d heading = (sensors.baseRotation * Eigen::Vector3d::UnitX()).head<2>();
  if (heading.norm() < 1e-6) return false;  // pitched straight up or down: no heading to move along
  const double forward = v.head<2>().dot(heading.normalized());
  double lo, hi;
  speedBand(from, to, &lo, &hi);
  const double slowest = std::max(lo - kSlowMargin, target.vx - kTargetSlack);
  return std::abs(brake.vx - target.vx) < 1e-9 && forward >= slowest && forward <= hi + kSlowMargin;
}

double forwardPitch(const Sensors& s) {
  const Eigen::Vector3d x = s.baseRotation * Eigen::Vector3d::UnitX(), z = s.baseRotation * Eigen::Vector3d::UnitZ();
  return std::atan2(-x.z(), z.z());
}

double sideLean(const Sensors& s) {
  const Eigen::Vector3d y = s.baseRotation * Eigen::Vector3d::UnitY();
  return std::asin(std::clamp(y.z(), -1.0, 1.0));
}

FallCause fallCause(const TerminationDef& t, const Sensors& s) {
  const double maxTilt = t.maxTiltDegrees * M_PI / 180.0;
  if (s.basePosition.z() < t.minHeight) return FallCause::Low;
  if (t.maxForwardPitchDegrees < 0)
    return std::abs(s.roll) > maxTilt || std::abs(s.pitch) > maxTilt ? FallCause::Tilt : FallCause::None;
  const double pitch = forwardPitch(s);
  if (std::abs(sideLean(s)) > maxTilt) return FallCause::Side;
  if (pitch < -maxTilt) return FallCause::Back;
  if (pitch > t.maxForwardPitchDegrees * M_PI / 180.0) return FallCause::OverHead;
  return FallCause::None;
}

bool mayHandOver(const SkillDef& from, const SkillDef& to) {
  return !isGroundSkill(from) || isGroundSkill(to) || to.name == from.up;
}

bool hasStoodUp(const Sensors& sensors) {
  return sensors.basePosition.z() >= kStoodPelvisHeight && sensors.tilt < kStoodTiltDegrees * M_PI / 180.0;
}

bool isLyingFaceDown(const Sensors& s) {
  const double pitch = forwardPitch(s) * 180.0 / M_PI;
  return s.basePosition.z() < 0.35 && pitch >= 70.0 && pitch <= 110.0;
}

bool isLyingStill(const Sensors& s) {
  return isLyingFaceDown(s) && (s.baseRotation * s.linearVelocity).norm() < kRestSpeed;
}

bool isKeyPoseCycle(const SkillDef& skill) {
  return startsFromDefaultPose(skill) && skill.prior.cycleTicks > 0 && skill.prior.keyframes.size() >= 2;
}

int closingStandTick(const PriorDef& prior) {
  return prior.keyframes.size() >= 2 ? prior.keyframes[prior.keyframes.size() - 2].tick : 0;
}

bool holdsClosingStand(const SkillDef& skill, const PhaseClock& phase, bool waitsForStill) {
  return waitsForStill && isKeyPoseCycle(skill) && phase.tp >= closingStandTick(skill.prior);
}

bool cycleAllowsSwitch(const SkillDef& from, const SkillDef& destination, const PhaseClock& phase, double drift,
                       int waitedTicks) {
  if (!isKeyPoseCycle(from)) return true;
  if (phase.tp < closingStandTick(from.prior)) return false;  // the landing first, whatever comes next
  return !isStillSkill(destination) || drift < kSettleDrift || waitedTicks >= kMaxSettleWaitTicks;
}

bool postureAllowsSwitch(const SkillDef& from, const SkillDef& to, const Sensors& sensors, int waitedTicks) {
  if (isGroundSkill(from) && isGroundSkill(to) && to.parent == from.name) return isLyingStill(sensors);
  if (startsFromDefaultPose(to) && !isStandingSettled(sensors)) return false;
  if (startsFromDefaultPose(from) &&
      !(waitedTicks >= kMaxSettleWaitTicks ? restingLevel(sensors) : isStandingSettled(sensors)))
    return false;
  if (!isGroundSkill(from) || isGroundSkill(to)) return true;
  return hasStoodUp(sensors) && restingLevel(sensors);
}

double steerTowardLine(const CommandDef& commands, double gain, const SkillCommand& line, double* averaged) {
  *averaged += engine::kTickSeconds * (line.aux0 + 0.5 * line.aux1 - *averaged);
  return std::clamp(-gain * *averaged, commands.wz.lo, commands.wz.hi);
}

bool phaseAllowsSwitch(const SkillDef& from, const SkillDef& to, const PhaseClock& phase) {
  if (from.prior.kind != PriorDef::Kind::Phase || (to.switchInPhase.lo <= 0.0 && to.switchInPhase.hi >= 1.0))
    return true;
  const double fraction = double(phase.tp) / (2.0 * from.prior.halfPeriodTicks);
  return fraction >= to.switchInPhase.lo && fraction <= to.switchInPhase.hi;
}

Eigen::Vector2d groundHeading(const Sensors& s) {
  Eigen::Vector2d h = (s.baseRotation * Eigen::Vector3d::UnitZ()).head<2>();
  if (h.norm() < 0.3) h = (s.baseRotation * Eigen::Vector3d::UnitX()).head<2>();
  return h.norm() > 1e-9 ? Eigen::Vector2d(h.normalized()) : Eigen::Vector2d::UnitX();
}

void carryPhase(const PriorDef& from, const PriorDef& to, PhaseClock* phase) {
  if (to.kind == PriorDef::Kind::Keyframes) {
    phase->tp = 0;
    return;
  }
  phase->tp =
      std::min(2 * to.halfPeriodTicks, int(std::lround(double(phase->tp) * to.halfPeriodTicks / from.halfPeriodTicks)));
}

void fadePrior(const RobotModel& model, const SkillDef& from, const PhaseClock& fromPhase, const SkillDef& to,
               const PhaseClock& phase, const SkillCommand& command, double w, PdCommand* out) {
  const std::array<float, kActionSize> none{};
  PdCommand oldPrior, newPrior;
  skillPdCommand(model, from, none, fromPhase, command, &oldPrior);
  skillPdCommand(model, to, none, phase, command, &newPrior);
  for (size_t j = 0; j < size_t(kNumJoints); ++j)
    out->target[j] = std::clamp(out->target[j] + w * (oldPrior.target[j] - newPrior.target[j]), model.joints[j].lower,
                                model.joints[j].upper);
}

}  // namespace robot
