// walk_card.cpp — measures the walk card. Episodes run in lock-step batches so the policy is called once per
// tick for all of them; each episode has its own world and RNG, so results do not depend on threads.
#include "ai/eval/walk_card.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "ai/env/worker_pool.h"
#include "engine/loop/clock.h"
#include "game/session.h"
#include "robot/skill_controller.h"

namespace ai {
namespace {

double unit(std::mt19937_64& rng) { return double(rng() >> 11) * (1.0 / 9007199254740992.0); }

struct Episode {
  robot::RobotModel model;
  std::unique_ptr<engine::PhysicsWorld> world;
  std::unique_ptr<robot::Robot> robot;
  std::mt19937_64 rng;
  robot::SkillCommand command;
  robot::PhaseClock phase;
  std::array<float, robot::kActionSize> action{};
  robot::Sensors sensors;
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  bool pushes = true, fallen = false;
  int nextPush = 0, segmentStart = 0;
  double speedError = 0, yawError = 0;
  int counted = 0;
  int alive = 0;  // ticks survived
  double kindError[4] = {0, 0, 0, 0};  // speed error by command kind: forward/back, sideways, turn, zero
  int kindCount[4] = {0, 0, 0, 0};
};

void sampleCommand(Episode& e) {
  e.command = robot::SkillCommand{};
  const double kind = unit(e.rng);
  if (kind < 0.4) e.command.vx = -0.6 + 1.8 * unit(e.rng);
  else if (kind < 0.6) e.command.vy = -0.4 + 0.8 * unit(e.rng);
  else if (kind < 0.8) e.command.wz = -1.0 + 2.0 * unit(e.rng);
}

// runs a batch of episodes of `ticks` ticks; standing episodes keep a zero command and no pushes
void runBatch(const robot::RobotModel& model, const robot::SkillDef& walk, const PolicyFn& policy,
              const WalkCardOptions& o, std::vector<Episode>& eps, int ticks, bool walking, WorkerPool& pool) {
  const int n = int(eps.size());
  const int segment = int(std::lround(o.segmentSeconds / engine::kTickSeconds));
  const int settle = int(std::lround(o.settleSeconds / engine::kTickSeconds));
  const int pushEvery = int(std::lround(walk.randomisation.pushEverySeconds / engine::kTickSeconds));
  const double maxTilt = walk.termination.maxTiltDegrees * M_PI / 180.0;
  Eigen::MatrixXf obs(robot::kObservationSize, n), act;

  pool.parallelFor(n, [&](int i) {
    Episode& e = eps[size_t(i)];
    e.model = model;
    const double friction = walking ? walk.randomisation.friction.lo +
                                          (walk.randomisation.friction.hi - walk.randomisation.friction.lo) * unit(e.rng)
                                    : 1.0;
    if (walking)
      e.model.articulation.base.mass +=
          walk.randomisation.addedMass.lo + (walk.randomisation.addedMass.hi - walk.randomisation.addedMass.lo) * unit(e.rng);
    e.world = std::make_unique<engine::PhysicsWorld>();
    e.world->addGround(friction);
    e.robot = std::make_unique<robot::Robot>(e.model, *e.world, 0, 0, M_PI * (2 * unit(e.rng) - 1), friction);
    e.sensors = e.robot->sense(*e.world);
    e.start = e.sensors.basePosition.head<2>();
    e.pushes = walking && pushEvery > 0;
    e.nextPush = pushEvery;
    if (walking) sampleCommand(e);
  });

  for (int t = 0; t < ticks; ++t) {
    for (int i = 0; i < n; ++i) {
      const Episode& e = eps[size_t(i)];
      double s, c;
      robot::phaseSignal(e.phase.tp, walk.prior.halfPeriodTicks, &s, &c);
      robot::Observation ob;
      robot::buildObservation(e.sensors, model, e.action, e.command, s, c, &ob);
      for (int k = 0; k < robot::kObservationSize; ++k) obs(k, i) = ob[size_t(k)];
    }
    policy(obs, &act);
    pool.parallelFor(n, [&](int i) {
      Episode& e = eps[size_t(i)];
      if (e.fallen) return;
      robot::filterAction(walk, act.col(i).data(), &e.action);
      e.phase.advance(walk.prior.halfPeriodTicks);
      robot::PdCommand pd;
      robot::skillPdCommand(e.model, walk, e.action, e.phase.tp, e.command, &pd);
      e.robot->setCommand(pd);
      for (int k = 0; k < game::kSubsteps; ++k) {
        e.robot->applyPd(*e.world);
        e.world->step(game::kSubstepSeconds);
      }
      e.sensors = e.robot->sense(*e.world);
      const int tick = t + 1;
      ++e.alive;
      if (std::abs(e.sensors.roll) > maxTilt || std::abs(e.sensors.pitch) > maxTilt ||
          e.sensors.basePosition.z() < walk.termination.minHeight) {
        e.fallen = true;
        return;
      }
      if (walking && tick - e.segmentStart > settle) {
        // velocity in the heading frame (yaw only), compared with the command
        const double yaw = e.sensors.yaw;
        const Eigen::Vector3d vWorld = e.sensors.baseRotation * e.sensors.linearVelocity;
        const Eigen::Vector2d v(std::cos(yaw) * vWorld.x() + std::sin(yaw) * vWorld.y(),
                                -std::sin(yaw) * vWorld.x() + std::cos(yaw) * vWorld.y());
        const double err = (v - Eigen::Vector2d(e.command.vx, e.command.vy)).norm();
        e.speedError += err;
        const int kind = e.command.vx != 0 ? 0 : e.command.vy != 0 ? 1 : e.command.wz != 0 ? 2 : 3;
        e.kindError[kind] += err;
        ++e.kindCount[kind];
        const double wz = (e.sensors.baseRotation * e.sensors.angularVelocity).z();
        e.yawError += std::abs(wz - e.command.wz);
        ++e.counted;
      }
      if (e.pushes && tick >= e.nextPush) {
        engine::ArticulationState s;
        e.world->readState(e.robot->id(), &s);
        const double angle = 2 * M_PI * unit(e.rng);
        const auto& ps = walk.randomisation.pushSpeed;
        const double speed = ps.lo + (ps.hi - ps.lo) * unit(e.rng);
        s.baseLinearVelocity += Eigen::Vector3d(std::cos(angle), std::sin(angle), 0) * speed;
        e.world->setState(e.robot->id(), s);
        e.nextPush += pushEvery;
      }
      if (walking && tick % segment == 0 && tick < ticks) {
        sampleCommand(e);
        e.segmentStart = tick;
      }
    });
  }
}

}  // namespace

CardResult runWalkCard(const robot::RobotModel& model, const robot::SkillDef& walk, const PolicyFn& policy,
                       const WalkCardOptions& o) {
  WorkerPool pool(o.threads);
  std::mt19937_64 seeder(o.seed);

  std::vector<Episode> walking(size_t(o.episodes));
  for (Episode& e : walking) e.rng.seed(seeder());
  runBatch(model, walk, policy, o, walking, int(std::lround(o.episodeSeconds / engine::kTickSeconds)), true, pool);
  std::vector<Episode> standing(size_t(o.standEpisodes));
  for (Episode& e : standing) e.rng.seed(seeder());
  runBatch(model, walk, policy, o, standing, int(std::lround(o.standSeconds / engine::kTickSeconds)), false, pool);

  double kindError[4] = {0, 0, 0, 0};
  long kindCount[4] = {0, 0, 0, 0};
  int upright = 0;
  double speed = 0, yaw = 0, survival = 0;
  const double walkTicks = std::lround(o.episodeSeconds / engine::kTickSeconds);
  long counted = 0;
  for (const Episode& e : walking) {
    upright += !e.fallen;
    speed += e.speedError;
    yaw += e.yawError;
    counted += e.counted;
    for (int k = 0; k < 4; ++k) {
      kindError[k] += e.kindError[k];
      kindCount[k] += e.kindCount[k];
    }
    survival += e.alive / walkTicks / std::max(1, o.episodes);
  }
  double drift = 0;
  int standFalls = 0;
  for (const Episode& e : standing) {
    drift = std::max(drift, (e.sensors.basePosition.head<2>() - e.start).norm());
    standFalls += e.fallen;
  }
  CardResult r;
  const double noFall = 100.0 * upright / std::max(1, o.episodes);
  const double meanSpeed = counted ? speed / double(counted) : 1e9;
  const double meanYaw = counted ? yaw / double(counted) : 1e9;
  r.figures.push_back({"episodes without a fall", noFall, ">= 95 %", noFall >= 95.0});
  r.figures.push_back({"mean |v - v_cmd|", meanSpeed, "<= 0.15 m/s", meanSpeed <= 0.15});
  r.figures.push_back({"mean |wz - wz_cmd|", meanYaw, "<= 0.2 rad/s", meanYaw <= 0.2});
  const char* kinds[4] = {"  of which forward/backward", "  of which sideways", "  of which turning", "  of which zero command"};
  for (int k = 0; k < 4; ++k)
    r.figures.push_back({kinds[k], kindCount[k] ? kindError[k] / double(kindCount[k]) : 0.0, "(reported)", true});
  r.figures.push_back({"mean time survived (of each episode)", 100.0 * survival, "(reported)", true});
  r.figures.push_back({"zero command: max drift over 10 s", standFalls ? 1e9 : drift, "< 0.2 m", !standFalls && drift < 0.2});
  r.pass = true;
  for (const CardFigure& f : r.figures) r.pass = r.pass && f.pass;
  // survival counts twice so that a policy cannot score by falling before tracking errors accumulate
  r.score = 2.0 * survival + noFall / 100.0 - std::min(meanSpeed, 2.0) - 0.5 * std::min(meanYaw, 2.0) - (standFalls ? 1.0 : std::min(drift, 1.0));
  return r;
}

}  // namespace ai
