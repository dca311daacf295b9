// reward_terms.cpp — the term table. Angles in the orientation term are in degrees, as in the paper.
#include "ai/rewards/reward_terms.h"

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "robot/skill_controller.h"

namespace ai {
double askedFootLift(const SkillSpec& skill, double amplitude) {
  double first, late;
  robot::poseStages(skill.prior, amplitude, &first, &late);
  return kFootLiftHeight * (skill.prior.hasLate ? late : amplitude);
}

double lineTurnTarget(double headingError, double offset) {
  return std::clamp(-(kLineTurnPerRad * headingError + kLineTurnPerMetre * offset), -kLineTurnMax, kLineTurnMax);
}

namespace {

// the ground under foot i's toe and heel (robot::groundHeading) differs by more than kFootEdgeRise, or one of them
// has none: the foot is half on a step, or overhangs it
bool footAcrossEdge(const robot::Sensors& sensors, const engine::PhysicsWorld& world, int i) {
  const Eigen::Vector2d h = robot::groundHeading(sensors);
  const Eigen::Vector3d& f = sensors.footPosition[size_t(i)];
  const Eigen::Vector2d toe = f.head<2>() + kFootEdgeToe * h, heel = f.head<2>() + kFootEdgeHeel * h;
  const double fromZ = f.z() + 0.3;  // above a tread up to 0.3 m over the sole (the toe against a riser)
  const double a = world.groundHeight(toe.x(), toe.y(), fromZ), b = world.groundHeight(heel.x(), heel.y(), fromZ);
  return !(std::abs(a - b) <= kFootEdgeRise);  // also when a ray meets nothing (-inf)
}

constexpr double kDeg = 180.0 / M_PI;

double velocity(const RewardContext& c) {
  const Eigen::Vector3d& v = c.sensors->linearVelocity;
  return 1.0 - 2.0 * std::abs(v.x() - c.command->vx) - 2.0 * std::abs(v.y() - c.command->vy);
}
double yawRate(const RewardContext& c) { return 1.0 - 2.0 * std::abs(c.sensors->angularVelocity.z() - c.command->wz); }
// legged_gym-style kernels: in (0, 1], smooth, never negative, so the step's clip at 0 never hides them
double velocityExp(const RewardContext& c) {
  const Eigen::Vector3d& v = c.sensors->linearVelocity;
  const double e2 =
      (v.x() - c.command->vx) * (v.x() - c.command->vx) + (v.y() - c.command->vy) * (v.y() - c.command->vy);
  return std::exp(-e2 / 0.5);
}
double yawRateExp(const RewardContext& c) {
  const double e = c.sensors->angularVelocity.z() - c.command->wz;
  return std::exp(-e * e / 0.5);
}
double orientation(const RewardContext& c) {
  return -0.1 * std::abs(c.sensors->roll * kDeg) - 0.1 * std::abs(c.sensors->pitch * kDeg);
}
double live(const RewardContext&) { return 1.0; }
double height(const RewardContext& c) { return 2.0 * (c.sensors->basePosition.z() - 0.78); }
double actionPenalty(const RewardContext& c) {
  // the paper's J = {1, 2, 5, 7, 8, 11}: hip roll, hip yaw, ankle roll of both legs
  static const int kJ[] = {1, 2, 5, 7, 8, 11};
  double sum = 0;
  for (int j : kJ) sum += std::abs((*c.action)[size_t(j)]);
  return -0.2 * sum;
}
double actionRate(const RewardContext& c) {
  double sum = 0;
  for (size_t j = 0; j < size_t(robot::kActionSize); ++j) {
    const double d = (*c.action)[j] - (*c.previousAction)[j];
    sum += d * d;
  }
  return -sum;
}
double verticalVelocity(const RewardContext& c) { return -std::abs(c.sensors->linearVelocity.z()); }
// the right sole's height asked [m]: a two-stage pose lifts the foot in its late stage only
double askedLift(const RewardContext& c) { return askedFootLift(*c.skill, c.command->amplitude); }
// a lift asked and the right foot on the ground (the toe of a folded leg resting there, the pelvis lowered to
// it: the one-leg stand's 19 M-step policy "held" the sole 4-5 cm up with 130-170 N on the right foot) pays nothing
bool liftedFootDown(const RewardContext& c) { return askedLift(c) >= 0.005 && c.sensors->footContact[1]; }
double footLift(const RewardContext& c) {
  if (liftedFootDown(c)) return 0.0;
  const double e = (c.sensors->footHeight[1] - askedLift(c)) / 0.04;
  return std::exp(-e * e);
}
double footClear(const RewardContext& c) {
  // how far the right sole is on its way up to the lift asked (1 when no lift is asked): unlike foot_lift's bump
  // around the target it pays for every centimetre, so a policy standing on both feet feels the way up
  const double lift = askedLift(c);
  if (lift < 0.005) return 1.0;
  if (liftedFootDown(c)) return 0.0;
  return std::clamp(c.sensors->footHeight[1] / lift, 0.0, 1.0);
}
double jumpHeight(const RewardContext& c) {
  return std::min(1.5, std::max(0.0, c.sensors->basePosition.z() - kStandingPelvisHeight) / 0.10);
}
double airTime(const RewardContext& c) { return !c.sensors->footContact[0] && !c.sensors->footContact[1] ? 1.0 : 0.0; }
double ballSpeed(const RewardContext& c) {
  if (!c.ball) return 0.0;
  return std::clamp(c.ball->velocity.head<2>().dot(c.kickDirection), 0.0, 3.5) / 2.5;
}
double ballStraight(const RewardContext& c) {
  if (!c.ball) return 0.0;
  const Eigen::Vector2d v = c.ball->velocity.head<2>();
  return -std::abs(v.x() * c.kickDirection.y() - v.y() * c.kickDirection.x());
}
double heightTrack(const RewardContext& c) {
  const double e = (c.sensors->basePosition.z() - targetPelvisHeight(*c.skill, c.command->amplitude)) / 0.05;
  return std::exp(-e * e);
}

// the centre of mass sideways (across the pelvis's heading) over the point between the feet while a two-stage
// pose's first stage has not moved the weight (the one-leg stand at amplitude 0, where play stands before the
// kick); the term fades to 1 as that stage moves the weight over the left foot: where it balances there (3-5 cm
// inside the ankle) is the policy's to find
double weightCentred(const RewardContext& c) {
  const robot::Sensors& s = *c.sensors;
  double first = 0.0, late = 0.0;
  if (c.skill->prior.hasLate) robot::poseStages(c.skill->prior, c.command->amplitude, &first, &late);
  const Eigen::Vector2d middle = 0.5 * (s.footPosition[0] + s.footPosition[1]).head<2>();
  const Eigen::Vector2d across(-std::sin(s.yaw), std::cos(s.yaw));
  const double e = (s.centreOfMass.head<2>() - middle).dot(across) / 0.05;
  return 1.0 - (1.0 - first) * (1.0 - std::exp(-e * e));
}

double standStill(const RewardContext& c) {
  if (!robot::commandIsZero(*c.command)) return 0.0;
  return -c.sensors->linearVelocity.head<2>().norm();
}
double holdPosition(const RewardContext& c) {
  if (!c.anchor || !robot::commandIsZero(*c.command)) return 0.0;
  return -(c.sensors->basePosition.head<2>() - *c.anchor).norm();
}
double pronePitch(const RewardContext& c) {
  const double e = (robot::forwardPitch(*c.sensors) * kDeg - 90.0) / 25.0;
  return std::exp(-e * e);
}
double proneHeight(const RewardContext& c) {
  const double e = std::max(0.0, c.sensors->basePosition.z() - kPronePelvisHeight) / 0.15;
  return std::exp(-e * e);
}
double sideLevel(const RewardContext& c) { return -0.05 * std::abs(robot::sideLean(*c.sensors) * kDeg); }
// the stand-up: the way from lying (pelvis on the ground) up to standing, the trunk coming upright, and
// standing as the card and the runtime's hand-over to the walk count it (robot::hasStoodUp)
double standHeight(const RewardContext& c) {
  return std::clamp(
      (c.sensors->basePosition.z() - kPronePelvisHeight) / (robot::kStoodPelvisHeight - kPronePelvisHeight), 0.0, 1.0);
}
double upright(const RewardContext& c) { return std::max(0.0, std::cos(c.sensors->tilt)); }
double stood(const RewardContext& c) { return robot::hasStoodUp(*c.sensors) ? 1.0 : 0.0; }
double feetDown(const RewardContext& c) { return c.sensors->footContact[0] && c.sensors->footContact[1] ? 1.0 : 0.0; }
// a foot on the ground across a step's edge (half on the tread, or its toe against the next riser): the blind
// stairs' feet landed so and the robot sat back onto the steps (docs/skills/stairs.md)
double footEdge(const RewardContext& c) {
  if (!c.world) return 0.0;
  double n = 0.0;
  for (int i = 0; i < 2; ++i)
    if (c.sensors->footContact[size_t(i)] && footAcrossEdge(*c.sensors, *c.world, i)) n += 1.0;
  return -n;
}
double crawlVelocity(const RewardContext& c) {
  const Eigen::Vector2d h = robot::groundHeading(*c.sensors);
  const Eigen::Vector2d v = (c.sensors->baseRotation * c.sensors->linearVelocity).head<2>();
  const double forward = v.dot(h) - c.command->vx, side = v.dot(Eigen::Vector2d(-h.y(), h.x())) - c.command->vy;
  return std::exp(-(forward * forward + side * side) / 0.05);
}
// on the line the episode began on, along the way the robot faced then (a tunnel's middle)
double crawlLine(const RewardContext& c) {
  if (!c.lineStart || !c.lineHeading) return 0.0;
  const Eigen::Vector2d d = c.sensors->basePosition.head<2>() - *c.lineStart;
  const double off = d.dot(Eigen::Vector2d(-c.lineHeading->y(), c.lineHeading->x()));
  return std::exp(-off * off / 0.1);
}
double headingHold(const RewardContext& c) {
  if (!c.lineHeading) return 0.0;
  const Eigen::Vector2d h = robot::groundHeading(*c.sensors);
  const double e = std::atan2(c.lineHeading->x() * h.y() - c.lineHeading->y() * h.x(), c.lineHeading->dot(h));
  return std::exp(-e * e / 0.04);
}
// turning back toward the line, measured on the smoothed yaw rate: pays at once for a turn the heading shows later
double lineTurn(const RewardContext& c) {
  if (!c.lineStart || !c.lineHeading) return 0.0;
  robot::SkillCommand line;
  robot::lineIntoCommand(*c.sensors, *c.lineStart, *c.lineHeading, &line);
  const double e = c.yawRateSmoothed - lineTurnTarget(line.aux0, line.aux1);
  return std::exp(-e * e / 0.01);
}
double headingRate(const RewardContext& c) {
  const double e = (c.sensors->baseRotation * c.sensors->angularVelocity).z() - c.command->wz;
  return std::exp(-e * e / 0.02);
}
// the pelvis follows the prior's cycle: low at the cycle's first key, high half way (0 without a repeating prior)
double pushUpHeight(const RewardContext& c) {
  const robot::PriorDef& p = c.skill->prior;
  if (p.cycleTicks <= 0) return 0.0;
  const double u = c.phaseTick < p.cycleStartTick
                       ? 0.0
                       : double(c.phaseTick - p.cycleStartTick) / double(p.cycleTicks - p.cycleStartTick);
  const double target =
      kPushUpPelvisLow + (kPushUpPelvisHigh - kPushUpPelvisLow) * 0.5 * (1.0 - std::cos(2.0 * M_PI * u));
  const double e = (c.sensors->basePosition.z() - target) / 0.05;
  return std::exp(-e * e);
}

}  // namespace

const std::vector<RewardTerm>& rewardTermTable() {
  static const std::vector<RewardTerm> kTable = {
      {"velocity", &velocity, "1 - 2|vx - vx_cmd| - 2|vy - vy_cmd| (pelvis frame)"},
      {"yaw_rate", &yawRate, "1 - 2|wz - wz_cmd|"},
      {"velocity_exp", &velocityExp, "exp(-|v_xy - v_cmd_xy|^2 / 0.5) (pelvis frame)"},
      {"yaw_rate_exp", &yawRateExp, "exp(-(wz - wz_cmd)^2 / 0.5)"},
      {"height", &height, "2 (h - 0.78 m)"},
      {"orientation", &orientation, "-0.1|roll_deg| - 0.1|pitch_deg|"},
      {"live", &live, "1"},
      {"action_penalty", &actionPenalty, "-0.2 sum_{hip roll, hip yaw, ankle roll} |a|"},
      {"action_rate", &actionRate, "-sum_j (a_j - a_prev_j)^2"},
      {"vertical_velocity", &verticalVelocity, "-|vz|"},
      {"height_track", &heightTrack, "exp(-((h - h_target(amplitude)) / 0.05 m)^2)"},
      {"jump_height", &jumpHeight, "min(1.5, max(0, h - 0.784 m) / 0.10 m)"},
      {"air_time", &airTime, "1 while neither foot touches the ground"},
      {"ball_speed", &ballSpeed, "min(3.5, max(0, v_ball . target)) / 2.5 m/s"},
      {"ball_straight", &ballStraight, "-|v_ball x target| (sideways ball speed)"},
      {"stand_still", &standStill,
       "-|v_xy| while the command is zero (pelvis frame; stepping in place must not drift)"},
      {"hold_position", &holdPosition,
       "-|p_xy - anchor| while the command is zero (anchor: the pelvis when the zero command began or the last push "
       "came)"},
      {"prone_pitch", &pronePitch, "exp(-((pitch_forward - 90 deg) / 25 deg)^2): face down (robot::forwardPitch)"},
      {"prone_height", &proneHeight, "exp(-(max(0, h - 0.12 m) / 0.15 m)^2): the pelvis down on the ground"},
      {"side_level", &sideLevel, "-0.05 |side lean_deg| (robot::sideLean: not rolled onto a side)"},
      {"stand_height", &standHeight, "clamp((h - 0.12 m) / (0.70 m - 0.12 m), 0, 1): from lying up to standing"},
      {"upright", &upright, "max(0, cos tilt): the pelvis upright"},
      {"crawl_velocity", &crawlVelocity,
       "exp(-((v_f - vx_cmd)^2 + (v_s - vy_cmd)^2) / 0.05), world velocity along / across the way the head points "
       "(pelvis z on the ground; pelvis x when upright)"},
      {"crawl_line", &crawlLine,
       "exp(-d^2 / 0.1), d: the pelvis's offset across the line the episode began on (start and heading after the "
       "handover)"},
      {"heading_hold", &headingHold,
       "exp(-e^2 / 0.04), e: the heading's angle from the one the episode began with, turned by the commanded yaw rate "
       "since (robot::groundHeading)"},
      {"line_turn", &lineTurn,
       "exp(-(w_s - w*)^2 / 0.01), w_s: the world yaw rate low-passed over 1 s, w* = -(1 aux0 + 0.5 aux1) within +-0.2 "
       "rad/s: turning back toward the line the episode began on (aux as line_command shows it)"},
      {"heading_rate", &headingRate,
       "exp(-(wz_world - wz_cmd)^2 / 0.02): turning about the vertical, whatever the posture (0.1 rad/s: 0.61)"},
      {"pushup_height", &pushUpHeight,
       "exp(-((h - h_cycle) / 0.05 m)^2), h_cycle = 0.11 m + 0.10 m (1 - cos 2 pi u) / 2 through the repeating prior's "
       "cycle u"},
      {"feet_down", &feetDown,
       "1 while both feet touch the ground (a kick that ends standing on both feet, not stepping: the switch out of it "
       "waits for a settled stand)"},
      {"foot_edge", &footEdge,
       "-(number of feet on the ground whose toe and heel have ground under them more than 0.02 m apart: across a "
       "step's edge)"},
      {"stood", &stood, "1 while standing: pelvis >= 0.70 m and tilt < 10 deg (robot::hasStoodUp)"},
      {"foot_clear", &footClear,
       "clamp(h_right_sole / (0.12 m lift), 0, 1); 1 when no lift is asked, 0 while the right foot touches the ground "
       "(lift as for foot_lift)"},
      {"weight_centred", &weightCentred,
       "1 - (1 - w)(1 - exp(-(d / 0.05 m)^2)), d: the centre of mass's sideways offset (pelvis heading) from the "
       "feet's midpoint, w: a two-stage pose's first-stage weight (0 otherwise)"},
      {"foot_lift", &footLift,
       "exp(-((h_right_sole - 0.12 m lift) / 0.04 m)^2), lift = amplitude or a two-stage pose's late weight; 0 while "
       "the right foot touches the ground"},
  };
  return kTable;
}

std::vector<WeightedTerm> resolveRewardTerms(const SkillSpec& skill, const std::string& treePath) {
  std::vector<WeightedTerm> out;
  for (const auto& [name, weight] : skill.rewardWeights) {
    const RewardTerm* found = nullptr;
    for (const RewardTerm& t : rewardTermTable())
      if (name == t.name) found = &t;
    if (!found) {
      std::string known;
      for (const RewardTerm& t : rewardTermTable()) known += std::string(known.empty() ? "" : ", ") + t.name;
      throw engine::Error(
          engine::located(treePath, skill.rewardLines.at(name),
                          "skill." + skill.name + ": unknown reward term '" + name + "' (known: " + known + ")"));
    }
    out.push_back({found, weight});
  }
  return out;
}

}  // namespace ai
