// robot.cpp — PD actuation and sensing for the G1.
#include "robot/robot.h"

#include <algorithm>
#include <cmath>

namespace robot {

Robot::Robot(const RobotModel& model, engine::PhysicsWorld& world, double x, double y, double yaw, double friction)
    : model_(model) {
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.translation() = Eigen::Vector3d(x, y, model.spawnHeight + 0.001);  // 1 mm gap: no initial penetration
  base.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  id_ = world.addArticulation(model.articulation, base, friction);
  command_ = standingCommand(model);
  teleport(world, base, command_.target);
}

PdCommand Robot::standingCommand(const RobotModel& model) {
  PdCommand c;
  for (size_t j = 0; j < kNumJoints; ++j) {
    c.target[j] = model.joints[j].defaultPosition;
    c.kp[j] = model.joints[j].standKp;
    c.kd[j] = model.joints[j].standKd;
  }
  return c;
}

void Robot::teleport(engine::PhysicsWorld& world, const Eigen::Isometry3d& base, const JointArray& q) {
  engine::ArticulationState s;
  s.basePosition = base.translation();
  s.baseRotation = Eigen::Quaterniond(base.rotation());
  s.q.assign(q.begin(), q.end());
  s.qd.assign(kNumJoints, 0.0);
  world.setState(id_, s);
}

void Robot::applyPd(engine::PhysicsWorld& world) {
  world.readState(id_, &scratch_);
  for (size_t j = 0; j < kNumJoints; ++j) {
    const double tau = command_.kp[j] * (command_.target[j] - scratch_.q[j]) - command_.kd[j] * scratch_.qd[j];
    const double limit = model_.joints[j].effort;
    torque_[j] = std::clamp(tau, -limit, limit);
  }
  world.setJointTorques(id_, torque_.data());
}

Sensors Robot::sense(const engine::PhysicsWorld& world) const {
  world.readState(id_, &scratch_);
  Sensors s;
  s.basePosition = scratch_.basePosition;
  s.baseRotation = scratch_.baseRotation;
  const Eigen::Matrix3d r = scratch_.baseRotation.toRotationMatrix();
  s.yaw = std::atan2(r(1, 0), r(0, 0));
  s.pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  s.roll = std::atan2(r(2, 1), r(2, 2));
  s.projectedGravity = r.transpose() * Eigen::Vector3d(0, 0, -1);
  s.linearVelocity = r.transpose() * scratch_.baseLinearVelocity;
  s.angularVelocity = r.transpose() * scratch_.baseAngularVelocity;
  for (size_t j = 0; j < kNumJoints; ++j) {
    s.q[j] = scratch_.q[j];
    s.qd[j] = scratch_.qd[j];
  }
  s.footForce = {world.contactNormalForce(id_, model_.leftFoot), world.contactNormalForce(id_, model_.rightFoot)};
  s.footContact = {s.footForce[0] > kFootContactThreshold, s.footForce[1] > kFootContactThreshold};
  s.footPosition = {world.linkPose(id_, model_.leftFoot).translation(),
                    world.linkPose(id_, model_.rightFoot).translation()};
  s.footHeight = {s.footPosition[0].z() - kSoleDepth, s.footPosition[1].z() - kSoleDepth};
  s.centreOfMass = world.centreOfMass(id_);
  s.tilt = std::acos(std::clamp(r(2, 2), -1.0, 1.0));
  return s;
}

}  // namespace robot
