// skill_env_test.cpp — the walk training environment: deterministic for a seed whatever the thread count,
// rewards are the weighted sum of the named terms, and falls terminate.
#include "ai/env/skill_env.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <set>

#include "ai/env/terrain.h"
#include "engine/core/error.h"
#include "robot/entry_state.h"
#include "robot/skill_runtime.h"

namespace {

const std::string kSource = TREELEARN_SOURCE_DIR;

struct Fixture {
  robot::RobotModel model = robot::loadRobotModel(kSource + "/assets/robots/g1_23dof.toml");
  ai::TrainingTree tree = ai::loadTrainingTree(kSource + "/assets/skills/tree.toml", model);
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

// environments without handover episodes (no parent policy), n of them on `threads` threads
ai::SkillEnvOptions envOptions(int n, int threads, bool randomise) {
  ai::SkillEnvOptions o;
  o.numEnvs = n;
  o.threads = threads;
  o.randomise = randomise;
  return o;
}

std::vector<float> rollout(int threads, uint64_t seed, int steps) {
  ai::SkillEnv env(fixture().model, *fixture().tree.find("walk"), fixture().tree.path, envOptions(6, threads, true));
  Eigen::MatrixXf obs;
  env.reset(seed, &obs);
  std::vector<float> trace(obs.data(), obs.data() + obs.size());
  ai::StepResult r;
  Eigen::MatrixXf act = Eigen::MatrixXf::Constant(robot::kActionSize, 6, 0.3f);
  for (int s = 0; s < steps; ++s) {
    env.step(act, &r);
    trace.insert(trace.end(), r.rewards.data(), r.rewards.data() + r.rewards.size());
    trace.insert(trace.end(), r.observations.data(), r.observations.data() + r.observations.size());
  }
  return trace;
}

// nothing ends the skill's episodes (no tilt, height, time or lifted-foot limit): only what a test watches changes
void neverEnds(ai::SkillSpec* s) {
  s->termination.maxTiltDegrees = 180.0;
  s->termination.minHeight = -10.0;
  s->termination.episodeSeconds = 100.0;
  s->termination.liftedFootTouchSeconds = 0.0;
}

}  // namespace

TEST(SkillEnv, SameSeedGivesTheSameRolloutOnOneOrTwoThreads) {
  const std::vector<float> a = rollout(1, 7, 150), b = rollout(2, 7, 150), c = rollout(2, 8, 150);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

TEST(SkillEnv, ObservationFollowsTheSharedLayout) {
  ai::SkillEnv env(fixture().model, *fixture().tree.find("walk"), fixture().tree.path, envOptions(2, 1, false));
  Eigen::MatrixXf obs;
  env.reset(1, &obs);
  ASSERT_EQ(obs.rows(), robot::kObservationSize);
  // standing upright: projected gravity (0, 0, -1); joints near the default pose; no previous action
  EXPECT_NEAR(obs(robot::kObsGravity + 2, 0), -1.0f, 1e-3f);
  for (int j = 0; j < robot::kNumJoints; ++j) EXPECT_NEAR(obs(robot::kObsJointPosition + j, 0), 0.0f, 0.021f);
  for (int j = 0; j < robot::kNumJoints; ++j) EXPECT_EQ(obs(robot::kObsPreviousAction + j, 0), 0.0f);
}

TEST(SkillEnv, RewardIsTheWeightedSumOfItsTermsClippedAtZero) {
  ai::SkillEnv env(fixture().model, *fixture().tree.find("walk"), fixture().tree.path, envOptions(1, 1, true));
  Eigen::MatrixXf obs;
  env.reset(3, &obs);
  ai::StepResult r;
  int clipped = 0, positive = 0;
  for (int s = 0; s < 200; ++s) {
    env.step(Eigen::MatrixXf::Constant(robot::kActionSize, 1, s % 2 ? 1.5f : -1.5f), &r);
    double total = 0;
    for (double t : r.rewardTermSums) total += t;
    EXPECT_NEAR(std::max(total, 0.0), double(r.rewards[0]), 1e-4);
    clipped += total < 0;
    positive += total > 0;
  }
  EXPECT_GT(clipped, 0);  // the alternating actions are punished below zero at least once
}

TEST(SkillEnv, AFallTerminatesAndResets) {
  // large constant actions throw the robot over within a few seconds
  ai::SkillEnv env(fixture().model, *fixture().tree.find("walk"), fixture().tree.path, envOptions(2, 1, false));
  Eigen::MatrixXf obs;
  env.reset(5, &obs);
  ai::StepResult r;
  int terminated = 0;
  for (int s = 0; s < 400 && !terminated; ++s) {
    env.step(Eigen::MatrixXf::Constant(robot::kActionSize, 2, 3.0f), &r);
    terminated += r.terminated[0] + r.terminated[1];
  }
  ASSERT_GT(terminated, 0);
  EXPECT_FALSE(r.episodeReturns.empty());
  // the reset robot stands at the start again
  EXPECT_NEAR(r.observations(robot::kObsGravity + 2, r.terminated[0] ? 0 : 1), -1.0f, 0.01f);
}

namespace {

// one rollout as the trainer runs it: reset, `steps` steps of zero actions, end of rollout
void zeroRollout(ai::SkillEnv* env, int steps, uint64_t seed = 1) {
  Eigen::MatrixXf obs;
  env->reset(seed, &obs);
  ai::StepResult r;
  const Eigen::MatrixXf zero = Eigen::MatrixXf::Zero(robot::kActionSize, env->numEnvs());
  for (int s = 0; s < steps; ++s) env->step(zero, &r);
  env->endRollout();
}

// the stairs with a four-lesson curriculum of step heights (the shipped stairs draw each episode's staircase instead)
ai::SkillSpec curriculumStairs() {
  ai::SkillSpec stairs = *fixture().tree.find("stairs");
  stairs.terrain.draw = ai::StairsDraw{};
  stairs.terrain.steps = 10, stairs.terrain.stepDepth = 0.30;
  stairs.terrain.lessons = {0.01, 0.05, 0.10, 0.15};
  return stairs;
}

}  // namespace

TEST(Curriculum, LessonAdvancesAtTheRolloutEndWhenTheSmoothedReturnPassesTheBarAndSurvivesACheckpoint) {
  ai::SkillSpec stairs = curriculumStairs();
  stairs.termination.episodeSeconds = 0.2;  // 20-tick episodes: many finish quickly
  stairs.terrain.advanceAt = 0.01;          // a zero policy still earns a little (the total is clipped at 0)
  ai::SkillEnv env(fixture().model, stairs, fixture().tree.path, envOptions(4, 1, false));
  EXPECT_EQ(env.curriculumLesson(), 0);
  EXPECT_DOUBLE_EQ(env.stepHeight(), stairs.terrain.lessons[0]);
  Eigen::MatrixXf obs;
  env.reset(1, &obs);
  ai::StepResult r;
  const Eigen::MatrixXf zero = Eigen::MatrixXf::Zero(robot::kActionSize, 4);
  for (int s = 0; s < 60; ++s) env.step(zero, &r);
  EXPECT_EQ(env.curriculumLesson(), 0);  // lessons change only between rollouts
  env.endRollout();
  EXPECT_EQ(env.curriculumLesson(), 1) << env.curriculumNote();
  for (int k = 0; k < 5; ++k) zeroRollout(&env, 20);  // one lesson per rollout, up to the last and no further
  EXPECT_EQ(env.curriculumLesson(), 3);
  EXPECT_DOUBLE_EQ(env.stepHeight(), 0.15);
  EXPECT_NE(env.curriculumNote().find("lesson 4/4"), std::string::npos) << env.curriculumNote();

  ai::SkillEnv resumed(fixture().model, stairs, fixture().tree.path, envOptions(4, 1, false));
  resumed.loadState(env.saveState());
  EXPECT_EQ(resumed.curriculumLesson(), 3);
  EXPECT_EQ(resumed.saveState(), env.saveState());
}

TEST(Curriculum, EpisodesLongerThanTheRolloutCountForWhatTheyPlayed) {
  // the walk's 20 s time limit is longer than a rollout: no episode times out, and standing without a fall for
  // the whole rollout must still count (it once did not, and a curriculum with only falls to measure never moved)
  ai::SkillSpec stairs = curriculumStairs();
  stairs.termination.episodeSeconds = 20.0;
  stairs.terrain.advanceAt = 0.01;
  ai::SkillEnv env(fixture().model, stairs, fixture().tree.path, envOptions(4, 1, false));
  zeroRollout(&env, 150);  // 1.5 s: the zero policy stands; 4 episodes, not yet two per environment
  EXPECT_EQ(env.curriculumLesson(), 0) << env.curriculumNote();
  zeroRollout(&env, 150, 2);
  EXPECT_EQ(env.curriculumLesson(), 1) << env.curriculumNote();
  zeroRollout(&env, 50);  // 0.5 s: too short a sample to judge, nothing counts
  EXPECT_EQ(env.curriculumLesson(), 1) << env.curriculumNote();
  EXPECT_NE(env.curriculumNote().find("over 0 episodes"), std::string::npos) << env.curriculumNote();
}

TEST(Curriculum, ScoreIsTheReturnPerTickEachEpisodeCouldPlayAveragedOverTheLesson) {
  // by hand from the step results: every episode of a 260-step rollout with a 1.5 s time limit, finished (fallen
  // or timed out) or cut by the rollout's end, scores return / min(150, 260 - its first step); those that could
  // play fewer than 100 ticks are left out; the score is the bias-corrected average (weight 0.02 per episode)
  ai::SkillSpec stairs = curriculumStairs();
  stairs.termination.episodeSeconds = 1.5;
  stairs.terrain.advanceAt = 1e9;  // never: only the score is checked
  const int n = 3, steps = 260, limit = 150;
  ai::SkillEnv env(fixture().model, stairs, fixture().tree.path, envOptions(n, 1, false));
  Eigen::MatrixXf obs;
  env.reset(4, &obs);
  ai::StepResult r;
  std::vector<double> running(n, 0.0);
  std::vector<int> start(n, 0);
  std::vector<double> finished, finishedPossible;  // in the order the environment sees them
  for (int t = 0; t < steps; ++t) {
    env.step(Eigen::MatrixXf::Constant(robot::kActionSize, n, t % 2 ? 0.4f : -0.4f), &r);
    for (int i = 0; i < n; ++i) {
      running[size_t(i)] += double(r.rewards[i]);
      if (r.terminated[size_t(i)] || r.truncated[size_t(i)]) {
        finished.push_back(running[size_t(i)]);
        finishedPossible.push_back(std::min(limit, steps - start[size_t(i)]));
        running[size_t(i)] = 0;
        start[size_t(i)] = t + 1;
      }
    }
  }
  env.endRollout();
  for (int i = 0; i < n; ++i)
    if (start[size_t(i)] < steps)
      finished.push_back(running[size_t(i)]), finishedPossible.push_back(std::min(limit, steps - start[size_t(i)]));
  double ema = 0;
  int k = 0;
  for (size_t e = 0; e < finished.size(); ++e) {
    if (finishedPossible[e] < 100) continue;
    ema = 0.98 * ema + 0.02 * finished[e] / finishedPossible[e];
    ++k;
  }
  ASSERT_GT(k, n);  // the time-outs at 150 and the episodes cut at 260 after 110 ticks both count
  EXPECT_NEAR(env.curriculumScore(), ema / (1.0 - std::pow(0.98, k)), 1e-4) << env.curriculumNote();
  EXPECT_NE(env.curriculumNote().find("over " + std::to_string(k) + " episodes"), std::string::npos)
      << env.curriculumNote();
}

TEST(Curriculum, CommandLessonsRaiseTheForwardTopAndChangeTheGait) {
  ai::SkillSpec run = *fixture().tree.find("run");
  run.handover = 0;        // no walk policy here: ordinary episodes only
  run.draws.ramp = false;  // each draw at once, so the lesson's top shows in the observed command
  run.termination.episodeSeconds = 0.2;
  run.curriculum.vxMax = {1.0, 1.5, run.commands.vx.hi};
  run.curriculum.halfPeriodTicks = {40, 35, run.prior.halfPeriodTicks};
  run.curriculum.advanceAt = 0.01;
  run.draws.resampleSeconds = 0.05;  // a new draw every 5 ticks: many draws per lesson
  ai::SkillEnv env(fixture().model, run, fixture().tree.path, envOptions(4, 1, false));
  EXPECT_DOUBLE_EQ(env.lessonSkill().commands.vx.hi, 1.0);
  EXPECT_EQ(env.lessonSkill().prior.halfPeriodTicks, 40);
  Eigen::MatrixXf obs;
  env.reset(1, &obs);
  ai::StepResult r;
  const Eigen::MatrixXf zero = Eigen::MatrixXf::Zero(robot::kActionSize, 4);
  double topSeen = 0;
  for (int s = 0; s < 60; ++s) {  // lesson 1: no forward command above its 1.0 m/s
    env.step(zero, &r);
    for (int n = 0; n < 4; ++n) topSeen = std::max(topSeen, double(r.observations(robot::kObsCommand, n)));
  }
  env.endRollout();
  EXPECT_LE(topSeen, 1.0 + 1e-6);
  EXPECT_GT(topSeen, 0.8);  // the run's commands start at 0.8 m/s
  EXPECT_EQ(env.curriculumLesson(), 1) << env.curriculumNote();
  EXPECT_DOUBLE_EQ(env.lessonSkill().commands.vx.hi, 1.5);
  EXPECT_EQ(env.lessonSkill().prior.halfPeriodTicks, 35);
  zeroRollout(&env, 60);
  EXPECT_EQ(env.curriculumLesson(), 2) << env.curriculumNote();
  EXPECT_DOUBLE_EQ(env.lessonSkill().commands.vx.hi, run.commands.vx.hi);
  EXPECT_EQ(env.lessonSkill().prior.halfPeriodTicks, run.prior.halfPeriodTicks);
  EXPECT_NE(env.curriculumNote().find("forward commands up to 2.20 m/s"), std::string::npos) << env.curriculumNote();
  // a resumed environment trains the lesson it was saved in
  ai::SkillEnv resumed(fixture().model, run, fixture().tree.path, envOptions(4, 1, false));
  resumed.loadState(env.saveState());
  EXPECT_EQ(resumed.lessonSkill().prior.halfPeriodTicks, run.prior.halfPeriodTicks);
}

TEST(Curriculum, AmplitudeLessonsRaiseTheAmplitudeTop) {
  ai::SkillSpec oneLeg = *fixture().tree.find("one_leg");
  oneLeg.curriculum.amplitudeMax = {0.6, oneLeg.commands.amplitude.hi};
  oneLeg.curriculum.advanceAt = 0.01;
  oneLeg.handover = 0;  // episodes from the spawn (a handover needs the walk's policy)
  ai::SkillEnv env(fixture().model, oneLeg, fixture().tree.path, envOptions(4, 1, false));
  EXPECT_DOUBLE_EQ(env.lessonSkill().commands.amplitude.hi, 0.6);
  EXPECT_DOUBLE_EQ(env.lessonSkill().commands.amplitude.lo, oneLeg.commands.amplitude.lo);
  zeroRollout(&env, 120);
  zeroRollout(&env, 120, 2);
  EXPECT_EQ(env.curriculumLesson(), 1) << env.curriculumNote();
  EXPECT_DOUBLE_EQ(env.lessonSkill().commands.amplitude.hi, oneLeg.commands.amplitude.hi);
  EXPECT_NE(env.curriculumNote().find("amplitude commands up to 1.00"), std::string::npos) << env.curriculumNote();
}

TEST(Curriculum, NoLessonChangeBelowTheBar) {
  ai::SkillSpec stairs = *fixture().tree.find("stairs");
  stairs.termination.episodeSeconds = 0.2;
  stairs.terrain.advanceAt = 100.0;  // unreachable
  ai::SkillEnv env(fixture().model, stairs, fixture().tree.path, envOptions(4, 1, false));
  Eigen::MatrixXf obs;
  env.reset(1, &obs);
  ai::StepResult r;
  const Eigen::MatrixXf zero = Eigen::MatrixXf::Zero(robot::kActionSize, 4);
  for (int s = 0; s < 100; ++s) env.step(zero, &r);
  env.endRollout();
  EXPECT_EQ(env.curriculumLesson(), 0);
}

TEST(SkillEnv, RampedAmplitudeMovesAtMostItsRatePerTick) {
  ai::SkillSpec oneLeg = *fixture().tree.find("one_leg");
  oneLeg.handover = 0;                                // episodes from the spawn (a handover needs the walk's policy)
  ASSERT_DOUBLE_EQ(oneLeg.draws.amplitudeRate, 1.0);  // the R / F keys' rate: 0.01 per tick
  ai::SkillEnv env(fixture().model, oneLeg, fixture().tree.path, envOptions(2, 1, false));
  Eigen::MatrixXf obs;
  env.reset(3, &obs);
  const int slot = robot::kObsCommand + 3;  // vx, vy, wz, amplitude
  // every episode starts at amplitude 0; its first observation shows the command one tick on (as play's keys ramp
  // before the control step)
  EXPECT_LE(std::abs(obs(slot, 0)), 0.01f + 1e-6f);
  ai::StepResult r;
  float previous = obs(slot, 0), highest = 0;
  for (int s = 0; s < 60; ++s) {
    env.step(Eigen::MatrixXf::Zero(robot::kActionSize, 2), &r);
    const float a = r.observations(slot, 0);
    EXPECT_LE(std::abs(a - previous), 0.01f + 1e-6f);
    previous = a;
    highest = std::max(highest, a);
  }
  EXPECT_GT(highest, 0.0f);
}

TEST(SkillEnv, RampedVelocityCommandsMoveAtTheKeyboardRatesOneAxisAtATime) {
  ai::SkillSpec walk = *fixture().tree.find("walk");
  walk.draws.ramp = true;
  walk.draws.zeroProbability = 0.0;
  walk.draws.resampleSeconds = 2.0;  // several changes within the run
  ai::SkillEnv env(fixture().model, walk, fixture().tree.path, envOptions(4, 1, false));
  Eigen::MatrixXf obs;
  env.reset(5, &obs);
  Eigen::MatrixXf previous = obs.middleRows(robot::kObsCommand, 3);
  // episodes start from rest and ramp up: the first observation is one tick of the ramp on
  for (int i = 0; i < 4; ++i) {
    EXPECT_LE(std::abs(previous(0, i)), 0.02f + 1e-5f);
    EXPECT_LE(std::abs(previous(1, i)), 0.02f + 1e-5f);
    EXPECT_LE(std::abs(previous(2, i)), 0.03f + 1e-5f);
  }
  ai::StepResult r;
  int moving = 0;
  for (int s = 0; s < 700; ++s) {
    env.step(Eigen::MatrixXf::Zero(robot::kActionSize, 4), &r);
    const Eigen::MatrixXf now = r.observations.middleRows(robot::kObsCommand, 3);
    for (int i = 0; i < 4; ++i) {
      if (r.terminated[size_t(i)] || r.truncated[size_t(i)]) continue;  // a new episode starts at rest
      EXPECT_LE(std::abs(now(0, i) - previous(0, i)), 0.02f + 1e-5f);   // vx: 2 m/s^2
      EXPECT_LE(std::abs(now(1, i) - previous(1, i)), 0.02f + 1e-5f);   // vy
      EXPECT_LE(std::abs(now(2, i) - previous(2, i)), 0.03f + 1e-5f);   // wz: 3 rad/s^2
      EXPECT_LE((now.col(i).array() != 0.0f).count(), 1);               // the interlock
      moving += now.col(i).norm() > 0.1f;
    }
    previous = now;
  }
  EXPECT_GT(moving, 700);  // the commands did move
}

// [draws] steer: while W moves the robot, play's heading hold adds a turn of at most 0.2 rad/s; a steered skill
// meets such turns in training, on top of the keys' interlocked and ramped command
TEST(SkillEnv, ASteeredForwardCommandTurnsAtItsDrawWhileTheRampKeepsItsRates) {
  ai::SkillSpec walk = *fixture().tree.find("walk");
  walk.draws.ramp = true;
  walk.draws.zeroProbability = 0.0;
  walk.draws.resampleSeconds = 2.0;
  walk.draws.steer = 0.3;
  ai::SkillEnv env(fixture().model, walk, fixture().tree.path, envOptions(4, 1, false));
  Eigen::MatrixXf obs;
  env.reset(5, &obs);
  Eigen::MatrixXf previous = obs.middleRows(robot::kObsCommand, 3);
  ai::StepResult r;
  int steered = 0, moving = 0;
  for (int s = 0; s < 700; ++s) {
    env.step(Eigen::MatrixXf::Zero(robot::kActionSize, 4), &r);
    const Eigen::MatrixXf now = r.observations.middleRows(robot::kObsCommand, 3);
    for (int i = 0; i < 4; ++i) {
      if (r.terminated[size_t(i)] || r.truncated[size_t(i)]) continue;
      EXPECT_LE(std::abs(now(0, i) - previous(0, i)), 0.02f + 1e-5f);  // vx still ramps at 2 m/s^2
      EXPECT_LE(std::abs(now(1, i) - previous(1, i)), 0.02f + 1e-5f);  // vy
      EXPECT_LE(now(0, i) != 0.0f && now(1, i) != 0.0f ? 1 : 0, 0);    // forward and sideways: still one at a time
      if (now(0, i) != 0.0f || now(1, i) != 0.0f) {
        ++moving;
        EXPECT_LE(std::abs(now(2, i)), 0.3f + 1e-5f);  // moving: the keys' turn is 0, the steer within +-0.3
        steered += now(2, i) != 0.0f;
      }
    }
    previous = now;
  }
  EXPECT_GT(moving, 700);
  EXPECT_GT(steered, moving / 2);  // turning while moving, which the interlock alone never gives
}

// [commands] turn_in_place = false: the draws move the robot or stop it, never turn it on the spot (a third of the
// stairs' training went to turns in place on the steps their card never asks for)
TEST(SkillEnv, WithoutTurnsInPlaceNoDrawTurnsTheRobotOnTheSpot) {
  for (const bool turns : {true, false}) {
    ai::SkillSpec walk = *fixture().tree.find("walk");
    walk.draws.zeroProbability = 0.0;
    walk.draws.resampleSeconds = 0.2;  // many draws
    walk.draws.turnInPlace = turns;
    ai::SkillEnv env(fixture().model, walk, fixture().tree.path, envOptions(4, 1, false));
    Eigen::MatrixXf obs;
    env.reset(5, &obs);
    ai::StepResult r;
    int turning = 0, moving = 0;
    for (int s = 0; s < 200; ++s) {
      env.step(Eigen::MatrixXf::Zero(robot::kActionSize, 4), &r);
      const Eigen::MatrixXf now = r.observations.middleRows(robot::kObsCommand, 3);
      for (int i = 0; i < 4; ++i) {
        turning += now(2, i) != 0.0f;
        moving += now(0, i) != 0.0f || now(1, i) != 0.0f;
      }
    }
    EXPECT_GT(moving, 400) << turns;
    if (turns)
      EXPECT_GT(turning, 100);  // a quarter of the draws turn in place
    else
      EXPECT_EQ(turning, 0);
  }
}

TEST(SkillEnv, JitteredCommandIntervalsVaryWithinTheirBand) {
  ai::SkillSpec walk = *fixture().tree.find("walk");
  walk.draws.zeroProbability = 0.0;
  walk.draws.resampleSeconds = 1.0;
  walk.draws.resampleJitter = 0.5;  // 0.5 .. 1.5 s
  neverEnds(&walk);                 // only command changes are watched
  ai::SkillEnv env(fixture().model, walk, fixture().tree.path, envOptions(1, 1, false));
  Eigen::MatrixXf obs;
  env.reset(9, &obs);
  Eigen::VectorXf previous = obs.col(0).segment(robot::kObsCommand, 3);
  ai::StepResult r;
  std::vector<int> changes;
  for (int s = 1; s <= 1000; ++s) {
    env.step(Eigen::MatrixXf::Zero(robot::kActionSize, 1), &r);
    const Eigen::VectorXf now = r.observations.col(0).segment(robot::kObsCommand, 3);
    if (now != previous) changes.push_back(s);
    previous = now;
  }
  ASSERT_GE(changes.size(), 7u);  // 10 s of 0.5-1.5 s intervals
  std::set<int> intervals;
  for (size_t k = 1; k < changes.size(); ++k) {
    const int gap = changes[k] - changes[k - 1];
    EXPECT_GE(gap, 50);
    EXPECT_LE(gap, 150);
    intervals.insert(gap);
  }
  EXPECT_GT(intervals.size(), 3u);  // not one fixed interval
}

TEST(SkillEnv, HandoverEpisodesStartWithTheParentsFilteredAction) {
  // the parent (walk without a gait) always outputs a balanced crouch (hip pitch -0.4, knee +0.8, ankle pitch
  // -0.4 on both legs), so the robot stands bent; the squat starts each handover episode after 0.5 s of it (plus
  // the wait for rest), with the parent's low-passed action (u = 0.8 u + 0.2 a: within 0.8^50 of it) in its
  // previous-action slot. Without handover the slot is 0.
  ai::SkillSpec walk = *fixture().tree.find("walk");
  walk.prior.kind = robot::PriorDef::Kind::None;
  ai::SkillSpec squat = *fixture().tree.find("squat");
  squat.handoverSeconds = {0.5, 0.5};
  Eigen::VectorXf crouch = Eigen::VectorXf::Zero(robot::kActionSize);
  for (int leg : {0, 6}) crouch(leg + 0) = -0.4f, crouch(leg + 3) = 0.8f, crouch(leg + 4) = -0.4f;
  std::atomic<int> calls{0};
  ai::SkillEnvOptions options = envOptions(4, 2, false);
  options.parent = &walk;
  options.parentPolicy = [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) {
    ++calls;
    *a = crouch.replicate(1, obs.cols());
  };
  for (double handover : {0.0, 1.0}) {
    squat.handover = handover;
    calls = 0;
    ai::SkillEnv env(fixture().model, squat, fixture().tree.path, options);
    Eigen::MatrixXf obs;
    env.reset(7, &obs);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < robot::kActionSize; ++j)
        EXPECT_NEAR(obs(robot::kObsPreviousAction + j, i), handover > 0 ? crouch(j) : 0.0f, 1e-4)
            << "env " << i << " joint " << j;
    if (handover > 0)
      EXPECT_GE(calls.load(), 4 * 50);  // 0.5 s of the parent in each of the 4 environments
    else
      EXPECT_EQ(calls.load(), 0);
  }
}

// the route walk -> squat -> jump of a handover: the walk without a gait, the walk's time 0.5 s and the squat's 0.3 s
struct JumpRoute {
  ai::SkillSpec walk, jump;
  const ai::SkillSpec& squat;
};
JumpRoute jumpRoute() {
  JumpRoute r{*fixture().tree.find("walk"), *fixture().tree.find("jump"), *fixture().tree.find("squat")};
  r.walk.prior.kind = robot::PriorDef::Kind::None;
  r.jump.handoverSeconds = {0.5, 0.5};
  r.jump.handoverViaSeconds = {0.3, 0.3};
  return r;
}

// both legs bent at (hip pitch, knee, ankle pitch), every other joint at its default
Eigen::VectorXf legCrouch(float hip, float knee, float ankle) {
  Eigen::VectorXf a = Eigen::VectorXf::Zero(robot::kActionSize);
  for (int leg : {0, 6}) a(leg + 0) = hip, a(leg + 3) = knee, a(leg + 4) = ankle;
  return a;
}

TEST(SkillEnv, HandoverFromAGrandparentRoutesThroughTheSkillBetweenForItsTime) {
  // walk -> squat -> jump, as a routed request in play: the walk (without a gait, its policy a balanced crouch)
  // drives 0.5 s, the squat takes over once the robot is at rest and runs 0.3 s at a zero command, then the jump.
  // The squat's policy (another crouch depth) is called 0.3 s per environment, and the jump starts with the
  // squat's low-passed action in its previous-action slot (within 0.8^30 of it, from the walk's).
  JumpRoute r = jumpRoute();
  r.jump.handover = 1.0;
  const ai::SkillSpec &walk = r.walk, &jump = r.jump, &squat = r.squat;
  const Eigen::VectorXf crouch = legCrouch(-0.4f, 0.8f, -0.4f), deeper = legCrouch(-0.5f, 1.0f, -0.5f);
  std::atomic<int> walkCalls{0}, squatCalls{0};
  ai::SkillEnvOptions options = envOptions(4, 2, false);
  options.parent = &walk;
  options.parentPolicy = [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) {
    ++walkCalls;
    *a = crouch.replicate(1, obs.cols());
  };
  options.via.push_back({&squat, [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) {
                           ++squatCalls;
                           *a = deeper.replicate(1, obs.cols());
                         }});
  ai::SkillEnv env(fixture().model, jump, fixture().tree.path, options);
  Eigen::MatrixXf obs;
  env.reset(7, &obs);
  EXPECT_GE(walkCalls.load(), 4 * 50);   // 0.5 s of the walk (and its wait for rest) in each environment
  EXPECT_GE(squatCalls.load(), 4 * 30);  // then 0.3 s of the squat in each
  EXPECT_LE(squatCalls.load(), 4 * 30 + 4 * robot::maxSwitchWaitTicks(jump));
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < robot::kActionSize; ++j)
      EXPECT_NEAR(obs(robot::kObsPreviousAction + j, i), deeper(j), 0.01) << "env " << i << " joint " << j;
}

TEST(SkillEnv, AHandoverIntoTheJumpWaitsForASettledStandAsPlayDoes) {
  // walk -> squat -> jump with the squat's time drawn at 0.3 s: the squat's policy bobs (crouch and deeper every
  // 0.1 s) for its first 0.5 s and then holds the crouch. Play switches into the jump only once the robot stands
  // settled (robot::postureAllowsSwitch); so must the lead-in: the jump starts with every leg joint slower than
  // kSettledJointSpeed, after the bobbing, not at the drawn 0.3 s (an earlier lead-in switched at
  // once from a still skill: the jump card's entries had leg joints at up to 4.7 rad/s). A squat that never stops
  // bobbing never hands over: the lead-in is drawn again.
  const JumpRoute r = jumpRoute();
  const ai::SkillSpec &walk = r.walk, &jump = r.jump, &squat = r.squat;
  const Eigen::VectorXf crouch = legCrouch(-0.4f, 0.8f, -0.4f), deeper = legCrouch(-0.6f, 1.2f, -0.6f);
  for (const int bobTicks : {50, 1000000}) {
    int squatCalls = 0;
    const std::vector<ai::HandoverStage> route{
        {&walk, [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) { *a = crouch.replicate(1, obs.cols()); }},
        {&squat, [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) {
           const int t = squatCalls++;
           *a = (t < bobTicks && (t / 10) % 2 == 1 ? deeper : crouch).replicate(1, obs.cols());
         }}};
    engine::PhysicsWorld world;
    world.addGround(1.0);
    robot::Robot robot(fixture().model, world, 0, 0, 0);
    robot::Sensors sensors = robot.sense(world);
    std::mt19937_64 rng(3);
    robot::SkillState state;
    robot::SkillCommand atSwitch;
    const bool handedOver = ai::runHandover(fixture().model, fixture().model, world, robot, &sensors,
                                            ai::makeHandoverRoute(route, jump), rng, &state, &atSwitch);
    if (bobTicks > 1000) {
      EXPECT_FALSE(handedOver) << "a squat that never settles must not hand over to the jump";
      continue;
    }
    ASSERT_TRUE(handedOver);
    EXPECT_GT(squatCalls, bobTicks) << "the switch came while the squat still bobbed";
    EXPECT_TRUE(robot::isStandingSettled(sensors));
    for (int j = 0; j < robot::kNumLegJoints; ++j)
      EXPECT_LT(std::abs(sensors.qd[size_t(j)]), robot::kSettledJointSpeed) << j;
  }
}

TEST(SkillEnv, ARampedCommandGoesOnFromTheHandoversAsTheKeysDoInPlay) {
  // the walk (no gait, zero output: it stands) is driven with W held at 1.0 m/s for 0.6 s: the keys' ramp
  // (0.02 m/s per tick) reaches 1.0 after 50 ticks. The run (ramped commands) then starts from that 1.0 and ramps
  // on to its own draw; an ordinary episode starts from 0 (each observation shows the command one tick of the ramp on).
  ai::SkillSpec walk = *fixture().tree.find("walk");
  walk.prior.kind = robot::PriorDef::Kind::None;
  ai::SkillSpec run = *fixture().tree.find("run");
  ASSERT_TRUE(run.draws.ramp);
  run.handoverSeconds = {0.6, 0.6};
  run.handoverVx = {1.0, 1.0};
  ai::SkillEnvOptions options = envOptions(4, 2, false);
  options.parent = &walk;
  options.parentPolicy = [](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) {
    *a = Eigen::MatrixXf::Zero(robot::kActionSize, obs.cols());
  };
  for (double handover : {0.0, 1.0}) {
    run.handover = handover;
    ai::SkillEnv env(fixture().model, run, fixture().tree.path, options);
    Eigen::MatrixXf obs;
    env.reset(3, &obs);
    for (int i = 0; i < 4; ++i)
      EXPECT_NEAR(obs(robot::kObsCommand, i), handover > 0 ? 1.0f : 0.0f, 0.02f + 1e-6f) << "env " << i;
  }
}

TEST(SkillEnv, ABallAbsentShareStartsThatShareOfEpisodesWithoutTheBall) {
  // the kick's entry without handovers; the ball's aux slots are its offset ahead (~0.3 m) or 0 without a ball
  ai::SkillSpec kick = *fixture().tree.find("kick");
  kick.handover = 0;
  auto ballless = [&](double absent) {
    kick.ball.absent = absent;
    ai::SkillEnv env(fixture().model, kick, fixture().tree.path, envOptions(40, 2, false));
    Eigen::MatrixXf obs;
    env.reset(3, &obs);
    int none = 0;
    for (int i = 0; i < 40; ++i) {
      const float ahead = obs(robot::kObsCommand + 4, i), side = obs(robot::kObsCommand + 5, i);
      if (ahead == 0.0f && side == 0.0f)
        ++none;
      else
        EXPECT_NEAR(ahead, 0.30f, 0.05f);
    }
    return none;
  };
  EXPECT_EQ(ballless(0.0), 0);
  EXPECT_EQ(ballless(1.0), 40);
  const int half = ballless(0.5);  // binomial(40, 0.5): 10..30 holds with probability > 0.998
  EXPECT_GE(half, 10);
  EXPECT_LE(half, 30);
}

TEST(SkillEnv, HandoverFromAChildStartsUnderItFromTheStandAndSwitchesOnceSettled) {
  // the way back up the tree (jump -> squat in play): the jump's prior (its policy only raises the arms) takes over
  // from the standing controller, jumps for 1 s and the squat takes over once the robot stands settled between
  // jumps (leg joints slower than kSettledJointSpeed, the pelvis slower than kRestSpeed), with the jump's
  // low-passed action in its previous-action slot. No walk policy is called: these episodes start under the child.
  ai::SkillSpec squat = *fixture().tree.find("squat");
  squat.handover = 0;
  squat.handoverBack = 1.0;
  squat.handoverBackFrom = "jump";
  squat.handoverBackSeconds = {1.0, 1.0};
  const ai::SkillSpec& jump = *fixture().tree.find("jump");
  Eigen::VectorXf arms = Eigen::VectorXf::Zero(robot::kActionSize);
  arms(13) = arms(18) = -0.1f;  // shoulder pitch, both arms
  std::atomic<int> jumpCalls{0};
  ai::SkillEnvOptions options = envOptions(4, 2, false);
  options.back = {&jump, [&](const Eigen::MatrixXf& obs, Eigen::MatrixXf* a) {
                    ++jumpCalls;
                    *a = arms.replicate(1, obs.cols());
                  }};
  ai::SkillEnv env(fixture().model, squat, fixture().tree.path, options);
  Eigen::MatrixXf obs;
  env.reset(3, &obs);
  EXPECT_GE(jumpCalls.load(), 4 * 100);  // 1 s of the jump in each environment, then its wait for a settled stand
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < robot::kActionSize; ++j)
      EXPECT_NEAR(obs(robot::kObsPreviousAction + j, i), arms(j), 0.01) << "env " << i << " joint " << j;
    for (int j = 0; j < robot::kNumLegJoints; ++j)
      EXPECT_LT(std::abs(obs(robot::kObsJointVelocity + j, i)), robot::kSettledJointSpeed)
          << "env " << i << " joint " << j;
    EXPECT_LT(Eigen::Vector2f(obs(robot::kObsLinearVelocity, i), obs(robot::kObsLinearVelocity + 1, i)).norm(),
              robot::kRestSpeed)
        << "env " << i;
  }
  // without the child's policy the environment cannot start these episodes
  EXPECT_THROW(ai::SkillEnv(fixture().model, squat, fixture().tree.path, envOptions(1, 1, false)), engine::Error);
}

TEST(SkillEnv, TheLiftedFootTouchingDownEndsTheEpisodeOnlyOnceTheLiftHasBeenAskedItsTime) {
  // the one-leg stand with its shift and lift taken out of the prior: the robot stands on both feet while the
  // amplitude ramps to 1 and the lift is asked
  ai::SkillSpec oneLeg = *fixture().tree.find("one_leg");
  oneLeg.handover = 0;
  oneLeg.handoverBack = 0;
  oneLeg.commands.amplitude = {1.0, 1.0};
  oneLeg.curriculum = ai::CurriculumDef{};  // no lessons capping the amplitude
  oneLeg.prior.poseOffset.fill(0.0);
  oneLeg.prior.lateOffset.fill(0.0);
  ASSERT_TRUE(oneLeg.prior.hasLate);
  // the tick at which the asked lift first reaches half the full one (the ramp's 0.01 a tick: amplitude 0.75)
  int firstAsked = 0;
  double a = 0;
  for (int k = 1; k < 200 && !firstAsked; ++k) {
    a += std::clamp(1.0 - a, -0.01, 0.01);
    if (ai::askedFootLift(oneLeg, a) >= 0.5 * ai::kFootLiftHeight) firstAsked = k;
  }
  ASSERT_NEAR(firstAsked, 75, 1);

  const auto terminationTick = [&](double touchSeconds) {
    ai::SkillSpec s = oneLeg;
    s.termination.liftedFootTouchSeconds = touchSeconds;
    ai::SkillEnv env(fixture().model, s, fixture().tree.path, envOptions(1, 1, false));
    Eigen::MatrixXf obs;
    env.reset(2, &obs);
    ai::StepResult r;
    for (int k = 1; k <= 300; ++k) {
      env.step(Eigen::MatrixXf::Zero(robot::kActionSize, 1), &r);
      if (r.terminated[0]) return k;
    }
    return 0;
  };
  EXPECT_EQ(terminationTick(0.0), 0);                    // off: the stand holds 3 s
  EXPECT_EQ(terminationTick(0.3), firstAsked + 30 - 1);  // the 30th tick of the lift asked, the foot still down
  EXPECT_EQ(terminationTick(1.0), firstAsked + 100 - 1);
}

TEST(SkillEnv, AmplitudeZeroMakesThatShareOfTheAmplitudeDrawsZero) {
  ai::SkillSpec oneLeg = *fixture().tree.find("one_leg");
  oneLeg.handover = 0;
  oneLeg.commands.amplitude = {0.5, 1.0};  // a draw is never 0 by itself
  oneLeg.draws.amplitudeRate = 0.0;        // at once, so every draw shows in the observation
  oneLeg.draws.resampleSeconds = 0.1;      // a draw every 10 ticks
  neverEnds(&oneLeg);
  const int slot = robot::kObsCommand + 3;
  auto zeroShare = [&](double p) {
    ai::SkillSpec s = oneLeg;
    s.draws.amplitudeZero = p;
    ai::SkillEnv env(fixture().model, s, fixture().tree.path, envOptions(4, 1, false));
    Eigen::MatrixXf obs;
    env.reset(5, &obs);
    ai::StepResult r;
    int zero = 0, draws = 0;
    for (int k = 1; k <= 1000; ++k) {
      env.step(Eigen::MatrixXf::Zero(robot::kActionSize, 4), &r);
      if (k % 10 != 5) continue;  // once per draw, between the draws
      for (int i = 0; i < 4; ++i, ++draws) {
        const float a = r.observations(slot, i);
        if (a == 0.0f)
          ++zero;
        else
          EXPECT_GE(a, 0.5f);
      }
    }
    return double(zero) / draws;
  };
  EXPECT_EQ(zeroShare(0.0), 0.0);
  EXPECT_NEAR(zeroShare(0.25), 0.25, 0.07);  // 400 draws: one standard deviation is 0.022
  EXPECT_EQ(zeroShare(1.0), 1.0);
}

TEST(SkillEnv, ALineKeepingSkillSeesHowFarItHasDriftedFromTheLineItBeganOn) {
  ai::SkillSpec lined = *fixture().tree.find("walk");
  lined.commands.lineCommand = true;
  neverEnds(&lined);
  ai::SkillSpec plain = lined;
  plain.commands.lineCommand = false;
  constexpr int kAux0 = robot::kObsCommand + 4, kAux1 = robot::kObsCommand + 5;
  ai::SkillEnv withLine(fixture().model, lined, fixture().tree.path, envOptions(2, 1, false));
  ai::SkillEnv without(fixture().model, plain, fixture().tree.path, envOptions(2, 1, false));
  Eigen::MatrixXf a, b;
  withLine.reset(2, &a);
  without.reset(2, &b);
  for (int i = 0; i < 2; ++i) {  // the line starts where the robot stands, the way it faces
    EXPECT_NEAR(a(kAux0, i), 0.0f, 1e-6f);
    EXPECT_NEAR(a(kAux1, i), 0.0f, 1e-6f);
  }
  ai::StepResult ra, rb;
  const Eigen::MatrixXf shove = Eigen::MatrixXf::Constant(robot::kActionSize, 2, 3.0f);  // throws it over
  double drift = 0;
  for (int s = 0; s < 200; ++s) {
    withLine.step(shove, &ra);
    without.step(shove, &rb);
    for (int i = 0; i < 2; ++i) {
      drift = std::max(drift, double(std::abs(ra.observations(kAux0, i)) + std::abs(ra.observations(kAux1, i))));
      EXPECT_EQ(rb.observations(kAux0, i), 0.0f);  // a skill without the line keeps its aux slots at 0
      EXPECT_EQ(rb.observations(kAux1, i), 0.0f);
    }
  }
  EXPECT_GT(drift, 0.05);             // the fall turned it or moved it off its line, and it sees that
  EXPECT_EQ(ra.rewards, rb.rewards);  // the same world: only what the policy is shown differs
}

TEST(SkillEnv, AStairsSkillSeesTheFirstRiserAheadOfItsSpawn) {
  ai::SkillSpec stairs = *fixture().tree.find("walk");
  stairs.commands.stepCommand = true;
  stairs.terrain.kind = ai::TerrainDef::Kind::Stairs;
  stairs.terrain.startX = 0.5;  // the first riser 0.5 m ahead of the spawn at x = 0 (facing +x within 0.2 rad)
  stairs.terrain.lessons = {0.10};
  ai::SkillSpec blind = stairs;
  blind.commands.stepCommand = false;
  constexpr int kAux0 = robot::kObsCommand + 4, kAux1 = robot::kObsCommand + 5;
  ai::SkillEnv seeing(fixture().model, stairs, fixture().tree.path, envOptions(4, 1, false));
  ai::SkillEnv without(fixture().model, blind, fixture().tree.path, envOptions(4, 1, false));
  Eigen::MatrixXf a, b;
  seeing.reset(3, &a);
  without.reset(3, &b);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(a(kAux0, i), 0.10f, 1e-4f);  // the first step's rise (float rays: to 0.1 mm)
    // 0.5 m / cos(yaw) from x = 0, less the pelvis's few centimetres off the spawn point, to within the 6 mm halving
    EXPECT_GT(a(kAux1, i), 0.45f);
    EXPECT_LT(a(kAux1, i), 0.52f);
    EXPECT_EQ(b(kAux0, i), 0.0f);
    EXPECT_EQ(b(kAux1, i), 0.0f);
  }
}

TEST(SkillEnv, LineJitterStartsEachEpisodeWithinItsBoundsOffTheLine) {
  ai::SkillSpec lined = *fixture().tree.find("walk");
  lined.commands.lineCommand = true;
  lined.lineJitterHeading = 0.3;
  lined.lineJitterOffset = 0.2;
  constexpr int kAux0 = robot::kObsCommand + 4, kAux1 = robot::kObsCommand + 5;
  ai::SkillEnv env(fixture().model, lined, fixture().tree.path, envOptions(8, 1, false));
  Eigen::MatrixXf obs;
  env.reset(4, &obs);
  double turned = 0, moved = 0;
  for (int i = 0; i < 8; ++i) {
    // the line is turned about the start and moved across it: the robot, still where it was, sees both at once
    EXPECT_LE(std::abs(obs(kAux0, i)), 0.3f + 1e-5f);
    EXPECT_LE(std::abs(obs(kAux1, i)), 0.2f + 1e-5f);
    turned = std::max(turned, double(std::abs(obs(kAux0, i))));
    moved = std::max(moved, double(std::abs(obs(kAux1, i))));
  }
  EXPECT_GT(turned, 0.05);  // eight draws of U(-0.3, 0.3) all within 0.05 of 0: chance (1/6)^8
  EXPECT_GT(moved, 0.03);
}

TEST(SkillEnv, LineSteerTurnsTheCommandBackTowardTheLine) {
  // each episode starts off its line (turned up to 0.3 rad, moved up to 0.2 m): after half a second the steered
  // yaw-rate command turns back toward it (its sign against the line error's, heading + 0.5 x offset), within
  // the skill's wz range; without line_steer the yaw-rate command is the draw's, whatever the line
  ai::SkillSpec lined = *fixture().tree.find("walk");
  lined.commands.lineCommand = true;
  lined.draws.turnInPlace = false;
  lined.lineJitterHeading = 0.3;
  lined.lineJitterOffset = 0.2;
  lined.commands.lineSteer = 2.0;
  constexpr int kWz = robot::kObsCommand + 2, kAux0 = robot::kObsCommand + 4, kAux1 = robot::kObsCommand + 5;
  ai::SkillEnv env(fixture().model, lined, fixture().tree.path, envOptions(8, 1, false));
  Eigen::MatrixXf obs;
  env.reset(4, &obs);
  Eigen::VectorXf error(8);
  for (int i = 0; i < 8; ++i) error(i) = obs(kAux0, i) + 0.5f * obs(kAux1, i);
  ai::StepResult r;
  for (int t = 0; t < 50; ++t) env.step(Eigen::MatrixXf::Zero(robot::kActionSize, 8), &r);
  int checked = 0;
  for (int i = 0; i < 8; ++i) {
    const float wz = r.observations(kWz, i);
    EXPECT_LE(std::abs(wz), float(lined.commands.wz.hi) + 1e-6f);
    if (std::abs(error(i)) < 0.05f) continue;  // too near the line for its sign to survive half a second of walking
    ++checked;
    EXPECT_GT(std::abs(wz), 0.05f) << "episode " << i << ", error " << error(i);
    EXPECT_LT(wz * error(i), 0.0f) << "episode " << i << ": wz " << wz << ", error " << error(i);
  }
  EXPECT_GE(checked, 4);
  lined.commands.lineSteer = 0;
  ai::SkillEnv unsteered(fixture().model, lined, fixture().tree.path, envOptions(8, 1, false));
  unsteered.reset(4, &obs);
  for (int t = 0; t < 50; ++t) unsteered.step(Eigen::MatrixXf::Zero(robot::kActionSize, 8), &r);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(r.observations(kWz, i), 0.0f);  // forward or zero draws (no turn in place)
}

TEST(HeadingHold, SquaringToPlusXTurnsBackAtTwiceTheYawWithinTheCap) {
  robot::CommandDef range;
  range.wz = {-0.3, 0.3};                                           // the cap is play's 0.2 rad/s
  EXPECT_DOUBLE_EQ(robot::squareToPlusX(0.05, 2.0, range), -0.10);  // turned left 0.05 rad: turn right at 0.1 rad/s
  EXPECT_DOUBLE_EQ(robot::squareToPlusX(-0.04, 2.0, range), 0.08);
  EXPECT_DOUBLE_EQ(robot::squareToPlusX(0.5, 2.0, range), -0.2);                   // capped
  EXPECT_NEAR(robot::squareToPlusX(2.0 * M_PI + 0.05, 2.0, range), -0.10, 1e-12);  // yaw wrapped first
  EXPECT_DOUBLE_EQ(robot::squareToPlusX(3.0, 2.0, range), -0.2);  // nearly turned round: the short way is right
  range.wz = {-0.1, 0.15};                                        // a narrower range caps at its nearer end
  EXPECT_DOUBLE_EQ(robot::squareToPlusX(-1.0, 2.0, range), 0.1);
}

namespace {

// The yaw-rate commands of n walk episodes (flat ground, spawned facing any way) after 20 ticks at zero action.
std::vector<float> yawRateCommandsAfter20Ticks(const ai::SkillSpec& walk, int n) {
  ai::SkillEnv env(fixture().model, walk, fixture().tree.path, envOptions(n, 1, false));
  Eigen::MatrixXf obs;
  env.reset(5, &obs);
  ai::StepResult r;
  for (int t = 0; t < 20; ++t) env.step(Eigen::MatrixXf::Zero(robot::kActionSize, n), &r);
  std::vector<float> wz(n);
  for (int i = 0; i < n; ++i) wz[i] = r.observations(robot::kObsCommand + 2, i);
  return wz;
}

int atCap(const std::vector<float>& wz, float cap) {
  int n = 0;
  for (float w : wz) n += std::abs(std::abs(w) - cap) < 1e-6f;
  return n;
}

}  // namespace

TEST(SkillEnv, HeadingSteerReplacesTheDrawnTurnWithTheHeadingHold) {
  // flat ground spawns face any way (U(-pi, pi)): nearly every episode is more than 0.1 rad off +X, so the steered
  // command sits at the heading hold's cap (0.2 rad/s) whatever was drawn; unsteered, the walk's draws are not
  ai::SkillSpec walk = *fixture().tree.find("walk");
  walk.headingSteer = 2.0;
  const float cap = float(robot::headingHoldLimit(walk.commands));
  const std::vector<float> steered = yawRateCommandsAfter20Ticks(walk, 8);
  for (float w : steered) EXPECT_LE(std::abs(w), cap + 1e-6f);
  EXPECT_GE(atCap(steered, cap), 6);
  walk.headingSteer = 0;
  EXPECT_LE(atCap(yawRateCommandsAfter20Ticks(walk, 8), cap), 2);
}

TEST(SkillEnv, HeadingSteerShareSteersOnlyThatShareOfEpisodes) {
  // half the episodes steered: of 16 spawned facing any way, the steered ones sit at the heading hold's cap after
  // 20 ticks and (nearly all) the others keep their drawn turns; a binomial(16, 0.5) draw lands well inside [3, 13]
  ai::SkillSpec walk = *fixture().tree.find("walk");
  walk.headingSteer = 2.0;
  walk.headingSteerShare = 0.5;
  const int steered = atCap(yawRateCommandsAfter20Ticks(walk, 16), float(robot::headingHoldLimit(walk.commands)));
  EXPECT_GE(steered, 3);
  EXPECT_LE(steered, 13);
}

TEST(StairsSpawn, PutsThePelvisOnATreadUpTheLandingOrDown) {
  ai::TerrainDef t;  // the stairs skill's staircase: first riser at x = 1, 10 up with a 1 m landing, 9 down
  t.kind = ai::TerrainDef::Kind::Stairs;
  t.steps = 10, t.stepDepth = 0.30, t.startX = 1.0, t.topDepth = 1.0;
  // 19 treads; u picks one with equal odds
  Eigen::Vector2d at = ai::stairsSpawn(t, 0.15, 0.0, 0.5);  // the first: 0.10 m past x = 1, 0.15 m up
  EXPECT_NEAR(at.x(), 1.10, 1e-12);
  EXPECT_NEAR(at.y(), 0.15, 1e-12);
  at = ai::stairsSpawn(t, 0.15, 0.0, 0.0);  // -0.03 m by v
  EXPECT_NEAR(at.x(), 1.07, 1e-12);
  at = ai::stairsSpawn(t, 0.15, 9.5 / 19, 1.0);  // the landing: 3.7 .. 4.7 m, from 3.8 to 4.45
  EXPECT_NEAR(at.x(), 4.45, 1e-12);
  EXPECT_NEAR(at.y(), 1.50, 1e-12);
  at = ai::stairsSpawn(t, 0.15, 0.9999, 1.0);  // the last step down: 4.7 + 8 x 0.3 = 7.1 to 7.4, one rise up
  EXPECT_NEAR(at.x(), 7.23, 1e-12);
  EXPECT_NEAR(at.y(), 0.15, 1e-12);
  at = ai::stairsSpawn(t, 0.15, 12.5 / 19, 0.5);  // the third tread down, 7 rises up: 4.7 + 2 x 0.3 + 0.1
  EXPECT_NEAR(at.x(), 5.40, 1e-12);
  EXPECT_NEAR(at.y(), 1.05, 1e-12);
}

TEST(SkillEnv, SpawnAlongStartsEpisodesStandingOnTheTreadsUpAndDown) {
  ai::SkillSpec stairs = *fixture().tree.find("walk");
  stairs.commands.stepCommand = true;
  stairs.draws.zeroProbability = 1.0;  // standing: only the spawn is watched
  stairs.terrain.kind = ai::TerrainDef::Kind::Stairs;
  stairs.terrain.lessons = {0.10};
  stairs.terrain.spawnAlong = 1.0;
  constexpr int kN = 8, kAux0 = robot::kObsCommand + 4;
  ai::SkillEnv env(fixture().model, stairs, fixture().tree.path, envOptions(kN, 1, false));
  Eigen::MatrixXf obs;
  env.reset(11, &obs);
  int up = 0, down = 0;
  for (int i = 0; i < kN; ++i) {
    // at the foot every robot sees the first riser (+0.10) ahead; on a tread the next rise is one up or one down
    // (the landing: one down, or none within sight)
    const float rise = obs(kAux0, i);
    EXPECT_TRUE(std::abs(std::abs(rise) - 0.10f) < 1e-3f || rise == 0.0f) << rise;
    up += rise > 0.05f, down += rise < -0.05f;
  }
  EXPECT_GT(up, 0);    // 9 of the 19 treads are on the way up, 9 on the way down:
  EXPECT_GT(down, 0);  // eight draws all on one side has odds (10/19)^8 each, and the seed is fixed
  // standing on the tread (not in a box nor above it): nothing falls and the pelvis barely moves up or down
  ai::StepResult r;
  for (int s = 0; s < 25; ++s) {
    env.step(Eigen::MatrixXf::Zero(robot::kActionSize, kN), &r);
    for (int i = 0; i < kN; ++i) {
      EXPECT_EQ(r.terminated[i], 0) << i;
      EXPECT_LT(std::abs(r.observations(robot::kObsLinearVelocity + 2, i)), 0.3f) << "env " << i << " step " << s;
    }
  }
}

namespace {

// a handover into the stairs on levels/steps, 0.8 m before its first riser (x = 11.55, rise 0.10) at y = 2.2, W held
// at 0.3 m/s, released 0.5 s after the entry; the segment 1 s long
robot::EntryState stairsEntry() {
  const robot::RobotModel& model = fixture().model;
  robot::EntryState e;
  e.skill = "stairs";
  e.level = kSource + "/levels/steps";
  e.source = "test";
  e.tick = 1000;
  e.segmentTicks = 100;
  e.body.basePosition = Eigen::Vector3d(10.75, 2.2, model.spawnHeight);
  for (const robot::JointInfo& j : model.joints) e.body.q.push_back(j.defaultPosition);
  e.body.qd.assign(robot::kNumJoints, 0.0);
  for (int j = 0; j < robot::kActionSize; ++j) e.runtime.action[size_t(j)] = 0.01f * float(j);
  e.runtime.phase.tp = 12;
  e.fadingFrom = "walk";
  e.runtime.fadeTicks = 10;
  e.keys.skillRequest = 2;
  e.keys.vx = 0.3;
  e.keys.keysHeld = engine::keyMask('W');
  e.limits.vxForward = 0.5;
  e.events = {{1050, engine::KeyAction::kUp, 'W'}};
  return e;
}

// the shipped tree, copied into a temp folder with the entry beside it, and the stairs as it would read
// `play_share = 1` and `play_entries = "stairs.entries"`, never ending by itself
struct PlayFixture {
  std::string treePath;
  ai::SkillSpec stairs;
  PlayFixture() {
    const std::string dir = testing::TempDir() + "/play_episodes";
    std::filesystem::create_directories(dir);
    treePath = dir + "/tree.toml";
    std::filesystem::copy_file(kSource + "/assets/skills/tree.toml", treePath,
                               std::filesystem::copy_options::overwrite_existing);
    robot::saveEntries(dir + "/stairs.entries", {stairsEntry()});
    stairs = *fixture().tree.find("stairs");
    stairs.playShare = 1.0;
    stairs.playEntries = "stairs.entries";
    stairs.handover = 0;
    neverEnds(&stairs);
  }
};

}  // namespace

TEST(PlayEpisodes, StartWhereTheEntryLeftTheRobotOnItsLevelAndFollowItsKeys) {
  const PlayFixture f;
  ai::SkillEnv env(fixture().model, f.stairs, f.treePath, envOptions(2, 1, false));
  Eigen::MatrixXf obs;
  env.reset(3, &obs);
  const robot::EntryState e = stairsEntry();
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < robot::kNumJoints; ++j) {
      EXPECT_NEAR(obs(robot::kObsJointPosition + j, i), 0.0f, 1e-5f) << j;           // the default pose, as the entry's
      EXPECT_LE(std::abs(obs(robot::kObsJointVelocity + j, i)), 0.1f + 1e-4f) << j;  // its 0 jittered by <= 0.1
      EXPECT_EQ(obs(robot::kObsPreviousAction + j, i), e.runtime.action[size_t(j)]) << j;
    }
    // the keys one tick on: W at 0.3 m/s ramps by 0.02; the level's first riser 0.10 m high, 0.8 m ahead
    EXPECT_NEAR(obs(robot::kObsCommand + 0, i), 0.32f, 1e-6f);
    EXPECT_NEAR(obs(robot::kObsCommand + 4, i), 0.10f, 1e-3f);
    EXPECT_NEAR(obs(robot::kObsCommand + 5, i), 0.8f, 0.02f);
  }
  // W goes up at the entry's tick + 50: by then the command has ramped to the stairs' W speed of 0.5 m/s; it is
  // back at 0 25 ticks later; the episode ends at the segment's end and kPlayEpisodeMarginSeconds (300 ticks)
  ai::StepResult r;
  const Eigen::MatrixXf zero = Eigen::MatrixXf::Zero(robot::kActionSize, 2);
  int endedAt = -1;
  for (int s = 1; s <= 300 && endedAt < 0; ++s) {
    env.step(zero, &r);
    if (s == 48) {
      EXPECT_NEAR(r.observations(robot::kObsCommand, 0), 0.5f, 1e-6f);
    }
    if (s == 80) {
      EXPECT_EQ(r.observations(robot::kObsCommand, 0), 0.0f);
    }
    if (r.truncated[0]) endedAt = s;
  }
  EXPECT_EQ(endedAt, 300);
}

TEST(PlayEpisodes, AnEntriesFileWithoutTheSkillIsRefused) {
  PlayFixture f;
  f.stairs.playEntries = "missing.entries";
  EXPECT_THROW(ai::SkillEnv(fixture().model, f.stairs, f.treePath, envOptions(1, 1, false)), engine::Error);
  robot::EntryState walk = stairsEntry();
  walk.skill = "walk";
  robot::saveEntries(std::filesystem::path(f.treePath).parent_path().string() + "/walk_only.entries", {walk});
  f.stairs.playEntries = "walk_only.entries";
  try {
    ai::SkillEnv env(fixture().model, f.stairs, f.treePath, envOptions(1, 1, false));
    ADD_FAILURE() << "no error";
  } catch (const engine::Error& err) {
    EXPECT_NE(std::string(err.what()).find("walk_only.entries: no handover state into 'stairs'"), std::string::npos)
        << err.what();
  }
}
