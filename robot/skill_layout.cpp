// skill_layout.cpp — writes the shared observation layout.
#include "robot/skill_layout.h"

#include <algorithm>
#include <cmath>

#include "robot/skill_controller.h"

namespace robot {

void buildObservation(const Sensors& s, const RobotModel& model, const std::array<float, kActionSize>& previousAction,
                      const SkillCommand& c, double phaseSin, double phaseCos, Observation* out) {
  Observation& o = *out;
  for (int i = 0; i < 3; ++i) {
    o[size_t(kObsGravity + i)] = float(s.projectedGravity[i]);
    o[size_t(kObsAngularVelocity + i)] = float(s.angularVelocity[i]);
    o[size_t(kObsLinearVelocity + i)] = float(s.linearVelocity[i]);
  }
  for (size_t j = 0; j < size_t(kNumJoints); ++j) {
    o[size_t(kObsJointPosition) + j] = float(s.q[j] - model.joints[j].defaultPosition);
    o[size_t(kObsJointVelocity) + j] = float(s.qd[j]);
    o[size_t(kObsPreviousAction) + j] = previousAction[j];
  }
  const double command[kNumCommandSlots] = {c.vx, c.vy, c.wz, c.amplitude, c.aux0, c.aux1};
  for (int i = 0; i < kNumCommandSlots; ++i) o[size_t(kObsCommand + i)] = float(command[i]);
  o[size_t(kObsPhase)] = float(phaseSin);
  o[size_t(kObsPhase + 1)] = float(phaseCos);
}

void ballIntoCommand(const Sensors& sensors, const Eigen::Vector3d& ball, SkillCommand* command) {
  const Eigen::Vector2d d = ball.head<2>() - sensors.basePosition.head<2>();
  const double c = std::cos(sensors.yaw), s = std::sin(sensors.yaw);
  command->aux0 = std::clamp(c * d.x() + s * d.y(), -5.0, 5.0);
  command->aux1 = std::clamp(-s * d.x() + c * d.y(), -5.0, 5.0);
}

void lineIntoCommand(const Sensors& sensors, const Eigen::Vector2d& start, const Eigen::Vector2d& along,
                     SkillCommand* command) {
  const Eigen::Vector2d h = groundHeading(sensors);
  const Eigen::Vector2d d = sensors.basePosition.head<2>() - start;
  command->aux0 = std::atan2(along.x() * h.y() - along.y() * h.x(), along.dot(h));
  command->aux1 = std::clamp(along.x() * d.y() - along.y() * d.x(), -2.0, 2.0);
}

void stepIntoCommand(const Sensors& sensors, const engine::PhysicsWorld& world, bool lookBack, SkillCommand* command) {
  const Eigen::Vector2d h = groundHeading(sensors);
  const Eigen::Vector2d p = sensors.basePosition.head<2>();
  const double top = sensors.basePosition.z();
  auto heightAt = [&](double d) {
    const Eigen::Vector2d q = p + d * h;
    return world.groundHeight(q.x(), q.y(), top);
  };
  const double here = heightAt(0.0);
  auto isStep = [&](double height) { return !(std::abs(height - here) <= kStepMinRise); };
  command->aux0 = 0.0;
  command->aux1 = kStepLookahead;
  auto edgeBetween = [&](double near, double far) {  // the edge lies in (near, far] (or [far, near) behind)
    for (int i = 0; i < 4; ++i) {
      const double mid = 0.5 * (near + far);
      (isStep(heightAt(mid)) ? far : near) = mid;
    }
    return 0.5 * (near + far);
  };
  const int samples = int(std::lround(kStepLookahead / kStepSampleSpacing));
  for (int k = 1; k <= samples; ++k) {
    const double far = k * kStepSampleSpacing;
    const double height = heightAt(far);
    if (!isStep(height)) continue;
    const double rise = std::isfinite(height) && std::isfinite(here) ? height - here : -0.3;
    command->aux0 = std::clamp(rise, -0.3, 0.3);
    command->aux1 = edgeBetween(far - kStepSampleSpacing, far);
    return;
  }
  if (!lookBack) return;
  double heel = 0.0;  // the rearmost heel's distance along the heading, <= 0
  for (const Eigen::Vector3d& f : sensors.footPosition) heel = std::min(heel, h.dot(f.head<2>() - p) + kSoleHeel);
  const double behind = heightAt(heel);
  if (heel < 0.0 && std::isfinite(behind) && std::isfinite(here) && isStep(behind)) {
    command->aux0 = std::clamp(here - behind, -0.3, 0.3);
    command->aux1 = edgeBetween(0.0, heel);
  }
}

}  // namespace robot
