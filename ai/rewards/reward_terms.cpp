// reward_terms.cpp — the term table. Angles in the orientation term are in degrees, as in the paper.
#include "ai/rewards/reward_terms.h"

#include <cmath>

#include "engine/core/error.h"

namespace ai {
namespace {

constexpr double kDeg = 180.0 / M_PI;

double velocity(const RewardContext& c) {
  const Eigen::Vector3d& v = c.sensors->linearVelocity;
  return 1.0 - 2.0 * std::abs(v.x() - c.command->vx) - 2.0 * std::abs(v.y() - c.command->vy);
}
double yawRate(const RewardContext& c) { return 1.0 - 2.0 * std::abs(c.sensors->angularVelocity.z() - c.command->wz); }
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
double footLift(const RewardContext& c) {
  const double e = (c.sensors->footHeight[1] - kFootLiftHeight * c.command->amplitude) / 0.04;
  return std::exp(-e * e);
}
double heightTrack(const RewardContext& c) {
  const double e = (c.sensors->basePosition.z() - targetPelvisHeight(*c.skill, c.command->amplitude)) / 0.05;
  return std::exp(-e * e);
}

}  // namespace

const std::vector<RewardTerm>& rewardTermTable() {
  static const std::vector<RewardTerm> kTable = {
      {"velocity", &velocity, "1 - 2|vx - vx_cmd| - 2|vy - vy_cmd| (pelvis frame)"},
      {"yaw_rate", &yawRate, "1 - 2|wz - wz_cmd|"},
      {"height", &height, "2 (h - 0.78 m)"},
      {"orientation", &orientation, "-0.1|roll_deg| - 0.1|pitch_deg|"},
      {"live", &live, "1"},
      {"action_penalty", &actionPenalty, "-0.2 sum_{hip roll, hip yaw, ankle roll} |a|"},
      {"action_rate", &actionRate, "-sum_j (a_j - a_prev_j)^2"},
      {"vertical_velocity", &verticalVelocity, "-|vz|"},
      {"height_track", &heightTrack, "exp(-((h - h_target(amplitude)) / 0.05 m)^2)"},
      {"foot_lift", &footLift, "exp(-((h_right_sole - 0.12 m amplitude) / 0.04 m)^2)"},
  };
  return kTable;
}

std::vector<WeightedTerm> resolveRewardTerms(const robot::SkillDef& skill, const std::string& treePath) {
  std::vector<WeightedTerm> out;
  for (const auto& [name, weight] : skill.rewardWeights) {
    const RewardTerm* found = nullptr;
    for (const RewardTerm& t : rewardTermTable())
      if (name == t.name) found = &t;
    if (!found) {
      std::string known;
      for (const RewardTerm& t : rewardTermTable()) known += std::string(known.empty() ? "" : ", ") + t.name;
      throw engine::Error(engine::located(treePath, skill.rewardLines.at(name),
                                          "skill." + skill.name + ": unknown reward term '" + name + "' (known: " + known + ")"));
    }
    out.push_back({found, weight});
  }
  return out;
}

}  // namespace ai
