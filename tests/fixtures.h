// fixtures.h — shared test fixtures: the shipped robot model and levels, loaded once per test binary.
#pragma once

#include <string>

#include "levels/level.h"
#include "robot/robot_model.h"

namespace fixtures {

inline const std::string kSource = TREELEARN_SOURCE_DIR;

/// The shipped G1 (assets/robots/g1_23dof.toml).
inline const robot::RobotModel& robotModel() {
  static const robot::RobotModel m = robot::loadRobotModel(kSource + "/assets/robots/g1_23dof.toml");
  return m;
}

}  // namespace fixtures
