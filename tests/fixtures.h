// fixtures.h — shared test fixtures: the shipped robot model and levels, loaded once per test binary.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
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

/// A gain for every joint group of a root skill named walk (a tree file needs them): 13 lines.
inline const std::string kWalkGains =
    "[skill.walk.gains]\nhip_pitch=[1,1]\nhip_roll=[1,1]\nhip_yaw=[1,1]\nknee=[1,1]\n"
    "ankle_pitch=[1,1]\nankle_roll=[1,1]\nwaist_yaw=[1,1]\nshoulder_pitch=[1,1]\n"
    "shoulder_roll=[1,1]\nshoulder_yaw=[1,1]\nelbow=[1,1]\nwrist_roll=[1,1]\n";

/// Writes `text` as t.toml in the temp folder `name` and returns its path (errors then read "t.toml:LINE: ...").
inline std::string writeTree(const std::string& name, const std::string& text) {
  const std::string dir = testing::TempDir() + "/" + name;
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/t.toml") << text;
  return dir + "/t.toml";
}

}  // namespace fixtures
