// skill_controller.h — turns a skill's policy output into PD targets: default pose + action scale x action
// + the skill's feed-forward prior (paper §3.1). Shared by training environments and the play runtime so a
// skill behaves identically in both.
#pragma once

#include <array>

#include "robot/skill_layout.h"
#include "robot/skill_tree.h"

namespace robot {

/// The gait counter tp of the phase prior (counts control ticks 1..2 T1, then wraps) and the share of the
/// stepping amplitude in use (gait, 0..1), which fades with the skill's stand ramp.
struct PhaseClock {
  int tp = 0;
  double gait = 0.0;
  /// Advances the counter one tick.
  void advance(int halfPeriodTicks) { tp = tp >= 2 * halfPeriodTicks ? 1 : tp + 1; }
  /// Advances the counter one tick and moves gait toward 1 (stepping) or 0 (a phase prior that stands still at
  /// a zero command, or a skill without a phase prior) by 1 / standRampTicks (at once when that is 0).
  void advance(const PriorDef& prior, const SkillCommand& command);
};

/// Left/right activation u1, u2 in [0, 1] of the cosine phase prior at counter tp.
void phaseActivation(int tp, int halfPeriodTicks, double* u1, double* u2);

/// sin and cos of the gait phase pi tp / T1 (one cycle = 2 T1 ticks), for the observation.
void phaseSignal(int tp, int halfPeriodTicks, double* s, double* c);

/// After a new draw into *command: *target takes the draw and, when the commands ramp, *command keeps the
/// velocities it had before the draw (`before`) so that the ramp moves them there.
void takeCommandDraw(const SkillCommand& before, bool ramp, SkillCommand* command, SkillCommand* target);

/// True when every motion command is zero (the walk's "stand still" case).
bool commandIsZero(const SkillCommand& c);

/// The action a skill applies this tick: clip the policy output to +-kActionClip, then low-pass it with the
/// skill's filter (the lab's agent smooths its 100 Hz actions the same way). `applied` holds last tick's value.
void filterAction(const SkillDef& skill, const float* policyOutput, std::array<float, kActionSize>* applied);

/// PD command for this tick: target = default + scale * clip(action) + prior; gains from the skill. A phase
/// prior with standStill steps with dh x phase.gait when the skill has a stand ramp, else with dh or 0 (zero
/// command).
void skillPdCommand(const RobotModel& model, const SkillDef& skill, const std::array<float, kActionSize>& action,
                    const PhaseClock& phase, const SkillCommand& command, PdCommand* out);

}  // namespace robot
