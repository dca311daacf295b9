// reward_terms.h — the reward as a table of named terms (paper Table 1 plus preference terms). A skill's
// entry in the tree file picks terms by name and weights them; unknown names fail at load with file:line.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "ai/tree/training_tree.h"
#include "engine/physics/physics_world.h"
#include "robot/skill_layout.h"

namespace ai {

/// Everything a reward term may look at after a control tick.
struct RewardContext {
  const robot::Sensors* sensors = nullptr;
  const robot::SkillCommand* command = nullptr;
  const std::array<float, robot::kActionSize>* action = nullptr;          ///< clipped policy output this tick
  const std::array<float, robot::kActionSize>* previousAction = nullptr;  ///< the tick before
  const SkillSpec* skill = nullptr;                                       ///< the skill being trained
  const engine::BallState* ball = nullptr;                                ///< the kick's ball, if the skill has one
  Eigen::Vector2d kickDirection = Eigen::Vector2d::UnitX();  ///< where the ball should go (world unit vector)
  /// where the pelvis was (world x, y) when the current zero command began or the last push ended; nullptr while
  /// the command is not zero or the environment does not track it
  const Eigen::Vector2d* anchor = nullptr;
  int phaseTick = 0;  ///< the skill's prior clock (robot::PhaseClock::tp) this tick
  /// crawl_line, heading_hold: where the episode's motion began (world x, y: the pelvis after the handover) and
  /// the way the robot faced then (robot::groundHeading); nullptr where the environment does not track them
  const Eigen::Vector2d* lineStart = nullptr;
  const Eigen::Vector2d* lineHeading = nullptr;
  /// line_turn: the world yaw rate low-passed over kLineTurnSeconds [rad/s] (a crawl's rock swings the raw rate)
  double yawRateSmoothed = 0;
  /// foot_edge: the world the feet stand in (its static geometry is read with ray casts); nullptr: no term looks
  const engine::PhysicsWorld* world = nullptr;
};

/// line_turn: the yaw rate's low-pass time constant [s], the turn asked per rad of heading error and per metre off
/// the line [rad/s], and the most it asks [rad/s]
constexpr double kLineTurnSeconds = 1.0;
constexpr double kLineTurnPerRad = 1.0;
constexpr double kLineTurnPerMetre = 0.5;
constexpr double kLineTurnMax = 0.2;
/// The turn toward the line line_turn asks for: -(kLineTurnPerRad aux0 + kLineTurnPerMetre aux1), within
/// +-kLineTurnMax (aux0, aux1 as robot::lineIntoCommand gives them)
double lineTurnTarget(double headingError, double offset);

/// The pelvis height of the G1 standing in its default pose (reference/g1/FACTS.md) [m].
constexpr double kStandingPelvisHeight = 0.784;

/// prone_height: the pelvis height of the G1 lying face down with its arms overhead (measured with the prone
/// prior alone: 0.119-0.124 m) [m].
constexpr double kPronePelvisHeight = 0.12;

/// foot_lift: the right sole's target height at amplitude 1 [m] (one_leg stands on the left leg).
constexpr double kFootLiftHeight = 0.12;
/// The right sole's height asked of a skill at an amplitude command [m]: kFootLiftHeight x the amplitude, or x a
/// two-stage pose's late weight (the one-leg stand lifts the foot in its late stage only).
double askedFootLift(const SkillSpec& skill, double amplitude);

/// pushup_height: the pelvis at the bottom and at the top of a push-up (measured with the pushup prior alone
/// from the prone pose: 0.10-0.12 m and 0.19-0.23 m) [m].
constexpr double kPushUpPelvisLow = 0.11;
constexpr double kPushUpPelvisHigh = 0.21;

/// The pelvis height a skill is asked for at an amplitude command (its commands.pelvis_height, linear).
inline double targetPelvisHeight(const SkillSpec& skill, double amplitude) {
  const robot::Range& h = skill.commands.pelvisHeight;
  return h.lo + amplitude * (h.hi - h.lo);
}

/// foot_edge: where along the foot the ground under it is sampled, from the foot link's origin along the heading
/// [m]: 1 cm in from the sole's toe and its heel (robot::kSoleToe, robot::kSoleHeel); a difference of more than
/// kFootEdgeRise between them is a foot standing across an edge
constexpr double kFootEdgeToe = robot::kSoleToe;
constexpr double kFootEdgeHeel = robot::kSoleHeel;
constexpr double kFootEdgeRise = 0.02;

/// A named term: value(context), unweighted.
struct RewardTerm {
  const char* name;
  double (*value)(const RewardContext&);
  const char* formula;  ///< for documentation and logs
};

/// Every term the tree file may use.
const std::vector<RewardTerm>& rewardTermTable();

/// A skill's terms with their weights (by name, alphabetical).
struct WeightedTerm {
  const RewardTerm* term;
  double weight;
};

/// Resolves the skill's reward names against the table; throws engine::Error "tree.toml:line: unknown reward term".
std::vector<WeightedTerm> resolveRewardTerms(const SkillSpec& skill, const std::string& treePath);

}  // namespace ai
