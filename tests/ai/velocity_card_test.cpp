// velocity_card_test.cpp — a card with a lead-in (CardDef::leadIn): each episode is entered as play enters the
// skill, with the drivers' policies first, as in the skill's training handover episodes.
#include "ai/eval/velocity_card.h"

#include <gtest/gtest.h>

#include <atomic>

#include "ai/onnx/policy_onnx.h"
#include "tests/fixtures.h"

TEST(VelocityCard, ALeadInCardRunsTheDriverBeforeEachEpisode) {
  // the squat's height card, entered after the walk (no gait, zero output: it stands) drove 0.5 s and the robot
  // came to rest: the walk's policy runs at least 0.5 s in each of the 2 episodes and none of the lead-ins falls;
  // without the lead-in the walk's policy never runs and no lead-in figure is reported
  const ai::TrainingTree tree =
      ai::loadTrainingTree(fixtures::kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  ai::SkillSpec walk = *tree.find("walk");
  walk.prior.kind = robot::PriorDef::Kind::None;
  ai::SkillSpec squat = *tree.find("squat");
  squat.handoverSeconds = {0.5, 0.5};
  ai::CardRun run{squat.card, 3, 1};
  run.card.episodes = 2;
  run.card.driven()->leadIn = true;
  std::atomic<int> calls{0};
  const ai::PolicyFn zero = [](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) {
    act->setZero(robot::kActionSize, obs.cols());
  };
  const std::vector<ai::HandoverStage> leadIn{{&walk, [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) {
                                                 ++calls;
                                                 act->setZero(robot::kActionSize, obs.cols());
                                               }}};
  const ai::CardResult with = ai::runVelocityCard(fixtures::robotModel(), squat, zero, run, leadIn);
  EXPECT_GE(calls.load(), 2 * 50);
  double leadInFalls = -1;
  for (const ai::CardFigure& f : with.figures)
    if (f.name.rfind("lead-ins that fell", 0) == 0) leadInFalls = f.value;
  EXPECT_EQ(leadInFalls, 0.0);
  calls = 0;
  const ai::CardResult without = ai::runVelocityCard(fixtures::robotModel(), squat, zero, run);
  EXPECT_EQ(calls.load(), 0);
  for (const ai::CardFigure& f : without.figures) EXPECT_EQ(f.name.find("lead-in"), std::string::npos) << f.name;
}

TEST(VelocityCard, AStairsCardSaysWhereEachFallHappened) {
  // a tilt limit of 0.01 deg makes every episode a fall within its first ticks, where it stands (x = 0): in front
  // of a staircase that starts 1 m ahead, that is before the stairs; with the staircase 10 m behind (its end at
  // -10 + 9 x 0.3 + 1 + 9 x 0.3 = -3.6 m) it is beyond them
  const ai::TrainingTree tree =
      ai::loadTrainingTree(fixtures::kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  ai::SkillSpec stairs = *tree.find("stairs");
  stairs.termination.maxTiltDegrees = 0.01;
  stairs.terrain.topDepth = 1.0;
  stairs.terrain.steps = 10, stairs.terrain.stepDepth = 0.30;
  ai::CardRun run{stairs.card, 1, 1};
  run.card.as<ai::StairsCard>()->draw = ai::StairsDraw{};  // the 10 steps above, 0.15 m high
  run.card.as<ai::StairsCard>()->stepHeight = 0.15;
  run.card.episodes = 2;
  run.card.driven()->episodeSeconds = 1.0;
  const ai::PolicyFn zero = [](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) {
    act->setZero(robot::kActionSize, obs.cols());
  };
  auto where = [&](double startX) {
    stairs.terrain.startX = startX;
    for (const ai::CardFigure& f : ai::runVelocityCard(fixtures::robotModel(), stairs, zero, run).figures)
      if (f.name.find("falls by place") != std::string::npos) return f.name;
    return std::string("no breakdown");
  };
  EXPECT_NE(where(1.0).find("before the stairs 2, up 0, landing 0, down 0, beyond 0"), std::string::npos) << where(1.0);
  EXPECT_NE(where(-10.0).find("before the stairs 0, up 0, landing 0, down 0, beyond 2"), std::string::npos)
      << where(-10.0);
  // no episode reached the way down, so the card gives no heading there (rather than a 0 that reads as squared up)
  stairs.terrain.startX = 1.0;
  for (const ai::CardFigure& f : ai::runVelocityCard(fixtures::robotModel(), stairs, zero, run).figures)
    EXPECT_EQ(f.name.find("heading off the stairs"), std::string::npos) << f.name << " " << f.value;
}

TEST(VelocityCard, AStairsCardThatSteersSquaresTheRobotUpToTheStairs) {
  // the shipped stairs model on 10 steps, 4 episodes each turned up to 0.2 rad (11.5 deg) at the start: unsteered it
  // keeps roughly that heading (no turn is asked), steered with play's heading-hold law it faces the stairs by the top
  const ai::TrainingTree tree =
      ai::loadTrainingTree(fixtures::kSource + "/assets/skills/tree.toml", fixtures::robotModel());
  ai::SkillSpec stairs = *tree.find("stairs");
  stairs.terrain.steps = 10, stairs.terrain.stepDepth = 0.30;
  const ai::LoadedPolicy model = ai::loadPolicyOnnx(fixtures::kSource + "/assets/skills/stairs.onnx");
  const ai::PolicyFn policy = [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* act) { model.act(obs, act); };
  ai::CardRun run{stairs.card, 1, 2};
  run.card.as<ai::StairsCard>()->draw = ai::StairsDraw{};  // 10 steps of 0.10 m x 0.30 m, turned up to 0.2 rad
  run.card.as<ai::StairsCard>()->stepHeight = 0.10;
  run.card.as<ai::StairsCard>()->heading = 0.2;
  run.card.episodes = 4;
  run.card.driven()->episodeSeconds = 20.0;  // past the top of the way down (x = 4.7 m)
  auto heading = [&](double steer) {
    run.card.as<ai::StairsCard>()->steer = steer;
    double value = -1, progress = 0;
    for (const ai::CardFigure& f : ai::runVelocityCard(fixtures::robotModel(), stairs, policy, run).figures) {
      if (f.name.rfind("heading off the stairs", 0) == 0) value = f.value;
      if (f.name.rfind("mean progress along the stairs", 0) == 0) progress = f.value;
    }
    EXPECT_GT(progress, 100.0 * 4.7 / 7.4) << "steer " << steer << ": the episodes must reach the way down";
    return value;
  };
  const double unsteered = heading(0.0), steered = heading(2.0);
  EXPECT_GT(unsteered, 2.0);
  EXPECT_LT(steered, 2.0);
  EXPECT_LT(steered, 0.5 * unsteered);
}
