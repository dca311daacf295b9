// robot_model.h — the G1 as data: joints by name in the shared 23-joint order, the articulation built
// from our URDF (urdfdom + the <armature> extension), and actuation settings from the robot TOML file.
// Loaded once; const afterwards. Errors name the file and line.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/physics/articulation.h"

namespace robot {

/// Number of actuated joints of the 23-DoF G1.
constexpr int kNumJoints = 23;
/// The legs come first in the joint order: joints 0-5 the left leg, 6-11 the right (hip pitch to ankle roll).
constexpr int kNumLegJoints = 12;

/// The shared joint order (DESIGN.md §3): left leg, right leg, waist, left arm, right arm.
extern const std::array<const char*, kNumJoints> kJointNames;

/// Per-joint actuation data.
struct JointInfo {
  std::string name;
  double lower = 0, upper = 0;  ///< limits [rad]
  double effort = 0;            ///< torque limit [N m]
  double velocity = 0;          ///< speed limit [rad/s] (from the URDF; reported, not enforced)
  double armature = 0;          ///< rotor inertia [kg m^2]
  double defaultPosition = 0;   ///< default (standing) pose [rad]
  double standKp = 0;           ///< standing controller stiffness [N m/rad]
  double standKd = 0;           ///< standing controller damping [N m s/rad]
};

/// The loaded robot.
struct RobotModel {
  std::string urdfPath, configPath;
  engine::ArticulationDef articulation;  ///< links[i] is driven by joint i (kJointNames order)
  std::vector<JointInfo> joints;         ///< kNumJoints entries
  int leftFoot = -1, rightFoot = -1;     ///< link indices of the ankle-roll (foot) links
  int torso = -1;                        ///< link index of the torso
  double totalMass = 0;                  ///< [kg]
  double spawnHeight = 0;                ///< pelvis height with feet on z = 0 in the default pose [m]
  uint64_t hash = 0;                     ///< content hash of the URDF and the config file
};

/// Loads the robot config TOML (which names its URDF, relative to itself). Throws engine::Error.
RobotModel loadRobotModel(const std::string& configPath);

/// Parses a URDF text into an articulation with the 23 G1 joints (joints[] limits, effort, armature filled).
/// fileName is used in error messages. Throws engine::Error "file:line: ...".
void parseG1Urdf(const std::string& text, const std::string& fileName, RobotModel* model);

/// Default location of the robot config, relative to the source tree.
std::string defaultRobotConfigPath();

}  // namespace robot
