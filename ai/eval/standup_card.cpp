// standup_card.cpp — measures a standup card: lie down under the parent, stand up, hand over to the up skill.
#include "ai/eval/standup_card.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "ai/env/worker_pool.h"
#include "engine/core/error.h"
#include "engine/loop/clock.h"
#include "game/session.h"
#include "robot/skill_controller.h"

namespace ai {
namespace {

double unit(std::mt19937_64& rng) { return double(rng() >> 11) * (1.0 / 9007199254740992.0); }

enum Stage { kLying = 0, kRising = 1, kAfter = 2, kDone = 3 };

struct Episode {
  robot::RobotModel model;
  std::unique_ptr<engine::PhysicsWorld> world;
  std::unique_ptr<robot::Robot> robot;
  std::mt19937_64 rng;
  robot::Sensors sensors;
  robot::PhaseClock phase, fadePhase;
  std::array<float, robot::kActionSize> action{};
  const robot::SkillDef* driving = nullptr;  // the skill in control
  const robot::SkillDef* fadingFrom = nullptr;
  int fadeTicks = 0;
  Stage stage = kLying;
  int stageTick = 0;    // ticks in the current stage
  int lieTicks = 0;     // drawn: how long the parent lies down
  bool lyingAtSwitch = false;
  int standTick = -1;   // ticks after the switch to the stand-up when the robot first stood (-1: never) ...
  int handOverTick = -1;  // ... and when it had settled there and the up skill took over
  Stage fellIn = kDone;  // where it fell (kDone: it did not)
  robot::FallCause fallCause = robot::FallCause::None;
};

// the switch as the runtime makes it (game::Session::switchTo): the action carries over, the gait clock is
// carried (a keyframes prior starts from its first key) and the old prior fades out on its own clock
void switchSkill(Episode& e, const robot::SkillDef& to) {
  e.fadePhase = e.phase;
  robot::carryPhase(e.driving->prior, to.prior, &e.phase);
  e.fadingFrom = e.driving;
  e.fadeTicks = robot::kSwitchFadeTicks;
  e.driving = &to;
  e.stageTick = 0;
}

}  // namespace

CardResult runStandUpCard(const robot::RobotModel& model, const robot::SkillDef& skill, const PolicyFn& policy,
                          const CardRun& run, const DrivingSkill& parent, const DrivingSkill& up) {
  const robot::CardDef& o = run.card;
  if (!parent.def || !parent.policy || !up.def || !up.policy)
    throw engine::Error("standup card of '" + skill.name + "': needs the models of its parent and of its up skill");
  WorkerPool pool(run.threads);
  std::mt19937_64 seeder(run.seed);
  const int n = o.episodes;
  std::vector<Episode> eps(static_cast<size_t>(n));
  const robot::RandomisationDef& r = skill.randomisation;
  for (Episode& e : eps) e.rng.seed(seeder());
  pool.parallelFor(n, [&](int i) {
    Episode& e = eps[size_t(i)];
    e.model = model;
    const double friction = r.friction.lo + (r.friction.hi - r.friction.lo) * unit(e.rng);
    e.model.articulation.base.mass += r.addedMass.lo + (r.addedMass.hi - r.addedMass.lo) * unit(e.rng);
    e.lieTicks = int(std::lround((o.lieSeconds.lo + (o.lieSeconds.hi - o.lieSeconds.lo) * unit(e.rng)) / engine::kTickSeconds));
    e.world = std::make_unique<engine::PhysicsWorld>();
    e.world->addGround(friction);
    e.robot = std::make_unique<robot::Robot>(e.model, *e.world, 0, 0, M_PI * (2 * unit(e.rng) - 1));
    e.sensors = e.robot->sense(*e.world);
    e.driving = parent.def;
  });
  const int riseTicks = int(std::lround(o.riseSeconds / engine::kTickSeconds));
  const int riseCap = riseTicks + int(std::lround(3.0 / engine::kTickSeconds));  // a late stand is still timed
  const int afterTicks = int(std::lround(o.afterSeconds / engine::kTickSeconds));
  const robot::SkillCommand command;  // none of the three moves on command here
  const DrivingSkill measured{&skill, policy};
  const DrivingSkill* drivers[3] = {&parent, &measured, &up};
  Eigen::MatrixXf obs(robot::kObservationSize, n);
  Eigen::MatrixXf act[3];

  for (;;) {
    bool any[3] = {false, false, false};
    for (int i = 0; i < n; ++i) {
      const Episode& e = eps[size_t(i)];
      if (e.stage == kDone) continue;
      any[e.stage] = true;
      double s, c;
      robot::phaseSignal(e.phase.tp, e.driving->prior.halfPeriodTicks, &s, &c);
      robot::Observation ob;
      robot::buildObservation(e.sensors, model, e.action, command, s, c, &ob);
      for (int k = 0; k < robot::kObservationSize; ++k) obs(k, i) = ob[size_t(k)];
    }
    if (!any[0] && !any[1] && !any[2]) break;
    for (int k = 0; k < 3; ++k)
      if (any[k]) drivers[k]->policy(obs, &act[k]);
    pool.parallelFor(n, [&](int i) {
      Episode& e = eps[size_t(i)];
      if (e.stage == kDone) return;
      robot::filterAction(*e.driving, act[e.stage].col(i).data(), &e.action);
      e.phase.advance(e.driving->prior, command);
      robot::PdCommand pd;
      robot::skillPdCommand(e.model, *e.driving, e.action, e.phase, command, &pd);
      if (e.fadeTicks > 0) {
        e.fadePhase.advance(e.fadingFrom->prior, command);
        robot::fadePrior(e.model, *e.fadingFrom, e.fadePhase, *e.driving, e.phase, command,
                         double(e.fadeTicks) / robot::kSwitchFadeTicks, &pd);
        --e.fadeTicks;
      }
      e.robot->setCommand(pd);
      for (int k = 0; k < game::kSubsteps; ++k) {
        e.robot->applyPd(*e.world);
        e.world->step(game::kSubstepSeconds);
      }
      e.sensors = e.robot->sense(*e.world);
      ++e.stageTick;
      if (e.stage == kRising && e.standTick < 0 && robot::hasStoodUp(e.sensors)) e.standTick = e.stageTick;
      const robot::FallCause cause = robot::fallCause(e.driving->termination, e.sensors);
      if (cause != robot::FallCause::None) {
        e.fellIn = e.stage;
        e.fallCause = cause;
        e.stage = kDone;
        return;
      }
      if (e.stage == kLying && e.stageTick >= e.lieTicks) {
        const double pitch = robot::forwardPitch(e.sensors) * 180.0 / M_PI;
        e.lyingAtSwitch = e.sensors.basePosition.z() < 0.35 && pitch >= 70 && pitch <= 110;
        switchSkill(e, skill);
        e.stage = kRising;
      } else if (e.stage == kRising && robot::postureAllowsSwitch(skill, *up.def, e.sensors)) {  // as the runtime does
        if (e.standTick < 0) e.standTick = e.stageTick;
        e.handOverTick = e.stageTick;
        switchSkill(e, *up.def);
        e.stage = kAfter;
      } else if ((e.stage == kRising && e.stageTick >= riseCap) || (e.stage == kAfter && e.stageTick >= afterTicks)) {
        e.stage = kDone;
      }
    });
  }

  int handedOver = 0;
  double handOverSeconds = 0;
  for (const Episode& e : eps)
    if (e.handOverTick >= 0) ++handedOver, handOverSeconds += e.handOverTick * engine::kTickSeconds;
  int success = 0, stood = 0, lying = 0, fellLying = 0, fellRising = 0, fellAfter = 0, side = 0, back = 0, over = 0;
  double seconds = 0, slowest = 0;
  for (const Episode& e : eps) {
    lying += e.lyingAtSwitch;
    if (e.standTick >= 0) {
      ++stood;
      seconds += e.standTick * engine::kTickSeconds;
      slowest = std::max(slowest, e.standTick * engine::kTickSeconds);
    }
    fellLying += e.fellIn == kLying;
    fellRising += e.fellIn == kRising;
    fellAfter += e.fellIn == kAfter;
    if (e.fellIn == kRising) {
      side += e.fallCause == robot::FallCause::Side;
      back += e.fallCause == robot::FallCause::Back;
      over += e.fallCause == robot::FallCause::OverHead;
    }
    success += e.standTick >= 0 && e.standTick <= riseTicks && e.handOverTick >= 0 && e.fellIn == kDone;
  }
  CardResult res;
  const double pct = 100.0 / std::max(1, n);
  char name[192];
  std::snprintf(name, sizeof name, "episodes standing (pelvis >= %.2f m, tilt < %.0f deg) within %.1f s, then %s %.0f s up",
                robot::kStoodPelvisHeight, robot::kStoodTiltDegrees, o.riseSeconds, up.def->name.c_str(), o.afterSeconds);
  char bar[48];
  std::snprintf(bar, sizeof bar, ">= %g %%", o.successPercent);
  res.figures.push_back({name, pct * success, o.successPercent < 0 ? "(reported)" : bar,
                         o.successPercent < 0 || pct * success >= o.successPercent});
  res.figures.push_back({"mean time to stand [s]", stood ? seconds / stood : 1e9, "(reported)", true});
  res.figures.push_back({"slowest stand [s]", stood ? slowest : 1e9, "(reported)", true});
  std::snprintf(name, sizeof name, "mean time to %s's takeover (standing and settled) [s]", up.def->name.c_str());
  res.figures.push_back({name, handedOver ? handOverSeconds / handedOver : 1e9, "(reported)", true});
  std::snprintf(name, sizeof name, "lying face down when %s began (%s's lead-in) [%%]", skill.name.c_str(), parent.def->name.c_str());
  res.figures.push_back({name, pct * lying, "(reported)", true});
  std::snprintf(name, sizeof name, "  falls: lying down %d; standing up %d (side %d, back %d, over the head %d); under %s %d",
                fellLying, fellRising, side, back, over, up.def->name.c_str(), fellAfter);
  res.figures.push_back({name, double(fellLying + fellRising + fellAfter), "(reported)", true});
  res.pass = true;
  for (const CardFigure& f : res.figures) res.pass = res.pass && f.pass;
  res.score = 2.0 * success / std::max(1, n) + double(stood) / std::max(1, n) -
              (stood ? std::min(1.0, seconds / stood / std::max(0.1, o.riseSeconds)) : 1.0);
  return res;
}

}  // namespace ai
