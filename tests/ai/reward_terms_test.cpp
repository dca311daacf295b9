// reward_terms_test.cpp — each named reward term against a hand-computed value.
#include "ai/rewards/reward_terms.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

double term(const std::string& name, const ai::RewardContext& c) {
  for (const ai::RewardTerm& t : ai::rewardTermTable())
    if (name == t.name) return t.value(c);
  ADD_FAILURE() << "no term " << name;
  return 0;
}

struct Context {
  robot::Sensors sensors;
  robot::SkillCommand command;
  std::array<float, robot::kActionSize> action{}, previous{};
  ai::SkillSpec skill;
  engine::BallState ball;
  ai::RewardContext get(bool withBall = false) {
    return {&sensors, &command, &action, &previous, &skill, withBall ? &ball : nullptr, Eigen::Vector2d(1, 0)};
  }
};

}  // namespace

TEST(RewardTerms, VelocityTermsPenaliseTheTrackingError) {
  Context c;
  c.sensors.linearVelocity = Eigen::Vector3d(0.5, 0.1, 0.0);
  c.command.vx = 0.8;  // error (-0.3, 0.1)
  EXPECT_NEAR(term("velocity", c.get()), 1 - 2 * 0.3 - 2 * 0.1, 1e-12);
  EXPECT_NEAR(term("velocity_exp", c.get()), std::exp(-(0.09 + 0.01) / 0.5), 1e-12);
  c.sensors.angularVelocity.z() = 0.4;
  c.command.wz = -0.1;
  EXPECT_NEAR(term("yaw_rate", c.get()), 1 - 2 * 0.5, 1e-12);
  EXPECT_NEAR(term("yaw_rate_exp", c.get()), std::exp(-0.25 / 0.5), 1e-12);
}

TEST(RewardTerms, HeightAndFootTermsPeakAtTheirTargets) {
  Context c;
  c.skill.commands.pelvisHeight = {0.78, 0.56};
  c.command.amplitude = 0.5;  // target 0.67 m
  c.sensors.basePosition.z() = 0.67;
  EXPECT_NEAR(term("height_track", c.get()), 1.0, 1e-12);
  c.sensors.basePosition.z() = 0.72;  // 0.05 m too high: exp(-1)
  EXPECT_NEAR(term("height_track", c.get()), std::exp(-1.0), 1e-9);
  c.command.amplitude = 1.0;
  c.sensors.footHeight = {0.0, 0.12};
  EXPECT_NEAR(term("foot_lift", c.get()), 1.0, 1e-12);
  EXPECT_NEAR(term("foot_clear", c.get()), 1.0, 1e-12);
  c.sensors.footHeight = {0.0, 0.03};  // a quarter of the way up: foot_clear pays a quarter, foot_lift almost nothing
  EXPECT_NEAR(term("foot_clear", c.get()), 0.25, 1e-12);
  EXPECT_NEAR(term("foot_lift", c.get()), std::exp(-(0.09 / 0.04) * (0.09 / 0.04)), 1e-12);
  c.sensors.footHeight = {0.0, 0.20};  // higher than asked: still 1
  EXPECT_NEAR(term("foot_clear", c.get()), 1.0, 1e-12);
  c.sensors.footHeight = {0.0, 0.12};  // at the height asked but touching the ground (a folded leg's toe): nothing
  c.sensors.footContact = {true, true};
  EXPECT_EQ(term("foot_clear", c.get()), 0.0);
  EXPECT_EQ(term("foot_lift", c.get()), 0.0);
  c.sensors.footContact = {true, false};
  EXPECT_NEAR(term("foot_lift", c.get()), 1.0, 1e-12);
  c.command.amplitude = 0.0;  // no lift asked
  c.sensors.footHeight = {0.0, 0.0};
  EXPECT_NEAR(term("foot_clear", c.get()), 1.0, 1e-12);
  c.sensors.basePosition.z() = 0.784 + 0.05;  // half-way to a counted jump
  EXPECT_NEAR(term("jump_height", c.get()), 0.5, 1e-9);
  c.sensors.footContact = {false, false};
  EXPECT_EQ(term("air_time", c.get()), 1.0);
  c.sensors.footContact = {true, false};
  EXPECT_EQ(term("air_time", c.get()), 0.0);
}

TEST(RewardTerms, BallTermsRewardSpeedAlongTheTargetOnly) {
  Context c;
  EXPECT_EQ(term("ball_speed", c.get(false)), 0.0);  // a skill without a ball
  c.ball.velocity = Eigen::Vector3d(2.0, -0.5, 0.0);
  EXPECT_NEAR(term("ball_speed", c.get(true)), 2.0 / 2.5, 1e-12);
  EXPECT_NEAR(term("ball_straight", c.get(true)), -0.5, 1e-12);
  c.ball.velocity = Eigen::Vector3d(-3.0, 0.0, 0.0);  // backwards earns nothing
  EXPECT_EQ(term("ball_speed", c.get(true)), 0.0);
}

TEST(RewardTerms, ProneTermsPeakFaceDownOnTheGround) {
  Context c;
  // standing upright at 0.78 m: pitch 0 is 90 deg from the target, (90 / 25)^2 = 12.96; the pelvis 0.66 m above
  // 0.12, (0.66 / 0.15)^2 = 19.36
  c.sensors.basePosition.z() = 0.78;
  EXPECT_NEAR(term("prone_pitch", c.get()), std::exp(-12.96), 1e-12);
  EXPECT_NEAR(term("prone_height", c.get()), std::exp(-19.36), 1e-12);
  EXPECT_NEAR(term("side_level", c.get()), 0.0, 1e-12);
  // face down (pitched 90 deg about y), pelvis at 0.12 m: both 1
  c.sensors.baseRotation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));
  c.sensors.basePosition.z() = 0.12;
  EXPECT_NEAR(term("prone_pitch", c.get()), 1.0, 1e-12);
  EXPECT_NEAR(term("prone_height", c.get()), 1.0, 1e-12);
  c.sensors.basePosition.z() = 0.05;  // lower than lying costs nothing
  EXPECT_NEAR(term("prone_height", c.get()), 1.0, 1e-12);
  // face down and rolled 20 deg onto a side (about the body's long axis): -0.05 x 20
  c.sensors.baseRotation = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()) *
                           Eigen::AngleAxisd(20 * M_PI / 180, Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(term("side_level", c.get()), -1.0, 1e-9);
}

TEST(RewardTerms, StandStillPenalisesDriftOnlyAtAZeroCommand) {
  Context c;
  c.sensors.linearVelocity = Eigen::Vector3d(0.03, -0.04, 0.2);  // 0.05 m/s across the ground; vz does not count
  EXPECT_NEAR(term("stand_still", c.get()), -0.05, 1e-12);
  c.command.vx = 0.5;  // walking: not this term's business
  EXPECT_EQ(term("stand_still", c.get()), 0.0);
}

TEST(RewardTerms, HoldPositionPenalisesTheDistanceFromTheAnchorAtAZeroCommand) {
  Context c;
  const Eigen::Vector2d anchor(1.0, 2.0);
  c.sensors.basePosition = Eigen::Vector3d(1.3, 2.4, 0.78);  // 0.3, 0.4 away: 0.5 m
  ai::RewardContext ctx = c.get();
  EXPECT_EQ(term("hold_position", ctx), 0.0);  // no anchor tracked
  ctx.anchor = &anchor;
  EXPECT_NEAR(term("hold_position", ctx), -0.5, 1e-12);
  c.command.wz = 0.5;  // turning: not held
  EXPECT_EQ(term("hold_position", ctx), 0.0);
}

TEST(RewardTerms, StandUpTermsGrowFromLyingToStanding) {
  Context c;
  c.sensors.basePosition.z() = 0.12;  // lying: the pelvis on the ground, face down
  c.sensors.tilt = M_PI / 2;
  EXPECT_NEAR(term("stand_height", c.get()), 0.0, 1e-12);
  EXPECT_NEAR(term("upright", c.get()), 0.0, 1e-12);
  EXPECT_EQ(term("stood", c.get()), 0.0);
  c.sensors.basePosition.z() = 0.41;  // half-way up (0.12 + 0.29 of the 0.58 m), the trunk at 60 deg
  c.sensors.tilt = M_PI / 3;
  EXPECT_NEAR(term("stand_height", c.get()), 0.5, 1e-12);
  EXPECT_NEAR(term("upright", c.get()), 0.5, 1e-12);
  EXPECT_EQ(term("stood", c.get()), 0.0);
  c.sensors.basePosition.z() = 0.75;  // up, but 12 deg off upright: not standing yet
  c.sensors.tilt = 12.0 * M_PI / 180.0;
  EXPECT_NEAR(term("stand_height", c.get()), 1.0, 1e-12);
  EXPECT_EQ(term("stood", c.get()), 0.0);
  c.sensors.tilt = 5.0 * M_PI / 180.0;  // standing
  EXPECT_EQ(term("stood", c.get()), 1.0);
  c.sensors.basePosition.z() = 0.69;  // 1 cm short of the stand
  EXPECT_EQ(term("stood", c.get()), 0.0);
}

TEST(RewardTerms, FeetDownPaysOnlyWithBothFeetOnTheGround) {
  Context c;
  c.sensors.footContact = {true, true};
  EXPECT_EQ(term("feet_down", c.get()), 1.0);
  c.sensors.footContact = {true, false};  // the kicking foot in the air
  EXPECT_EQ(term("feet_down", c.get()), 0.0);
  c.sensors.footContact = {false, true};
  EXPECT_EQ(term("feet_down", c.get()), 0.0);
  c.sensors.footContact = {false, false};  // in flight
  EXPECT_EQ(term("feet_down", c.get()), 0.0);
}

TEST(RewardTerms, FootEdgeCountsTheFeetOnTheGroundAcrossAStepsEdge) {
  // a 0.15 m step from x = 1.0 to 2.0; the sole's samples lie 0.12 m ahead of the foot link and 0.04 m behind it
  engine::PhysicsWorld world;
  world.addGround(1.0);
  world.addStaticBox(Eigen::Vector3d(1.5, 0, 0.075), Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.5, 1, 0.075),
                     1.0);
  Context c;
  ai::RewardContext ctx = c.get();
  c.sensors.footContact = {true, true};
  c.sensors.footPosition = {Eigen::Vector3d(0.50, 0.1, 0.035), Eigen::Vector3d(1.50, -0.1, 0.185)};  // floor, tread
  EXPECT_EQ(term("foot_edge", ctx), 0.0);  // no world: the term looks at nothing
  ctx.world = &world;
  EXPECT_EQ(term("foot_edge", ctx), 0.0);
  c.sensors.footPosition[0].x() = 0.95;  // toe (1.07) on the tread, heel (0.91) on the floor
  EXPECT_EQ(term("foot_edge", ctx), -1.0);
  c.sensors.footPosition[1].x() = 1.90;  // toe (2.02) over the edge down, heel (1.86) on the tread
  EXPECT_EQ(term("foot_edge", ctx), -2.0);
  c.sensors.footContact = {false, true};  // the left foot in the air over the edge counts for nothing
  EXPECT_EQ(term("foot_edge", ctx), -1.0);
  c.sensors.footPosition[1].x() = 1.87;  // toe at 1.99: on the tread
  EXPECT_EQ(term("foot_edge", ctx), 0.0);
  // turned round, the same foot's toe points back over the floor below the riser
  c.sensors.baseRotation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()));
  c.sensors.footPosition[1].x() = 1.08;  // toe at 0.96, heel at 1.12
  EXPECT_EQ(term("foot_edge", ctx), -1.0);
  c.sensors.footPosition[1].x() = 1.20;  // toe at 1.08
  EXPECT_EQ(term("foot_edge", ctx), 0.0);
}

TEST(RewardTerms, PushUpHeightFollowsThePriorsCycleDownAtItsStartUpHalfWay) {
  Context c;
  c.skill.prior.kind = robot::PriorDef::Kind::Keyframes;
  c.skill.prior.cycleStartTick = 60;  // a 0.6 s lead-in, then a 1.6 s cycle
  c.skill.prior.cycleTicks = 220;
  auto at = [&](int tick, double pelvis) {
    c.sensors.basePosition.z() = pelvis;
    ai::RewardContext ctx = c.get();
    ctx.phaseTick = tick;
    return term("pushup_height", ctx);
  };
  EXPECT_NEAR(at(60, 0.11), 1.0, 1e-12);              // the cycle's start: down (0.11 m)
  EXPECT_NEAR(at(140, 0.21), 1.0, 1e-12);             // half way: up (0.21 m)
  EXPECT_NEAR(at(140, 0.16), std::exp(-1.0), 1e-12);  // 0.05 m short
  EXPECT_NEAR(at(100, 0.16), 1.0, 1e-12);             // a quarter: half way up, (1 - cos(pi / 2)) / 2
  EXPECT_NEAR(at(20, 0.11), 1.0, 1e-12);              // the lead-in: down
  EXPECT_LT(at(60, 0.21), 0.02);                      // up when it should be down
  c.skill.prior.cycleTicks = 0;                       // no repeating prior: nothing to follow
  EXPECT_EQ(at(140, 0.21), 0.0);
}

TEST(RewardTerms, CrawlTermsMeasureAlongTheWayTheHeadPointsWhateverThePosture) {
  Context c;
  // face down, head toward +x: the pelvis pitched 90 deg forward (its x axis at the ground, its z axis along +x)
  c.sensors.baseRotation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));
  const Eigen::Matrix3d toBody = c.sensors.baseRotation.toRotationMatrix().transpose();
  c.command.vx = 0.3;
  c.sensors.linearVelocity = toBody * Eigen::Vector3d(0.3, 0.0, 0.0);  // crawling at the command
  EXPECT_NEAR(term("crawl_velocity", c.get()), 1.0, 1e-12);
  c.sensors.linearVelocity = toBody * Eigen::Vector3d(0.1, 0.1, 0.0);  // 0.2 m/s short, 0.1 m/s sideways
  EXPECT_NEAR(term("crawl_velocity", c.get()), std::exp(-(0.04 + 0.01) / 0.05), 1e-12);
  c.sensors.linearVelocity = toBody * Eigen::Vector3d(0.0, 0.0, 0.3);  // the pelvis frame's own x is up: no credit
  EXPECT_NEAR(term("crawl_velocity", c.get()), std::exp(-(0.09 + 0.0) / 0.05), 1e-12);
  // turning about the vertical at 0.1 rad/s, whatever the body axis that is
  c.sensors.angularVelocity = toBody * Eigen::Vector3d(0.0, 0.0, 0.1);
  EXPECT_NEAR(term("heading_rate", c.get()), std::exp(-0.5), 1e-12);
  c.sensors.angularVelocity = toBody * Eigen::Vector3d(0.5, 0.0, 0.0);  // rocking about the heading is not turning
  EXPECT_NEAR(term("heading_rate", c.get()), 1.0, 1e-12);
  // the line the episode began on: from (1, 2) along +x; the robot 3 m on and 0.3 m to the left, facing 0.2 rad left
  const Eigen::Vector2d start(1, 2), along(1, 0);
  ai::RewardContext ctx = c.get();
  EXPECT_EQ(term("crawl_line", ctx), 0.0);  // not tracked here
  ctx.lineStart = &start, ctx.lineHeading = &along;
  c.sensors.basePosition = Eigen::Vector3d(4.0, 2.3, 0.3);
  c.sensors.baseRotation =
      Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY());
  EXPECT_NEAR(term("crawl_line", ctx), std::exp(-0.09 / 0.1), 1e-12);
  EXPECT_NEAR(term("heading_hold", ctx), std::exp(-0.04 / 0.04), 1e-12);
  c.sensors.basePosition = Eigen::Vector3d(-2.0, 2.0, 0.3);  // behind the start, on the line, facing the start's way
  c.sensors.baseRotation = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY());
  EXPECT_NEAR(term("crawl_line", ctx), 1.0, 1e-12);
  EXPECT_NEAR(term("heading_hold", ctx), 1.0, 1e-12);
}

TEST(RewardTerms, LineTurnPaysForTurningBackTowardTheLine) {
  Context c;
  const Eigen::Vector2d start(0, 0), along(1, 0);
  ai::RewardContext ctx = c.get();
  EXPECT_EQ(term("line_turn", ctx), 0.0);  // no line tracked
  ctx.lineStart = &start, ctx.lineHeading = &along;
  // face down on all fours, 0.1 rad left of the line and 0.1 m left of it: the turn asked is -(0.1 + 0.05) rad/s
  c.sensors.baseRotation =
      Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY());
  c.sensors.basePosition = Eigen::Vector3d(2.0, 0.1, 0.3);
  EXPECT_NEAR(ai::lineTurnTarget(0.1, 0.1), -0.15, 1e-12);
  ctx.yawRateSmoothed = -0.15;  // turning right as asked
  EXPECT_NEAR(term("line_turn", ctx), 1.0, 1e-12);
  ctx.yawRateSmoothed = 0.0;  // holding its wrong heading
  EXPECT_NEAR(term("line_turn", ctx), std::exp(-0.0225 / 0.01), 1e-12);
  ctx.yawRateSmoothed = 0.05;  // turning further away
  EXPECT_NEAR(term("line_turn", ctx), std::exp(-0.04 / 0.01), 1e-12);
  // far off: the turn asked is capped at 0.2 rad/s
  EXPECT_DOUBLE_EQ(ai::lineTurnTarget(-0.5, -1.0), 0.2);
  EXPECT_DOUBLE_EQ(ai::lineTurnTarget(0.0, 0.0), 0.0);
}

TEST(RewardTerms, WeightCentredWantsTheCentreOfMassBetweenTheFeetUntilThePoseShiftsTheWeight) {
  Context c;
  c.skill.prior.kind = robot::PriorDef::Kind::Pose;
  c.skill.prior.hasLate = true;  // the one-leg stand: first half of the amplitude shifts the weight, second lifts
  c.sensors.yaw = M_PI / 2;      // facing +Y: sideways is -X (the robot's left)
  c.sensors.footPosition = {Eigen::Vector3d(-0.10, 0.0, 0.035), Eigen::Vector3d(0.10, 0.05, 0.035)};  // left, right
  c.sensors.centreOfMass = Eigen::Vector3d(0.0, 0.3, 0.7);  // over the midpoint sideways (0.3 m ahead does not count)
  c.command.amplitude = 0.0;
  EXPECT_NEAR(term("weight_centred", c.get()), 1.0, 1e-12);
  c.sensors.centreOfMass.x() = -0.05;  // 0.05 m to the left: exp(-1)
  EXPECT_NEAR(term("weight_centred", c.get()), std::exp(-1.0), 1e-12);
  c.command.amplitude = 0.25;  // half-way through the shift: half the shortfall
  EXPECT_NEAR(term("weight_centred", c.get()), 1.0 - 0.5 * (1.0 - std::exp(-1.0)), 1e-12);
  c.command.amplitude = 0.8;  // shift done: wherever the weight is
  EXPECT_NEAR(term("weight_centred", c.get()), 1.0, 1e-12);
  c.skill.prior.hasLate = false;  // other skills: always between the feet
  EXPECT_NEAR(term("weight_centred", c.get()), std::exp(-1.0), 1e-12);
}
