// ground_card.cpp — measures a ground card: lie down under the parent, then the skill from lying (stand up and
// hand over to the up skill, push-ups, or a crawl through a tunnel).
#include "ai/eval/ground_card.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "ai/env/terrain.h"
#include "ai/eval/card_ranks.h"
#include "engine/core/error.h"
#include "engine/core/worker_pool.h"
#include "engine/loop/clock.h"
#include "robot/skill_runtime.h"

namespace ai {
namespace {

double unit(std::mt19937_64& rng) { return double(rng() >> 11) * (1.0 / 9007199254740992.0); }

enum Stage { kLying = 0, kRising = 1, kAfter = 2, kDone = 3 };  // kRising: the measured skill (stand-up or other)

// push-ups: a rise of the torso counts once it is `rise` above the lowest point since the last one came down by as much
struct RiseCounter {
  double low = 1e9, high = -1e9;
  bool up = false;  // a rise counted, waiting for the torso to come down
  int count = 0;
  double sum = 0;  // trough to crest of each rise that came down again [m]
  int done = 0;
  void add(double z, double rise) {
    if (!up) {
      low = std::min(low, z);
      if (z - low >= rise) up = true, high = z, ++count;
    } else {
      high = std::max(high, z);
      if (high - z >= rise) up = false, sum += high - low, ++done, low = z;
    }
  }
};

struct Episode {
  robot::RobotModel model;
  std::unique_ptr<engine::PhysicsWorld> world;
  std::unique_ptr<robot::Robot> robot;
  std::mt19937_64 rng;
  robot::Sensors sensors;
  robot::SkillState state;  // the runtime: the skill in control (the parent, the measured skill, its up skill)
  const robot::Skill* wanted = nullptr;  // the skill the card asks for (the runtime switches when its rules allow)
  int64_t tick = 0;                      // ticks since the start
  Stage stage = kLying;
  int stageTick = 0;  // ticks in the current stage
  int lieTicks = 0;   // drawn: how long the parent lies down
  bool lyingAtSwitch = false;
  int standTick = -1;           // ticks after the switch to the stand-up when the robot first stood (-1: never) ...
  int handOverTick = -1;        // ... and when it had settled there and the up skill took over
  RiseCounter torso, chest;     // push-ups: the torso link's origin, and the shoulders' midpoint (reported)
  robot::SkillCommand command;  // the measured skill's (a crawl's forward speed); the others run at zero
  // crawls: where the tunnel starts and its direction, the progress along it and how long it went without 0.1 m more
  Eigen::Vector2d start = Eigen::Vector2d::Zero(), along = Eigen::Vector2d::UnitX();
  double best = 0, side = 0;
  double offset = 0,
         headingOff = 0;  // the latest offset across the tunnel [m] and heading from its axis [rad], left > 0
  int reachTick = -1, gainTick = 0, longestStall = 0;
  bool outside = false;
  double friction = 1;
  Stage fellIn = kDone;  // where it fell (kDone: it did not)
  robot::FallCause fallCause = robot::FallCause::None;
};

// what the figures read of an episode: a plain struct, gathered from the ranks that ran the episodes
struct Outcome {
  int standTick, handOverTick, reachTick, longestStall;
  bool lyingAtSwitch, outside;
  Stage fellIn;
  robot::FallCause fallCause;
  RiseCounter torso, chest;
  double best, side, offset, headingOff;
};

Outcome outcomeOf(const Episode& e) {
  return {e.standTick, e.handOverTick, e.reachTick, e.longestStall, e.lyingAtSwitch, e.outside, e.fellIn,
          e.fallCause, e.torso,        e.chest,     e.best,         e.side,          e.offset,  e.headingOff};
}

}  // namespace

namespace {
CardResult pushUpResult(const SkillSpec& skill, const CardDef& o, const DrivingSkill& parent,
                        const std::vector<Outcome>& eps);
CardResult crawlResult(const SkillSpec& skill, const CardDef& o, const DrivingSkill& parent,
                       const std::vector<Outcome>& eps);
}  // namespace

CardResult runGroundCard(const robot::RobotModel& model, const SkillSpec& skill, const PolicyFn& policy,
                         const CardRun& run, const DrivingSkill& parent, const DrivingSkill& up) {
  const CardDef& o = run.card;
  const StandUpCard* standUpCard = o.as<StandUpCard>();
  const PushUpCard* pushUpCard = o.as<PushUpCard>();
  const CrawlCard* crawlCard = o.as<CrawlCard>();
  const bool standUp = standUpCard != nullptr, crawl = crawlCard != nullptr;
  if (!o.lying())
    throw engine::Error("ground card of '" + skill.name + "': the card is not a standup, pushup or crawl card");
  if (!parent.def || !parent.policy || (standUp && (!up.def || !up.policy)))
    throw engine::Error("ground card of '" + skill.name + "': needs the models of its parent" +
                        (standUp ? std::string(" and of its up skill") : std::string()));
  engine::WorkerPool pool(run.threads);
  std::mt19937_64 seeder(run.seed);
  const dist::Comm& comm = dist::orOneProcess(run.comm);
  // every episode's seed as one process draws them; this rank runs its share (all of them on one process)
  std::vector<uint64_t> seeds(size_t(o.episodes));
  for (uint64_t& s : seeds) s = seeder();
  const EpisodeShare share = episodeShare(o.episodes, comm);
  const int n = share.count;
  std::vector<Episode> eps(static_cast<size_t>(n));
  const RandomisationDef& r = skill.randomisation;
  for (int k = 0; k < n; ++k) eps[size_t(k)].rng.seed(seeds[size_t(share.first + k)]);
  pool.parallelFor(n, [&](int i) {
    Episode& e = eps[size_t(i)];
    e.model = model;
    const double friction = e.friction = r.friction.lo + (r.friction.hi - r.friction.lo) * unit(e.rng);
    e.model.articulation.base.mass += r.addedMass.lo + (r.addedMass.hi - r.addedMass.lo) * unit(e.rng);
    e.lieTicks = int(
        std::lround((o.lying()->lieSeconds.lo + (o.lying()->lieSeconds.hi - o.lying()->lieSeconds.lo) * unit(e.rng)) /
                    engine::kTickSeconds));
    e.world = std::make_unique<engine::PhysicsWorld>();
    e.world->addGround(friction);
    e.robot = std::make_unique<robot::Robot>(e.model, *e.world, 0, 0, M_PI * (2 * unit(e.rng) - 1));
    e.sensors = e.robot->sense(*e.world);
    if (crawl) e.command.vx = crawlCard->vx.lo + (crawlCard->vx.hi - crawlCard->vx.lo) * unit(e.rng);
  });
  const int riseTicks = standUp ? int(std::lround(standUpCard->riseSeconds / engine::kTickSeconds)) : 0;
  // a late stand is still timed; other skills run the card's episode_s
  const int riseCap =
      standUp
          ? riseTicks + int(std::lround(3.0 / engine::kTickSeconds))
          : int(std::lround((crawl ? crawlCard->episodeSeconds : pushUpCard->episodeSeconds) / engine::kTickSeconds));
  const int afterTicks = standUp ? int(std::lround(standUpCard->afterSeconds / engine::kTickSeconds)) : 0;
  const robot::SkillCommand still;  // the parent and the up skill run at a zero command
  // the runtime's skills: the parent, the measured skill, its up skill (stand-ups)
  robot::SkillSet set;
  set.skills.push_back({*parent.def, parent.policy});
  set.skills.push_back({skill, policy});
  if (standUp) set.skills.push_back({*up.def, up.policy});
  const robot::Skill& measured = set.skills[1];
  std::vector<PolicyFn> batchPolicy;  // each skill's, run on every rank's episodes at once (card_ranks.h)
  for (const robot::Skill& sk : set.skills) batchPolicy.push_back(policyOverRanks(sk.policy, comm, o.episodes));
  for (Episode& e : eps) robot::enterSkill(&e.state, set.skills[0], e.sensors, 0);
  Eigen::MatrixXf obs(robot::kObservationSize, n);
  Eigen::MatrixXf act[3];
  auto driver = [&](const Episode& e) { return size_t(e.state.active - set.skills.data()); };
  // the longest the switch into the measured skill may wait for the runtime's rules (prone lying still)
  const int maxSwitchWait = int(std::lround(6.0 / engine::kTickSeconds));

  for (;;) {
    bool any[3] = {false, false, false};
    for (int i = 0; i < n; ++i) {
      const Episode& e = eps[size_t(i)];
      if (e.stage == kDone) continue;
      any[driver(e)] = true;
      robot::observe(model, e.state, e.sensors, *e.world, e.stage == kRising ? e.command : still, obs.col(i).data());
    }
    if (comm.size() > 1)  // the batch is every rank's: a skill acts if it drives an episode on any rank
      for (bool& a : any) a = comm.any(a);
    if (!any[0] && !any[1] && !any[2]) break;
    for (size_t k = 0; k < set.skills.size(); ++k)
      if (any[k]) batchPolicy[k](obs, &act[k]);
    pool.parallelFor(n, [&](int i) {
      Episode& e = eps[size_t(i)];
      if (e.stage == kDone) return;
      robot::PdCommand pd;
      robot::act(e.model, &e.state, act[driver(e)].col(i).data(), e.stage == kRising ? e.command : still, false, &pd);
      e.robot->setCommand(pd);
      robot::stepPhysicsTick(*e.robot, *e.world);
      e.sensors = e.robot->sense(*e.world);
      robot::updateDrift(e.sensors, &e.state.drift);
      ++e.stageTick;
      ++e.tick;
      if (e.stage == kRising && e.standTick < 0 && robot::hasStoodUp(e.sensors)) e.standTick = e.stageTick;
      if (e.stage == kRising && crawl) {
        const Eigen::Vector2d d = e.sensors.basePosition.head<2>() - e.start;
        const double progress = d.dot(e.along);
        robot::SkillCommand line;  // the offset across the tunnel's axis and the heading off it
        robot::lineIntoCommand(e.sensors, e.start, e.along, &line);
        e.offset = line.aux1, e.headingOff = line.aux0;
        e.side = std::max(e.side, std::abs(e.offset));
        if (crawlCard->steer > 0) {  // as a player steers: back toward the axis, not at every swing of the rock
          e.command.wz = robot::steerTowardLine(skill.commands, crawlCard->steer, line, &e.state.lineSteerError);
        }
        if (progress >= e.best + 0.1) {
          e.longestStall = std::max(e.longestStall, e.stageTick - e.gainTick);
          e.best = progress, e.gainTick = e.stageTick;
        }
        if (e.reachTick < 0 && progress >= crawlCard->distance) e.reachTick = e.stageTick;
        e.outside = e.outside || e.side > 0.5 * skill.terrain.width;
      } else if (e.stage == kRising && !standUp) {
        const Eigen::Isometry3d torso = e.robot->linkPose(*e.world, model.torso);
        e.torso.add(torso.translation().z(), pushUpCard->rise);
        e.chest.add((torso * robot::kChestInTorso).z(), pushUpCard->rise);
      }
      const robot::FallCause cause = robot::fallCause(e.state.active->def.termination, e.sensors);
      if (cause != robot::FallCause::None) {
        e.fellIn = e.stage;
        e.fallCause = cause;
        e.stage = kDone;
        return;
      }
      // the card's requests, switched by the runtime when its rules allow: the measured skill once the parent has
      // lain lieTicks, and from a stand-up the up skill at once (it takes over once the robot stands settled)
      if (e.stage == kLying && e.stageTick >= e.lieTicks) e.wanted = &measured;
      bool switched = false;
      if (e.wanted && e.wanted != e.state.active) {
        robot::SwitchRequest request;
        request.wanted = e.wanted;
        const robot::RouteResult routed = robot::route(set, &e.state, e.sensors, request, e.tick);
        switched = routed.switchedTo != nullptr;
        if (routed.switchedTo == &measured) {
          e.lyingAtSwitch = robot::isLyingFaceDown(e.sensors);
          e.stage = kRising;
          e.stageTick = 0;
          e.start = e.state.lineStart;  // the line the skill begins on
          e.along = e.state.lineAlong;
          if (standUp) e.wanted = &set.skills[2];
          if (crawl) {  // the tunnel over the robot, along the way it faces, from just behind its feet
            addCeiling(*e.world, skill.terrain, e.start, std::atan2(e.along.y(), e.along.x()), 1.0,
                       crawlCard->distance + 2.5, skill.terrain.width, e.friction);
          }
        } else if (routed.switchedTo) {  // the up skill
          if (e.standTick < 0) e.standTick = e.stageTick;
          e.handOverTick = e.stageTick;
          e.stage = kAfter;
          e.stageTick = 0;
        } else if (e.stage == kLying && e.stageTick - e.lieTicks > maxSwitchWait) {
          e.stage = kDone;  // the measured skill never took over
        }
      }
      if (!switched && ((e.stage == kRising && (e.stageTick >= riseCap || e.reachTick >= 0 || e.outside)) ||
                        (e.stage == kAfter && e.stageTick >= afterTicks))) {
        if (e.stage == kRising && crawl && e.reachTick < 0)
          e.longestStall = std::max(e.longestStall, e.stageTick - e.gainTick);
        e.stage = kDone;
      }
    });
  }

  std::vector<Outcome> mine;
  for (const Episode& e : eps) mine.push_back(outcomeOf(e));
  const std::vector<Outcome> outcomes = gatherOutcomes(mine, comm);
  if (crawl) return crawlResult(skill, o, parent, outcomes);
  if (!standUp) return pushUpResult(skill, o, parent, outcomes);
  const int episodes = int(outcomes.size());  // every rank's
  int handedOver = 0;
  double handOverSeconds = 0;
  for (const Outcome& e : outcomes)
    if (e.handOverTick >= 0) ++handedOver, handOverSeconds += e.handOverTick * engine::kTickSeconds;
  int success = 0, stood = 0, lying = 0, fellLying = 0, fellRising = 0, fellAfter = 0, side = 0, back = 0, over = 0;
  double seconds = 0, slowest = 0;
  for (const Outcome& e : outcomes) {
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
  const double pct = 100.0 / std::max(1, episodes);
  char name[192];
  std::snprintf(name, sizeof name,
                "episodes standing (pelvis >= %.2f m, tilt < %.0f deg) within %.1f s, then %s %.0f s up",
                robot::kStoodPelvisHeight, robot::kStoodTiltDegrees, standUpCard->riseSeconds, up.def->name.c_str(),
                standUpCard->afterSeconds);
  char bar[48];
  std::snprintf(bar, sizeof bar, ">= %g %%", o.successPercent);
  res.figures.push_back({name, pct * success, o.successPercent < 0 ? "(reported)" : bar,
                         o.successPercent < 0 || pct * success >= o.successPercent});
  res.figures.push_back({"mean time to stand [s]", stood ? seconds / stood : 1e9, "(reported)", true});
  res.figures.push_back({"slowest stand [s]", stood ? slowest : 1e9, "(reported)", true});
  std::snprintf(name, sizeof name, "mean time to %s's takeover (standing and settled) [s]", up.def->name.c_str());
  res.figures.push_back({name, handedOver ? handOverSeconds / handedOver : 1e9, "(reported)", true});
  std::snprintf(name, sizeof name, "lying face down when %s began (%s's lead-in) [%%]", skill.name.c_str(),
                parent.def->name.c_str());
  res.figures.push_back({name, pct * lying, "(reported)", true});
  std::snprintf(name, sizeof name,
                "  falls: lying down %d; standing up %d (side %d, back %d, over the head %d); under %s %d", fellLying,
                fellRising, side, back, over, up.def->name.c_str(), fellAfter);
  res.figures.push_back({name, double(fellLying + fellRising + fellAfter), "(reported)", true});
  res.pass = true;
  for (const CardFigure& f : res.figures) res.pass = res.pass && f.pass;
  res.score = 2.0 * success / std::max(1, episodes) + double(stood) / std::max(1, episodes) -
              (stood ? std::min(1.0, seconds / stood / std::max(0.1, standUpCard->riseSeconds)) : 1.0);
  return res;
}

namespace {

CardResult pushUpResult(const SkillSpec& skill, const CardDef& o, const DrivingSkill& parent,
                        const std::vector<Outcome>& eps) {
  const PushUpCard& k = *o.as<PushUpCard>();
  const int n = int(eps.size());
  int success = 0, lying = 0, fellLying = 0, fellSkill = 0, cycles = 0, fewest = 1 << 30, done = 0, chestDone = 0;
  double rise = 0, chestRise = 0;
  for (const Outcome& e : eps) {
    lying += e.lyingAtSwitch;
    fellLying += e.fellIn == kLying;
    fellSkill += e.fellIn == kRising;
    cycles += e.torso.count;
    fewest = std::min(fewest, e.torso.count);
    rise += e.torso.sum, done += e.torso.done;
    chestRise += e.chest.sum, chestDone += e.chest.done;
    success += e.fellIn == kDone && e.torso.count >= k.pushUps;
  }
  CardResult res;
  const double pct = 100.0 / std::max(1, n);
  char name[192], bar[48];
  std::snprintf(name, sizeof name, "episodes with >= %d push-ups (torso rising >= %.2f m) in %.0f s, no fall",
                k.pushUps, k.rise, k.episodeSeconds);
  std::snprintf(bar, sizeof bar, ">= %g %%", o.successPercent);
  res.figures.push_back({name, pct * success, o.successPercent < 0 ? "(reported)" : bar,
                         o.successPercent < 0 || pct * success >= o.successPercent});
  res.figures.push_back({"mean push-ups per episode", double(cycles) / std::max(1, n), "(reported)", true});
  res.figures.push_back({"fewest push-ups in an episode", n ? double(fewest) : 0.0, "(reported)", true});
  res.figures.push_back(
      {"mean torso rise per push-up, trough to crest [m]", done ? rise / done : 0.0, "(reported)", true});
  res.figures.push_back(
      {"mean chest (shoulders) rise per push-up [m]", chestDone ? chestRise / chestDone : 0.0, "(reported)", true});
  std::snprintf(name, sizeof name, "lying face down when %s began (%s's lead-in) [%%]", skill.name.c_str(),
                parent.def->name.c_str());
  res.figures.push_back({name, pct * lying, "(reported)", true});
  std::snprintf(name, sizeof name, "  falls: lying down %d; during %s %d", fellLying, skill.name.c_str(), fellSkill);
  res.figures.push_back({name, double(fellLying + fellSkill), "(reported)", true});
  res.pass = true;
  for (const CardFigure& f : res.figures) res.pass = res.pass && f.pass;
  res.score = 2.0 * success / std::max(1, n) + std::min(1.0, double(cycles) / std::max(1, n * k.pushUps)) -
              double(fellSkill) / std::max(1, n);
  return res;
}

CardResult crawlResult(const SkillSpec& skill, const CardDef& o, const DrivingSkill& parent,
                       const std::vector<Outcome>& eps) {
  const CrawlCard& k = *o.as<CrawlCard>();
  const int n = int(eps.size());
  const double limit = k.distance / k.speed;  // the slowest that passes [s]
  int success = 0, reached = 0, lying = 0, fellLying = 0, fellSkill = 0, outside = 0, outLeft = 0, crawled = 0;
  double seconds = 0, slowest = 0, stall = 0, progress = 0, side = 0, heading = 0, headingAbs = 0;
  for (const Outcome& e : eps) {
    lying += e.lyingAtSwitch;
    outLeft += e.outside && e.offset > 0;
    if (e.fellIn != kLying) ++crawled, heading += e.headingOff, headingAbs += std::abs(e.headingOff);
    fellLying += e.fellIn == kLying;
    fellSkill += e.fellIn == kRising;
    outside += e.outside;
    progress += std::min(e.best, k.distance);
    side = std::max(side, e.side);
    stall = std::max(stall, e.longestStall * engine::kTickSeconds);
    if (e.reachTick >= 0) {
      ++reached;
      seconds += e.reachTick * engine::kTickSeconds;
      slowest = std::max(slowest, e.reachTick * engine::kTickSeconds);
    }
    success += e.reachTick >= 0 && e.reachTick * engine::kTickSeconds <= limit && e.fellIn == kDone && !e.outside;
  }
  CardResult res;
  const double pct = 100.0 / std::max(1, n);
  char name[192], bar[48];
  std::snprintf(name, sizeof name, "episodes crawling %.1f m under a %.2f m ceiling at >= %.2f m/s, no fall",
                k.distance, skill.terrain.ceilingHeight, k.speed);
  std::snprintf(bar, sizeof bar, ">= %g %%", o.successPercent);
  res.figures.push_back({name, pct * success, o.successPercent < 0 ? "(reported)" : bar,
                         o.successPercent < 0 || pct * success >= o.successPercent});
  std::snprintf(name, sizeof name, "mean speed over the %.1f m (episodes that got there) [m/s]", k.distance);
  res.figures.push_back({name, reached ? k.distance * reached / seconds : 0.0, "(reported)", true});
  std::snprintf(name, sizeof name, "slowest to %.1f m [s]", k.distance);
  res.figures.push_back({name, reached ? slowest : 1e9, "(reported)", true});
  res.figures.push_back({"mean progress along the tunnel [m]", progress / std::max(1, n), "(reported)", true});
  res.figures.push_back({"longest stall (no 0.1 m of progress) [s]", stall, "(reported)", true});
  res.figures.push_back({"largest drift across the tunnel (pelvis) [m]", side, "(reported)", true});
  const double deg = 180.0 / M_PI / std::max(1, crawled);
  res.figures.push_back(
      {"heading off the tunnel's axis at the end, mean (left > 0) [deg]", heading * deg, "(reported)", true});
  res.figures.push_back(
      {"heading off the tunnel's axis at the end, mean of |.| [deg]", headingAbs * deg, "(reported)", true});
  std::snprintf(name, sizeof name, "lying face down when %s began (%s's lead-in) [%%]", skill.name.c_str(),
                parent.def->name.c_str());
  res.figures.push_back({name, pct * lying, "(reported)", true});
  std::snprintf(name, sizeof name,
                "  falls: lying down %d; during %s %d; out of the tunnel's side %d (left %d, right %d)", fellLying,
                skill.name.c_str(), fellSkill, outside, outLeft, outside - outLeft);
  res.figures.push_back({name, double(fellLying + fellSkill), "(reported)", true});
  res.pass = true;
  for (const CardFigure& f : res.figures) res.pass = res.pass && f.pass;
  res.score =
      2.0 * success / std::max(1, n) + progress / std::max(1, n) / k.distance - double(fellSkill) / std::max(1, n);
  return res;
}

}  // namespace
}  // namespace ai
