// ground_card.h — the report cards of skills entered lying down (CardKind::StandUp, PushUp, Crawl): each
// episode lies down under the parent skill's model (prone), switches to the skill the way the runtime does, and
// measures it; a stand-up then hands the robot to its `up` skill (the walk), which must keep it up. The policies
// drive in turn; all measured in physics.
#pragma once

#include "ai/eval/velocity_card.h"

namespace ai {

/// A skill that drives part of an episode other than the one being measured, with its deterministic policy.
struct DrivingSkill {
  const SkillSpec* def = nullptr;
  PolicyFn policy;
};

/// Runs a ground card: `parent` lies down for a random lie_s (no pushes; friction and mass randomised as in
/// `skill`'s training), then the switch to `skill` (its action carried over, the parent's prior fading out).
/// StandUp: the stand is timed at the first tick the robot stands (robot::hasStoodUp), and once it has also settled
/// there (robot::postureAllowsSwitch, as in play) `up` takes over with a zero command for after_s.
/// PushUp: the skill runs episode_s; a push-up counts when the torso link's origin rises at least `rise` above its
/// lowest point since the last one came down by as much (trough to crest); success = push_ups of them, no fall.
/// Crawl: once the robot lies, a tunnel (the skill's ceiling terrain, `width` wide) goes over it along its heading
/// (robot::groundHeading) from 1 m behind it, and the skill crawls at a forward command drawn from the card's vx;
/// success = the pelvis crawl_distance along the tunnel within crawl_distance / crawl_speed of the switch, never
/// beyond the tunnel's width, no fall.
/// `up` is needed only by a StandUp card. Results do not depend on the thread count.
CardResult runGroundCard(const robot::RobotModel& model, const SkillSpec& skill, const PolicyFn& policy,
                         const CardRun& run, const DrivingSkill& parent, const DrivingSkill& up);

}  // namespace ai
