// skill_layout.h — THE observation and action layout shared by all 11 skills (DESIGN.md §3). Every skill
// network reads kObservationSize floats in this order and writes kActionSize; ONNX metadata records it.
// Changing anything here invalidates every trained model: bump kLayoutVersion.
#pragma once

#include <array>

#include "robot/robot.h"

namespace robot {

/// Version of this layout, stored in every skill file.
constexpr int kLayoutVersion = 1;

//-------------------------------- observation ------------------------------------------------------
// index range      content                                      units
//  0 ..  2         projected gravity in the pelvis frame         unit vector
//  3 ..  5         pelvis angular velocity, pelvis frame         rad/s
//  6 ..  8         pelvis linear velocity, pelvis frame          m/s
//  9 .. 31         joint position minus default pose (23)        rad
// 32 .. 54         joint velocity (23)                           rad/s
// 55 .. 77         previous action (23)                          policy units
// 78 .. 83         commands: vx, vy, wz, amplitude, aux0, aux1   m/s, m/s, rad/s, 0..1, -, -
// 84 .. 85         phase: sin, cos of the gait phase             -
constexpr int kObsGravity = 0;
constexpr int kObsAngularVelocity = 3;
constexpr int kObsLinearVelocity = 6;
constexpr int kObsJointPosition = 9;
constexpr int kObsJointVelocity = kObsJointPosition + kNumJoints;
constexpr int kObsPreviousAction = kObsJointVelocity + kNumJoints;
constexpr int kObsCommand = kObsPreviousAction + kNumJoints;
constexpr int kNumCommandSlots = 6;
constexpr int kObsPhase = kObsCommand + kNumCommandSlots;
constexpr int kObservationSize = kObsPhase + 2;

//-------------------------------- action ----------------------------------------------------------
// one channel per joint in kJointNames order; joint target = default + actionScale[j] * clamp(a, -kActionClip,
// kActionClip) + prior[j]
constexpr int kActionSize = kNumJoints;
constexpr double kActionClip = 4.0;

using Observation = std::array<float, kObservationSize>;

/// The command slots a skill may read (unused slots stay 0).
struct SkillCommand {
  double vx = 0, vy = 0, wz = 0;  ///< m/s, m/s, rad/s
  double amplitude = 0;           ///< 0..1 (e.g. squat depth)
  double aux0 = 0, aux1 = 0;      ///< skill-specific
};

/// Puts a ball's position relative to the pelvis, in the heading frame, into command.aux0 (forward) and
/// command.aux1 (left) [m], clamped to +-5 m: how ball skills (kick) see their ball.
void ballIntoCommand(const Sensors& sensors, const Eigen::Vector3d& ball, SkillCommand* command);

/// Puts the line a skill keeps to ([commands] line_command: the crawl, a tunnel's middle) into command.aux0 and
/// command.aux1: aux0 is the ground heading's angle from the line's direction (robot::groundHeading; turned left
/// > 0, in (-pi, pi]), aux1 the pelvis's offset across the line (left > 0, clamped to +-2 m). `start` is a point of
/// the line, `along` its unit direction. Without them a policy sees only its yaw rate, so a drift it has made is
/// out of its sight (the crawl's rewards for the line and the heading paid for what it could not observe).
void lineIntoCommand(const Sensors& sensors, const Eigen::Vector2d& start, const Eigen::Vector2d& along,
                     SkillCommand* command);

/// How far ahead robot::stepIntoCommand looks [m], its sampling interval and the height change it counts as a step.
constexpr double kStepLookahead = 0.8;
constexpr double kStepSampleSpacing = 0.1;
constexpr double kStepMinRise = 0.02;

/// Puts the next step ahead ([commands] step_command: the stairs) into command.aux0 and command.aux1: aux0 is its
/// rise [m] (up > 0, clamped to +-0.3), aux1 its distance ahead of the pelvis along the ground heading [m]. The
/// ground is sampled every kStepSampleSpacing up to kStepLookahead, from the height under the pelvis; the first
/// sample that differs from it by more than kStepMinRise is a step, and its edge is found to 1/16 of the spacing
/// by halving. No step in sight: aux0 = 0, aux1 = kStepLookahead (what flat ground shows). Static geometry only
/// (engine::PhysicsWorld::groundHeight); without it a blind policy meets each riser with its toes.
///
/// lookBack ([commands] step_look_back): with no step ahead, an edge the pelvis has passed but a foot has not is
/// reported instead: the ground under the rearmost heel (robot::kSoleHeel, along the heading) differs from the
/// height under the pelvis by more than kStepMinRise. aux0 is then the step that foot has still to take (here
/// minus its ground: the last step off a staircase down reads -0.15, as the steps before it), aux1 the edge's
/// distance from the pelvis, negative (behind), found by halving as ahead. Without it the last step off a
/// staircase shows flat ground while the trailing foot is still on the last tread.
void stepIntoCommand(const Sensors& sensors, const engine::PhysicsWorld& world, bool lookBack, SkillCommand* command);

/// Fills an observation from sensors, the model's default pose, the previous action, command and phase.
void buildObservation(const Sensors& s, const RobotModel& model, const std::array<float, kActionSize>& previousAction,
                      const SkillCommand& command, double phaseSin, double phaseCos, Observation* out);

}  // namespace robot
