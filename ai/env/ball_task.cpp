// ball_task.cpp — see ball_task.h.
#include "ai/env/ball_task.h"

#include <algorithm>
#include <cmath>

namespace ai {

engine::BallId placeBall(engine::PhysicsWorld& world, const BallTaskDef& task, const robot::Sensors& start,
                         std::mt19937_64& rng, Eigen::Vector2d* targetDirection) {
  auto jitter = [&] { return task.jitter * (2.0 * (double(rng() >> 11) * (1.0 / 9007199254740992.0)) - 1.0); };
  const double c = std::cos(start.yaw), s = std::sin(start.yaw);
  const double x = task.x + jitter(), y = task.y + jitter();
  const engine::BallDef def;
  const Eigen::Vector3d centre(start.basePosition.x() + c * x - s * y, start.basePosition.y() + s * x + c * y,
                               def.radius);
  *targetDirection = Eigen::Vector2d(c, s);
  return world.addBall(def, centre);
}

}  // namespace ai
