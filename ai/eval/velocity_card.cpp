// velocity_card.cpp — measures a velocity card. Episodes run in lock-step batches so the policy is called once per
// tick for all of them; each episode has its own world and RNG, so results do not depend on threads.
#include "ai/eval/velocity_card.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "ai/env/ball_task.h"
#include "ai/env/terrain.h"
#include "ai/eval/card_ranks.h"
#include "ai/rewards/reward_terms.h"
#include "engine/core/error.h"
#include "engine/core/worker_pool.h"
#include "engine/input/command.h"
#include "engine/loop/clock.h"
#include "robot/skill_runtime.h"

namespace ai {
namespace {

double unit(std::mt19937_64& rng) { return double(rng() >> 11) * (1.0 / 9007199254740992.0); }

struct Episode {
  robot::RobotModel model;
  std::unique_ptr<engine::PhysicsWorld> world;
  std::unique_ptr<robot::Robot> robot;
  std::mt19937_64 rng;
  robot::SkillCommand command;
  robot::SkillCommand target;  // this segment's draw; a ramped command heads for it
  robot::SkillState state;     // the runtime: the measured skill's clock and filtered action, a lead-in's fade
  robot::Sensors sensors;
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  Staircase stairs;  // a stairs card's staircase (drawn per episode when the card draws them)
  double downX = 0;  // ... where its way down begins
  bool pushes = true, fallen = false;
  int nextPush = 0, segmentStart = 0;
  double speedError = 0, yawError = 0;
  int counted = 0;
  int alive = 0;                       // ticks survived
  double kindError[4] = {0, 0, 0, 0};  // speed error by command kind: forward/back, sideways, turn, zero
  int kindCount[4] = {0, 0, 0, 0};
  Eigen::Vector3d velocitySum = Eigen::Vector3d::Zero();  // heading-frame vx, vy and wz after the settle time
  double heightError = 0;                                 // sum of |h - h_target(amplitude)| after the settle time
  double amplitudeTarget = 0, amplitudeRate = 0;          // the amplitude ramps as in training (the skill's rate)
  int liftRun = 0, longestLift = 0;
  double maxX = -1e9;       // furthest pelvis x (stairs)
  double headingDown = -1;  // stairs: |heading off +X| when the pelvis first crossed the landing's far edge [rad]
  // jumps: the flight in progress, and the best run of qualifying jumps in a row
  double startHeight = 0, apex = 0;
  int flightTicks = 0, inARow = 0, bestInARow = 0, jumps = 0;
  double bestApex = 0;
  // kick: the ball, where it should go, and the fastest ball speed within the angle
  engine::BallId ball = -1;
  engine::BallState ballState;
  Eigen::Vector2d kickDirection = Eigen::Vector2d::UnitX();
  double bestKick = 0;
  int leadInFalls = 0;           // a lead-in (CardDef::leadIn) drawn again after a fall
  int fallKind = -1;             // command kind active when it fell (0 forward/backward, 1 sideways, 2 turn, 3 zero)
  bool fellAfterPush = false;    // within 2 s of a push
  bool fellAfterChange = false;  // within 2 s of a command change (not counting the first command)
  int fallTick = -1;
  int lastPush = -1000;  // ticks the right sole has been (and was at most) lifted in one go
  // prone: the first tick lying (torso low, pitched face down), whether it still lies at the end, and the
  // largest pelvis acceleration (the impact)
  int proneTick = -1;
  bool lying = false;
  robot::FallCause fallCause = robot::FallCause::None;
  double peakAcceleration = 0;
  Eigen::Vector3d lastVelocity = Eigen::Vector3d::Zero();
};

// what the figures read of an episode: a plain struct, gathered from the ranks that ran the episodes
struct Outcome {
  bool fallen, fellAfterPush, fellAfterChange, lying;
  int counted, alive, kindCount[4], longestLift, bestInARow, jumps, leadInFalls, fallKind, fallTick, proneTick;
  robot::FallCause fallCause;
  double speedError, yawError, heightError, kindError[4], maxX, headingDown, bestApex, bestKick, peakAcceleration;
  double landingFrom, landingTo, stairsEnd;  // stairs: where the landing begins and ends, and the staircase's end (x)
  double x, drift;                           // the pelvis's x at the end, and how far it is from its start (x, y)
};

Outcome outcomeOf(const Episode& e, bool stairs) {
  Outcome o{};
  o.fallen = e.fallen, o.fellAfterPush = e.fellAfterPush, o.fellAfterChange = e.fellAfterChange, o.lying = e.lying;
  o.counted = e.counted, o.alive = e.alive, o.longestLift = e.longestLift, o.bestInARow = e.bestInARow;
  o.jumps = e.jumps, o.leadInFalls = e.leadInFalls, o.fallKind = e.fallKind, o.fallTick = e.fallTick;
  o.proneTick = e.proneTick, o.fallCause = e.fallCause;
  o.speedError = e.speedError, o.yawError = e.yawError, o.heightError = e.heightError, o.maxX = e.maxX;
  o.headingDown = e.headingDown, o.bestApex = e.bestApex, o.bestKick = e.bestKick;
  o.peakAcceleration = e.peakAcceleration;
  for (int k = 0; k < 4; ++k) o.kindCount[k] = e.kindCount[k], o.kindError[k] = e.kindError[k];
  if (stairs) {
    const Eigen::Vector2d landing = stairsLandingX(e.stairs.terrain);
    o.landingFrom = landing.x(), o.landingTo = landing.y(), o.stairsEnd = terrainEndX(e.stairs.terrain);
  }
  o.x = e.sensors.basePosition.x();
  o.drift = (e.sensors.basePosition.head<2>() - e.start).norm();
  return o;
}

// what a batch does: walking episodes randomise friction, mass and pushes and resample commands; standing and
// sweep episodes do neither (a sweep keeps the command each episode was given)
enum class Mode { kWalking, kStanding, kSweep };

double uniform(std::mt19937_64& rng, const robot::Range& r) { return r.lo + (r.hi - r.lo) * unit(rng); }

void sampleCommand(const DrivenCard& card, Episode& e) {
  const robot::SkillCommand now = e.command;  // ramped commands continue from where they are
  e.command = robot::SkillCommand{};
  const double kind = unit(e.rng);
  const std::array<double, 4>& m = card.mix;
  if (kind < m[0])
    e.command.vx = uniform(e.rng, card.vx);
  else if (kind < m[0] + m[1])
    e.command.vy = uniform(e.rng, card.vy);
  else if (kind < m[0] + m[1] + m[2])
    e.command.wz = uniform(e.rng, card.wz);
  if (card.amplitude.hi > 0) {
    e.amplitudeTarget = uniform(e.rng, card.amplitude);
    e.command.amplitude = e.amplitudeRate > 0 ? now.amplitude : e.amplitudeTarget;
  }
  robot::takeCommandDraw(now, card.ramp, &e.command, &e.target);
}

// the kind of a command: 0 forward/backward, 1 sideways, 2 turn, 3 zero
int commandKind(const robot::SkillCommand& c) { return c.vx != 0 ? 0 : c.vy != 0 ? 1 : c.wz != 0 ? 2 : 3; }

// runs a batch of episodes of `ticks` ticks; standing episodes keep a zero command and no pushes
// batchPolicy acts for the batch each tick (policy itself, or policy over the ranks: card_ranks.h); policy is the
// measured skill's as a lead-in hands over to it
void runBatch(const robot::RobotModel& model, const SkillSpec& walk, const PolicyFn& policy,
              const PolicyFn& batchPolicy, const CardDef& o, std::vector<Episode>& eps, int ticks, Mode mode,
              engine::WorkerPool& pool, const std::vector<HandoverStage>& leadIn) {
  const DrivenCard& d = *o.driven();
  const KickCard* kickCard = o.as<KickCard>();  // the kinds whose figures runBatch measures as it goes
  const JumpCard* jumpCard = o.as<JumpCard>();
  const ProneCard* proneCard = o.as<ProneCard>();
  const BalanceCard* balanceCard = o.as<BalanceCard>();
  const StairsCard* stairsCard = o.as<StairsCard>();
  const robot::Skill measured{walk, policy};
  const HandoverRoute route = makeHandoverRoute(leadIn, walk);
  const bool walking = mode == Mode::kWalking;
  const int n = int(eps.size());
  const int segment = int(std::lround(d.segmentSeconds / engine::kTickSeconds));
  const int settle = int(std::lround(d.settleSeconds / engine::kTickSeconds));
  const double pushSeconds = d.pushEverySeconds > 0 ? d.pushEverySeconds : walk.randomisation.pushEverySeconds;
  const int pushEvery = int(std::lround(pushSeconds / engine::kTickSeconds));
  Eigen::MatrixXf obs(robot::kObservationSize, n), act;

  pool.parallelFor(n, [&](int i) {
    Episode& e = eps[size_t(i)];
    e.model = model;
    const double friction = walking
                                ? walk.randomisation.friction.lo +
                                      (walk.randomisation.friction.hi - walk.randomisation.friction.lo) * unit(e.rng)
                                : 1.0;
    if (walking)
      e.model.articulation.base.mass +=
          walk.randomisation.addedMass.lo +
          (walk.randomisation.addedMass.hi - walk.randomisation.addedMass.lo) * unit(e.rng);
    const StairsCard* stairs = o.as<StairsCard>();
    if (stairs) {  // the card's staircase, or one drawn for this episode (drawn only when asked for)
      double u[3] = {0, 0, 0};
      if (stairs->draw.drawn())
        for (double& x : u) x = unit(e.rng);
      e.stairs = drawStaircase(walk.terrain, stairs->draw, stairs->stepHeight, u[0], u[1], u[2]);
      e.downX = stairsLandingX(e.stairs.terrain).y();
    }
    auto place = [&] {
      e.world = std::make_unique<engine::PhysicsWorld>();
      e.world->addGround(friction);
      if (stairs) addTerrain(*e.world, e.stairs.terrain, e.stairs.rise, friction);
      const double yaw = stairs ? stairs->heading * (2 * unit(e.rng) - 1) : M_PI * (2 * unit(e.rng) - 1);
      e.robot = std::make_unique<robot::Robot>(e.model, *e.world, 0, 0, yaw);  // feet 1: the contact gets the draw
      e.sensors = e.robot->sense(*e.world);
    };
    place();
    robot::SkillCommand handedOver;
    robot::enterSkill(&e.state, measured, e.sensors, 0);
    if (walking && !leadIn.empty()) {  // enter the skill as play does (a fallen lead-in is drawn again)
      while (!runHandover(model, e.model, *e.world, *e.robot, &e.sensors, route, e.rng, &e.state, &handedOver)) {
        if (++e.leadInFalls == 5) {
          robot::enterSkill(&e.state, measured, e.sensors, 0);
          e.fallen = true;
          e.fallTick = 0;
          return;
        }
        place();
      }
      e.state.active = &measured;  // the route's last skill, with the measured policy
    }
    if (d.ramp) e.command.vx = handedOver.vx, e.command.vy = handedOver.vy, e.command.wz = handedOver.wz;
    e.start = e.sensors.basePosition.head<2>();
    e.startHeight = e.sensors.basePosition.z();
    e.pushes = walking && d.pushes && pushEvery > 0;
    e.nextPush = pushEvery;
    e.amplitudeRate = walk.draws.amplitudeRate;
    if (walking) sampleCommand(d, e);
    if (o.kind() == CardKind::Kick && walk.ball.enabled) {
      e.ball = placeBall(*e.world, walk.ball, e.sensors, e.rng, &e.kickDirection);
      e.ballState = e.world->ballState(e.ball);
      ballIntoCommand(e.sensors, e.ballState, &e.command);
    }
  });

  for (int t = 0; t < ticks; ++t) {
    for (int i = 0; i < n; ++i) {
      Episode& e = eps[size_t(i)];
      if (!e.fallen) {  // the command moves one tick toward its draw, then the skill observes it (as play's keys)
        if (e.amplitudeRate > 0) {
          const double step = e.amplitudeRate * engine::kTickSeconds;
          e.command.amplitude += std::clamp(e.amplitudeTarget - e.command.amplitude, -step, step);
        }
        if (walking && d.ramp) {
          const engine::CommandLimits keys;  // the keyboard's rates
          engine::rampVelocityCommand(e.target.vx, e.target.vy, e.target.wz, keys.vRate, keys.wzRate, &e.command.vx,
                                      &e.command.vy, &e.command.wz);
        }
      }
      robot::observe(model, e.state, e.sensors, *e.world, e.command, obs.col(i).data());
    }
    batchPolicy(obs, &act);
    pool.parallelFor(n, [&](int i) {
      Episode& e = eps[size_t(i)];
      if (e.fallen) return;
      robot::PdCommand pd;
      robot::act(e.model, &e.state, act.col(i).data(), e.command, false, &pd);
      e.robot->setCommand(pd);
      robot::stepPhysicsTick(*e.robot, *e.world);
      e.sensors = e.robot->sense(*e.world);
      if (stairsCard && stairsCard->steer > 0) {
        // a player keeping the robot square to the staircase (it runs along +X), with play's heading-hold law
        // (robot::shapeCommand's heading hold): steer x the heading error, at most kHeadingMaxRate and the skill's wz
        // range
        e.command.wz = robot::squareToPlusX(e.sensors.yaw, stairsCard->steer, walk.commands);
      }
      const int tick = t + 1;
      ++e.alive;
      if (robot::fallCause(walk.termination, e.sensors) != robot::FallCause::None) {
        e.fallen = true;
        e.fallKind = commandKind(walking ? e.target : e.command);  // what the segment asks for
        e.fellAfterPush = tick - e.lastPush <= 200;
        e.fellAfterChange = e.segmentStart > 0 && tick - e.segmentStart <= 200;
        e.fallTick = tick;
        e.fallCause = robot::fallCause(walk.termination, e.sensors);
        return;
      }
      if (mode != Mode::kStanding && tick - e.segmentStart > settle) {
        // velocity in the heading frame (yaw only), compared with the command
        const double yaw = e.sensors.yaw;
        const Eigen::Vector3d vWorld = e.sensors.baseRotation * e.sensors.linearVelocity;
        const Eigen::Vector2d v(std::cos(yaw) * vWorld.x() + std::sin(yaw) * vWorld.y(),
                                -std::sin(yaw) * vWorld.x() + std::cos(yaw) * vWorld.y());
        const double err = (v - Eigen::Vector2d(e.command.vx, e.command.vy)).norm();
        e.speedError += err;
        const int kind = commandKind(walking ? e.target : e.command);
        e.kindError[kind] += err;
        ++e.kindCount[kind];
        const double wz = (e.sensors.baseRotation * e.sensors.angularVelocity).z();
        e.yawError += std::abs(wz - e.command.wz);
        e.velocitySum += Eigen::Vector3d(v.x(), v.y(), wz);
        e.heightError += std::abs(e.sensors.basePosition.z() - targetPelvisHeight(walk, e.command.amplitude));
        ++e.counted;
      }
      e.maxX = std::max(e.maxX, e.sensors.basePosition.x());
      if (stairsCard && e.headingDown < 0 && e.sensors.basePosition.x() > e.downX)
        e.headingDown = std::abs(std::remainder(e.sensors.yaw, 2.0 * M_PI));
      if (e.ball >= 0) {
        e.ballState = e.world->ballState(e.ball);
        ballIntoCommand(e.sensors, e.ballState, &e.command);
        const Eigen::Vector2d v = e.ballState.velocity.head<2>();
        const double along = v.dot(e.kickDirection);
        const double angle = std::atan2(std::abs(v.x() * e.kickDirection.y() - v.y() * e.kickDirection.x()), along);
        if (kickCard && along > 0 && angle <= kickCard->angleDegrees * M_PI / 180.0)
          e.bestKick = std::max(e.bestKick, v.norm());
      }
      if (!e.sensors.footContact[0] && !e.sensors.footContact[1]) {
        ++e.flightTicks;
        e.apex = std::max(e.apex, e.sensors.basePosition.z());
      } else if (e.flightTicks > 0) {  // landed: was it a jump?
        const bool counts = jumpCard && e.flightTicks >= 3 && e.apex - e.startHeight >= jumpCard->height;
        e.jumps += counts;
        e.inARow = counts ? e.inARow + 1 : 0;
        e.bestInARow = std::max(e.bestInARow, e.inARow);
        e.bestApex = std::max(e.bestApex, e.apex - e.startHeight);
        e.flightTicks = 0;
        e.apex = 0;
      }
      if (proneCard) {
        const Eigen::Vector3d v = e.sensors.baseRotation * e.sensors.linearVelocity;
        if (tick > 1)
          e.peakAcceleration = std::max(e.peakAcceleration, (v - e.lastVelocity).norm() / engine::kTickSeconds);
        e.lastVelocity = v;
        const double pitch = robot::forwardPitch(e.sensors) * 180.0 / M_PI;
        const double torsoHeight = e.robot->linkPose(*e.world, model.torso).translation().z();
        e.lying = torsoHeight < proneCard->height && pitch >= proneCard->pitch.lo && pitch <= proneCard->pitch.hi;
        if (e.lying && e.proneTick < 0) e.proneTick = tick;
      }
      // lifted: on the left foot alone, the right sole at least liftHeight up (a folded leg's toe resting on the
      // ground does not count, however high the ankle is)
      const bool lifted = balanceCard && e.sensors.footHeight[1] >= balanceCard->liftHeight &&
                          e.sensors.footContact[0] && !e.sensors.footContact[1];
      e.liftRun = lifted ? e.liftRun + 1 : 0;
      e.longestLift = std::max(e.longestLift, e.liftRun);
      if (e.pushes && tick >= e.nextPush) {
        engine::ArticulationState s;
        e.world->readState(e.robot->id(), &s);
        const double angle = 2 * M_PI * unit(e.rng);
        const robot::Range& ps = d.pushSpeed.lo >= 0 ? d.pushSpeed : walk.randomisation.pushSpeed;
        const double speed = ps.lo + (ps.hi - ps.lo) * unit(e.rng);
        s.baseLinearVelocity += Eigen::Vector3d(std::cos(angle), std::sin(angle), 0) * speed;
        e.world->setState(e.robot->id(), s);
        e.nextPush += pushEvery;
        e.lastPush = tick;
      }
      if (walking && tick % segment == 0 && tick < ticks) {
        sampleCommand(d, e);
        if (e.ball >= 0) ballIntoCommand(e.sensors, e.ballState, &e.command);
        e.segmentStart = tick;
      }
    });
  }
}

}  // namespace

CardResult runVelocityCard(const robot::RobotModel& model, const SkillSpec& skill, const PolicyFn& policy,
                           const CardRun& run, const std::vector<HandoverStage>& leadIn) {
  const CardDef& o = run.card;
  if (!o.driven())
    throw engine::Error("velocity card of '" + skill.name + "': a standup, pushup or crawl card runs as a ground card");
  const DrivenCard& d = *o.driven();
  engine::WorkerPool pool(run.threads);
  std::mt19937_64 seeder(run.seed);
  const dist::Comm& comm = dist::orOneProcess(run.comm);
  const bool onStairs = o.as<StairsCard>() != nullptr;

  // every episode's seed, as one process draws them; this rank runs its share, and the outcomes of all are gathered
  std::vector<uint64_t> walkingSeeds(size_t(o.episodes)), standingSeeds(size_t(d.standEpisodes));
  for (uint64_t& s : walkingSeeds) s = seeder();
  for (uint64_t& s : standingSeeds) s = seeder();
  auto runShare = [&](const std::vector<uint64_t>& seeds, double seconds, Mode mode,
                      const std::vector<HandoverStage>& stages) {
    const EpisodeShare share = episodeShare(int(seeds.size()), comm);
    std::vector<Episode> mine(size_t(share.count));
    for (int k = 0; k < share.count; ++k) mine[size_t(k)].rng.seed(seeds[size_t(share.first + k)]);
    runBatch(model, skill, policy, policyOverRanks(policy, comm, int(seeds.size())), o, mine,
             int(std::lround(seconds / engine::kTickSeconds)), mode, pool, stages);
    std::vector<Outcome> outcomes;
    for (const Episode& e : mine) outcomes.push_back(outcomeOf(e, onStairs));
    return gatherOutcomes(outcomes, comm);
  };
  const std::vector<Outcome> walking = runShare(walkingSeeds, d.episodeSeconds, Mode::kWalking, leadIn);
  const std::vector<Outcome> standing = runShare(standingSeeds, d.standSeconds, Mode::kStanding, {});

  double kindError[4] = {0, 0, 0, 0};
  long kindCount[4] = {0, 0, 0, 0};
  int upright = 0;
  double speed = 0, yaw = 0, survival = 0, height = 0;
  const double walkTicks = std::lround(d.episodeSeconds / engine::kTickSeconds);
  long counted = 0;
  for (const Outcome& e : walking) {
    upright += !e.fallen;
    speed += e.speedError;
    yaw += e.yawError;
    height += e.heightError;
    counted += e.counted;
    for (int k = 0; k < 4; ++k) {
      kindError[k] += e.kindError[k];
      kindCount[k] += e.kindCount[k];
    }
    survival += e.alive / walkTicks / std::max(1, o.episodes);
  }
  double drift = 0;
  int standFalls = 0;
  for (const Outcome& e : standing) {
    drift = std::max(drift, e.drift);
    standFalls += e.fallen;
  }
  CardResult r;
  auto bar = [](double v, const char* unit) {
    char b[48];
    std::snprintf(b, sizeof b, "%s %g %s", unit[0] == '%' ? ">=" : "<=", v, unit);
    return std::string(b);
  };
  const double noFall = 100.0 * upright / std::max(1, o.episodes);
  const double meanSpeed = counted ? speed / double(counted) : 1e9;
  const double meanYaw = counted ? yaw / double(counted) : 1e9;
  // a figure with a bar is checked; the others are reported
  auto add = [&](const std::string& name, double value, double limit, const char* unit, bool atLeast) {
    if (limit < 0)
      r.figures.push_back({name, value, "(reported)", true});
    else
      r.figures.push_back({name, value, bar(limit, unit), atLeast ? value >= limit : value <= limit});
  };
  add("episodes without a fall", noFall, d.noFallPercent, "%", true);
  // tracking figures belong to the skills that move on command (and to any card that puts a bar on them)
  const bool moves = o.kind() == CardKind::Velocity || o.kind() == CardKind::Stairs;
  if (moves || d.speedError >= 0) add("mean |v - v_cmd|", meanSpeed, d.speedError, "m/s", false);
  if (moves || d.yawError >= 0) add("mean |wz - wz_cmd|", meanYaw, d.yawError, "rad/s", false);
  const double meanHeight = counted ? height / double(counted) : 1e9;
  if (!leadIn.empty()) {  // how often the way in (not the skill) fell and was drawn again
    int again = 0, lost = 0;
    for (const Outcome& e : walking) again += e.leadInFalls, lost += e.leadInFalls >= 5;
    r.figures.push_back({"lead-ins that fell and were drawn again (5 in a row: the episode counts as a fall)",
                         double(again), "(reported)", true});
    if (lost > 0) r.figures.push_back({"episodes lost to their lead-in", double(lost), "(reported)", true});
  }
  double balanceScore = 0;
  if (const KickCard* kick = o.as<KickCard>()) {
    int success = 0;
    double best = 0;
    for (const Outcome& e : walking) {
      success += !e.fallen && e.bestKick >= kick->speed;
      best += e.bestKick / std::max(1, o.episodes);
    }
    char name[96];
    std::snprintf(name, sizeof name, "kicks >= %.1f m/s within %.0f deg, robot up", kick->speed, kick->angleDegrees);
    add(name, 100.0 * success / std::max(1, o.episodes), o.successPercent, "%", true);
    r.figures.push_back({"mean ball speed within the angle [m/s]", best, "(reported)", true});
    balanceScore = 2.0 * success / std::max(1, o.episodes) + std::min(best, kick->speed) / std::max(0.1, kick->speed);
  }
  if (const JumpCard* jump = o.as<JumpCard>()) {
    int success = 0;
    double jumps = 0, apex = 0;
    for (const Outcome& e : walking) {
      success += !e.fallen && e.bestInARow >= jump->jumps;
      jumps += double(e.jumps) / std::max(1, o.episodes);
      apex += e.bestApex / std::max(1, o.episodes);
    }
    char name[96];
    std::snprintf(name, sizeof name, "episodes with %d jumps >= %.2f m in a row", jump->jumps, jump->height);
    add(name, 100.0 * success / std::max(1, o.episodes), o.successPercent, "%", true);
    r.figures.push_back({"mean qualifying jumps per episode", jumps, "(reported)", true});
    r.figures.push_back({"mean best apex above start [m]", apex, "(reported)", true});
    balanceScore = 2.0 * success / std::max(1, o.episodes) + std::min(jumps, double(jump->jumps)) / jump->jumps +
                   5.0 * std::min(apex, 0.2);
  }
  if (const StairsCard* stairs = o.as<StairsCard>()) {
    int across = 0;
    double progress = 0;
    for (const Outcome& e : walking) {
      const double end = e.stairsEnd;
      across += !e.fallen && e.maxX > end;
      progress += std::clamp(e.maxX / end, 0.0, 1.0) / std::max(1, o.episodes);
    }
    char name[160];
    if (stairs->draw.drawn())
      std::snprintf(name, sizeof name, "episodes up and down %g-%g steps of %.2f-%.2f m x %.2f-%.2f m",
                    stairs->draw.steps.lo, stairs->draw.steps.hi, stairs->draw.rise.lo, stairs->draw.rise.hi,
                    stairs->draw.tread.lo, stairs->draw.tread.hi);
    else
      std::snprintf(name, sizeof name, "episodes up and down %d steps of %.2f m", skill.terrain.steps,
                    stairs->stepHeight);
    add(name, 100.0 * across / std::max(1, o.episodes), o.successPercent, "%", true);
    r.figures.push_back({"mean progress along the stairs", 100.0 * progress, "(reported) %", true});
    double heading = 0;
    int down = 0;
    for (const Outcome& e : walking)
      if (e.headingDown >= 0) heading += e.headingDown * 180.0 / M_PI, ++down;
    if (down > 0)  // (no figure when no episode got there: a 0 would read as squared up)
      r.figures.push_back(
          {"heading off the stairs where the way down begins, mean of |.| [deg]", heading / down, "(reported)", true});
    balanceScore = 2.0 * across / std::max(1, o.episodes) + 2.0 * progress;
  }
  if (const BalanceCard* balance = o.as<BalanceCard>()) {
    int success = 0;
    double longest = 0;
    for (const Outcome& e : walking) {
      success += !e.fallen && e.longestLift * engine::kTickSeconds >= balance->liftSeconds;
      longest += e.longestLift * engine::kTickSeconds / std::max(1, o.episodes);
    }
    char name[96];
    std::snprintf(name, sizeof name, "episodes lifted >= %.2f m for %.0f s", balance->liftHeight, balance->liftSeconds);
    add(name, 100.0 * success / std::max(1, o.episodes), o.successPercent, "%", true);
    r.figures.push_back({"mean longest lift [s]", longest, "(reported)", true});
    balanceScore = 2.0 * success / std::max(1, o.episodes) + longest / std::max(1.0, balance->liftSeconds);
  }
  if (const ProneCard* prone = o.as<ProneCard>()) {
    int success = 0, reached = 0;
    double seconds = 0, peak = 0, meanPeak = 0;
    const int limit = int(std::lround(prone->seconds / engine::kTickSeconds));
    for (const Outcome& e : walking) {
      const bool inTime = e.proneTick >= 0 && e.proneTick <= limit;
      success += !e.fallen && inTime && e.lying;
      if (e.proneTick >= 0) ++reached, seconds += e.proneTick * engine::kTickSeconds;
      peak = std::max(peak, e.peakAcceleration);
      meanPeak += e.peakAcceleration / std::max(1, o.episodes);
    }
    char name[128];
    std::snprintf(name, sizeof name,
                  "episodes lying (torso < %.2f m, pitch %.0f-%.0f deg) within %.1f s and at the end", prone->height,
                  prone->pitch.lo, prone->pitch.hi, prone->seconds);
    add(name, 100.0 * success / std::max(1, o.episodes), o.successPercent, "%", true);
    r.figures.push_back({"mean time to lying [s]", reached ? seconds / reached : 1e9, "(reported)", true});
    int side = 0, back = 0, over = 0;
    double fallSeconds = 0;
    for (const Outcome& e : walking) {
      if (!e.fallen) continue;
      side += e.fallCause == robot::FallCause::Side;
      back += e.fallCause == robot::FallCause::Back;
      over += e.fallCause == robot::FallCause::OverHead;
      fallSeconds += e.fallTick * engine::kTickSeconds;
    }
    if (upright < o.episodes) {
      std::snprintf(name, sizeof name, "  falls: onto a side %d, onto the back %d, over the head %d; mean time %.2f s",
                    side, back, over, fallSeconds / std::max(1, o.episodes - upright));
      r.figures.push_back({name, double(o.episodes - upright), "(reported)", true});
    }
    r.figures.push_back({"peak impact: pelvis acceleration, mean of episodes [m/s^2]", meanPeak, "(reported)", true});
    r.figures.push_back({"peak impact: pelvis acceleration, largest [m/s^2]", peak, "(reported)", true});
    balanceScore = 2.0 * success / std::max(1, o.episodes) + double(reached) / std::max(1, o.episodes) -
                   std::min(meanPeak, 500.0) / 500.0;
  }
  if (o.kind() == CardKind::Height)
    add("mean |h - h_target| (pelvis)", meanHeight, o.as<HeightCard>()->heightError, "m", false);
  const char* kinds[4] = {"  of which forward/backward", "  of which sideways", "  of which turning",
                          "  of which zero command"};
  for (int k = 0; k < 4; ++k)
    if (moves && kindCount[k] && d.mix[size_t(k)] < 1.0)
      r.figures.push_back({kinds[k], kindError[k] / double(kindCount[k]), "(reported)", true});
  r.figures.push_back({"mean time survived (of each episode)", 100.0 * survival, "(reported) %", true});
  if (moves && upright < o.episodes) {
    int byKind[4] = {0, 0, 0, 0}, afterPush = 0, afterChange = 0;
    for (const Outcome& e : walking)
      if (e.fallen) ++byKind[e.fallKind], afterPush += e.fellAfterPush, afterChange += e.fellAfterChange;
    char name[160];
    std::snprintf(name, sizeof name,
                  "  falls: fwd/back %d, side %d, turn %d, zero %d; <2 s after a push %d, <2 s after a change %d",
                  byKind[0], byKind[1], byKind[2], byKind[3], afterPush, afterChange);
    r.figures.push_back({name, double(o.episodes - upright), "(reported)", true});
    // when: falls per command segment of the episode
    const int segmentTicks = std::max(1, int(std::lround(d.segmentSeconds / engine::kTickSeconds)));
    const int segments = std::max(1, int(std::ceil(d.episodeSeconds / std::max(1e-9, d.segmentSeconds) - 1e-9)));
    std::vector<int> bySegment(size_t(segments), 0);
    for (const Outcome& e : walking)
      if (e.fallen) ++bySegment[size_t(std::min(segments - 1, (e.fallTick - 1) / segmentTicks))];
    std::string when = "  falls per command segment:";
    for (int k = 0; k < segments; ++k) when += (k ? ", " : " ") + std::to_string(bySegment[size_t(k)]);
    r.figures.push_back({when, double(o.episodes - upright), "(reported)", true});
    if (o.as<StairsCard>()) {          // where: by the pelvis's x when it fell
      int where[5] = {0, 0, 0, 0, 0};  // before, up, landing, down, beyond
      for (const Outcome& e : walking) {
        if (!e.fallen) continue;
        const double x = e.x;
        ++where[x < skill.terrain.startX ? 0 : x < e.landingFrom ? 1 : x < e.landingTo ? 2 : x < e.stairsEnd ? 3 : 4];
      }
      char at[160];
      std::snprintf(at, sizeof at, "  falls by place: before the stairs %d, up %d, landing %d, down %d, beyond %d",
                    where[0], where[1], where[2], where[3], where[4]);
      r.figures.push_back({at, double(o.episodes - upright), "(reported)", true});
    }
  }
  if (d.standEpisodes > 0) {
    const double most = standFalls ? 1e9 : drift;
    r.figures.push_back({"zero command: max drift over " + std::to_string(int(d.standSeconds)) + " s", most,
                         d.standDrift < 0 ? "(reported)" : "< " + std::to_string(d.standDrift).substr(0, 4) + " m",
                         d.standDrift < 0 || most < d.standDrift});
  }
  r.pass = true;
  for (const CardFigure& f : r.figures) r.pass = r.pass && f.pass;
  // survival counts twice so that a policy cannot score by falling before tracking errors accumulate
  r.score = 2.0 * survival + noFall / 100.0 - std::min(meanSpeed, 2.0) - 0.5 * std::min(meanYaw, 2.0) -
            (o.kind() == CardKind::Height ? 5.0 * std::min(meanHeight, 1.0) : 0.0) -
            (d.standEpisodes == 0 ? 0.0
             : standFalls         ? 1.0
                                  : std::min(drift, 1.0)) +
            balanceScore;
  return r;
}

std::vector<SweepRow> runSpeedSweep(const robot::RobotModel& model, const SkillSpec& walk, const PolicyFn& policy,
                                    const std::vector<robot::SkillCommand>& commands, double seconds, int threads) {
  engine::WorkerPool pool(threads);
  std::vector<Episode> eps(commands.size());
  for (size_t i = 0; i < eps.size(); ++i) {
    eps[i].rng.seed(i + 1);  // only the spawn heading is random
    eps[i].command = commands[i];
  }
  CardDef o;
  o.card = VelocityCard{};
  o.driven()->segmentSeconds = seconds + 1;
  runBatch(model, walk, policy, policy, o, eps, int(std::lround(seconds / engine::kTickSeconds)), Mode::kSweep, pool,
           {});
  std::vector<SweepRow> rows;
  for (const Episode& e : eps) {
    SweepRow r;
    r.command = e.command;
    r.fell = e.fallen;
    r.secondsUp = e.alive * engine::kTickSeconds;
    r.mean = e.counted ? Eigen::Vector3d(e.velocitySum / double(e.counted)) : Eigen::Vector3d::Zero();
    rows.push_back(r);
  }
  return rows;
}

}  // namespace ai
