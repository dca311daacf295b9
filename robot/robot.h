// robot.h — one G1 inside a PhysicsWorld: PD actuation to joint targets (every physics substep, torque
// clamped to the joint's effort limit) and the sensors every controller and skill reads.
// The robot does not own the world; the game loop steps it.
#pragma once

#include <Eigen/Geometry>
#include <array>

#include "engine/physics/physics_world.h"
#include "robot/robot_model.h"

namespace robot {

using JointArray = std::array<double, kNumJoints>;

/// PD command: tau = kp (target - q) - kd qd, clamped to +-effort.
struct PdCommand {
  JointArray target{};  ///< [rad]
  JointArray kp{};      ///< [N m/rad]
  JointArray kd{};      ///< [N m s/rad]
};

/// What the robot senses after a control tick. Body frame = pelvis link frame.
struct Sensors {
  Eigen::Vector3d basePosition = Eigen::Vector3d::Zero();            ///< pelvis origin, world [m]
  Eigen::Quaterniond baseRotation = Eigen::Quaterniond::Identity();  ///< pelvis -> world
  double roll = 0, pitch = 0, yaw = 0;                               ///< ZYX Euler angles of the pelvis [rad]
  Eigen::Vector3d projectedGravity = Eigen::Vector3d(0, 0, -1);      ///< unit gravity in the body frame
  Eigen::Vector3d linearVelocity = Eigen::Vector3d::Zero();          ///< body frame [m/s]
  Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();         ///< body frame [rad/s]
  JointArray q{};                                                    ///< joint positions [rad]
  JointArray qd{};                                                   ///< joint velocities [rad/s]
  std::array<bool, 2> footContact{};                                 ///< left, right
  std::array<double, 2> footForce{};                                 ///< contact normal force, left, right [N]
  std::array<double, 2> footHeight{};  ///< sole height above z = 0, left, right [m]: foot-link origin - kSoleDepth
  std::array<Eigen::Vector3d, 2> footPosition{Eigen::Vector3d::Zero(),
                                              Eigen::Vector3d::Zero()};  ///< foot-link origins (ankle roll), world [m]
  Eigen::Vector3d centreOfMass = Eigen::Vector3d::Zero();                ///< world [m]
  double tilt = 0;                                                       ///< angle between pelvis Z and world Z [rad]
};

/// The midpoint between the shoulder joints in the torso link's frame (reference/g1/FACTS.md: the shoulder-pitch
/// joints at (0.004, +-0.100, 0.248)) [m]: the chest's height in a push-up.
inline const Eigen::Vector3d kChestInTorso(0.004, 0.0, 0.248);

/// The sole is this far below the ankle-roll (foot) link origin (reference/g1/FACTS.md: 0.035 m).
constexpr double kSoleDepth = 0.035;

/// Points 1 cm in from the sole's toe and heel, from the foot link's origin along the foot [m]: the sole's box
/// (assets/robots/g1_23dof.urdf) is 0.18 m long and centred 0.04 m ahead of the ankle.
constexpr double kSoleToe = 0.12;
constexpr double kSoleHeel = -0.04;

class Robot {
 public:
  /// Adds the robot to the world with the pelvis at (x, y, spawn height) facing yaw, joints at the default pose.
  Robot(const RobotModel& model, engine::PhysicsWorld& world, double x, double y, double yaw, double friction = 1.0);

  /// The command applied by applyPd() from now on.
  void setCommand(const PdCommand& command) { command_ = command; }
  const PdCommand& command() const { return command_; }

  /// Computes PD torques from the current joint state and hands them to the world for the next substep.
  void applyPd(engine::PhysicsWorld& world);

  /// Reads all sensors from the world.
  Sensors sense(const engine::PhysicsWorld& world) const;

  /// World pose of link i's frame (-1 = pelvis).
  Eigen::Isometry3d linkPose(const engine::PhysicsWorld& world, int link) const { return world.linkPose(id_, link); }

  /// Sets joint positions (zero velocity) and the base pose; used for resets.
  void teleport(engine::PhysicsWorld& world, const Eigen::Isometry3d& base, const JointArray& q);

  const RobotModel& model() const { return model_; }
  engine::ArticulationId id() const { return id_; }

  /// Torques applied in the last substep [N m].
  const JointArray& lastTorques() const { return torque_; }

  /// The standing controller: PD to the default pose with the model's standing gains.
  static PdCommand standingCommand(const RobotModel& model);

 private:
  const RobotModel& model_;
  engine::ArticulationId id_ = -1;
  PdCommand command_;
  JointArray torque_{};
  mutable engine::ArticulationState scratch_;
};

/// A foot counts as in contact above this normal force [N].
constexpr double kFootContactThreshold = 5.0;

}  // namespace robot
