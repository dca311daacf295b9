// standup_card.h — the report card of a stand-up skill (CardDef::Kind::StandUp): each episode lies down under the
// parent skill's model, switches to the stand-up the way the runtime does, and once the robot stands hands it to
// the `up` skill (the walk), which must keep it up. Three policies drive in turn; all measured in physics.
#pragma once

#include "ai/eval/velocity_card.h"

namespace ai {

/// A skill that drives part of an episode other than the one being measured, with its deterministic policy.
struct DrivingSkill {
  const robot::SkillDef* def = nullptr;
  PolicyFn policy;
};

/// Runs a standup card: `parent` lies down for a random lie_s (no pushes; friction and mass randomised as in
/// `skill`'s training), the switch to `skill` (its action carried over, the parent's prior fading out); the stand is
/// timed at the first tick the robot stands (robot::hasStoodUp), and once it has also settled there
/// (robot::postureAllowsSwitch, as in play) `up` takes over with a zero command for after_s. Results do not depend
/// on the thread count.
CardResult runStandUpCard(const robot::RobotModel& model, const robot::SkillDef& skill, const PolicyFn& policy,
                          const CardRun& run, const DrivingSkill& parent, const DrivingSkill& up);

}  // namespace ai
