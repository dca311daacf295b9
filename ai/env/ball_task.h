// ball_task.h — the kick's ball: placed in front of the robot at an episode start (training and card alike),
// and seen by the policy through the command's aux slots (ball position relative to the pelvis, heading frame).
#pragma once

#include <random>

#include "ai/tree/training_tree.h"
#include "engine/physics/physics_world.h"
#include "robot/robot.h"
#include "robot/skill_layout.h"

namespace ai {

/// Adds the ball at the skill's offset from the pelvis (heading frame) plus jitter; returns its id and the
/// target direction (the robot's heading at the start, a world unit vector in the ground plane).
engine::BallId placeBall(engine::PhysicsWorld& world, const BallTaskDef& task, const robot::Sensors& start,
                         std::mt19937_64& rng, Eigen::Vector2d* targetDirection);

/// robot::ballIntoCommand for a ball state.
inline void ballIntoCommand(const robot::Sensors& sensors, const engine::BallState& ball,
                            robot::SkillCommand* command) {
  robot::ballIntoCommand(sensors, ball.position, command);
}

}  // namespace ai
