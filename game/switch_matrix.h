// switch_matrix.h — `treelearn eval switches`: every allowed switch (each tree edge, both directions) tried at
// random moments and commands through the real runtime (a Session on a level driven by key events), with its
// success rate and how much the switch disturbs the motion.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "levels/level.h"
#include "robot/skill_runtime.h"

namespace game {

/// One trial of a switch.
struct SwitchTrial {
  bool switched = false, upright = false;
  double accelAround = 0, accelBefore = 0;    ///< peak |d v_CoM / dt| [m/s^2] around the switch / 1 s earlier
  double targetAround = 0, targetBefore = 0;  ///< peak per-tick joint-target change [rad]
  double latencyTicks = -1;                   ///< key tick -> tick the new skill first acts
  char keyBefore = 0, keyAfter = 0;           ///< the movement keys held before and after the switch (0: none)
  int64_t switchTick = 0, fallTick = -1;      ///< the switch key's tick; the tick the robot was down (-1: never)
  std::string fallSkill;                      ///< the skill driving when it fell, and how it lay
  double fallHeight = 0, fallPitchDeg = 0, fallLeanDeg = 0;
};

constexpr double kSwitchWindowSeconds = 0.2;  ///< the window around the switch (and the earlier reference window)
constexpr double kSwitchAfterSeconds = 3.0;   ///< no fall for this long after the switch
constexpr double kSwitchMaxWaitSeconds =
    6.0;  ///< a switch may wait this long after its key (a stand-up: until it stands)

/// One trial of from -> to: from's key (a skill entered lying: its parent's first), a random movement key, then at a
/// random moment to's key with another random movement key; measured until kSwitchAfterSeconds after the switch.
SwitchTrial runSwitchTrial(const levels::Level& level, const robot::RobotModel& model, const robot::SkillSet& skills,
                           const robot::Skill& from, const robot::Skill& to, uint64_t seed);

/// The switches the matrix tries: each edge down the tree (parent -> child) and each way up (child -> its parent, or
/// -> its `up` skill), for the skills with models. `untried` gets a line for each way up it cannot try.
std::vector<std::pair<const robot::Skill*, const robot::Skill*>> switchPairs(const robot::SkillSet& skills,
                                                                             std::vector<std::string>* untried);

struct SwitchMatrixOptions {
  int trials = 10;  ///< per ordered pair
  uint64_t seed = 1;
  int threads = 2;
  std::string only;                ///< only the switches into or out of this skill (each trial as in the full run)
  std::vector<std::string> anyOf;  ///< if given, only the switches into or out of one of these skills
};

/// One row of the matrix: a switch and its trials.
struct SwitchRow {
  const robot::Skill* from = nullptr;
  const robot::Skill* to = nullptr;
  std::vector<SwitchTrial> trials;
  /// trials that switched within kSwitchMaxWaitSeconds and stayed up [%]
  double successPercent() const;
};

struct SwitchMatrix {
  size_t allowed = 0;  ///< every allowed switch (rows holds those selected by `only`)
  std::vector<SwitchRow> rows;
  std::vector<std::string> untried;
};

/// Runs the matrix on `level` (each pair's trials keep their seeds whatever `only` selects). Errors: no two connected
/// skills with models; `only` naming no loaded skill, or one without a switch.
SwitchMatrix runSwitchMatrix(const levels::Level& level, const robot::RobotModel& model, const robot::SkillSet& skills,
                             const SwitchMatrixOptions& options);

}  // namespace game
